//! The scene interpreters' value stack keeps its upper values in registers
//! and the rest in an array: scenes whose evaluation needs a deeper stack
//! than the registers hold agree with the f64 reference on the device, as
//! points (the scalar interpreter) and as enclosures over boxes (the
//! interval one).

use super::common::gpu;
use super::scene_common::{random_primitive, random_tree, TreeShape};
use super::scene_enclosures::{random_box, sampled_range};
use crate::gpu::eval::{eval_boxes_scene, eval_points_scene, Box8};
use crate::scene::generate::Rng;
use crate::scene::linear::Linear;
use crate::scene::{Blend, Builder, OpKind, Operator, Scene};

/// Values the registers hold below the top (scene.wgsl, `g_scene_near`).
const IN_REGISTERS: u32 = 4;

/// A chain of differences nested in their right operands, p0 − (p1 − (p2 −
/// …)), smooth every other level: each level holds one more value on the
/// stack, which no reordering removes.
fn right_nested(rng: &mut Rng, n: usize) -> Scene {
    let mut b = Builder::default();
    let prims: Vec<_> = (0..n)
        .map(|k| {
            let centre = [0.3 * k as f64 - 1.5, rng.range(-0.3, 0.3), 0.0];
            b.primitive(random_primitive(rng, centre, 0.8, false))
        })
        .collect();
    let mut top = prims[n - 1];
    for (k, p) in prims.iter().enumerate().rev().skip(1) {
        let op = if k % 2 == 0 { Operator::DIFFERENCE } else { Operator::smooth(OpKind::Difference, Blend { beta: 0.2, range: 0.5 }) };
        top = b.operator(op, *p, top);
    }
    b.finish(top).unwrap()
}

/// Scenes whose evaluation needs more values than the registers hold, laid
/// out.
fn deep_scenes(rng: &mut Rng) -> Vec<(Scene, Linear)> {
    let scenes = [right_nested(rng, 12), random_tree(rng, 64, TreeShape::Balanced, 0.5, false), random_tree(rng, 128, TreeShape::Balanced, 1.0, true)];
    scenes
        .into_iter()
        .enumerate()
        .map(|(k, scene)| {
            let lin = Linear::new(&scene).unwrap();
            assert!(lin.stack_depth > IN_REGISTERS + 1, "scene {k}: a stack of {} stays in the registers", lin.stack_depth);
            (scene, lin)
        })
        .collect()
}

#[test]
fn deep_stacks_evaluate_as_the_reference_on_the_device() {
    let gpu = gpu();
    let mut rng = Rng::new(0xdee9_57ac);
    for (k, (scene, lin)) in deep_scenes(&mut rng).into_iter().enumerate() {
        let bb = lin.bounds;
        let points: Vec<[f32; 3]> = (0..4000).map(|_| [0, 1, 2].map(|a| rng.range(bb.min[a] - 0.3, bb.max[a] + 0.3) as f32)).collect();
        let got = eval_points_scene(gpu, &lin.field_data(), &points).unwrap();
        let worst = points.iter().zip(&got).map(|(p, g)| (f64::from(*g) - scene.eval(p.map(f64::from))).abs()).fold(0.0, f64::max);
        assert!(worst < 2e-4, "scene {k} (stack {}): worst difference {worst}", lin.stack_depth);
    }
}

#[test]
fn deep_stacks_enclose_the_references_values_on_the_device() {
    let gpu = gpu();
    let mut rng = Rng::new(0x57ac_b0c5);
    for (k, (scene, lin)) in deep_scenes(&mut rng).into_iter().enumerate() {
        let bbox = lin.bounds.padded().unwrap();
        let boxes: Vec<Box8> = (0..8000)
            .map(|_| {
                let b = random_box(&mut rng, &bbox);
                [b[0] as f32, b[1] as f32, b[2] as f32, b[3] as f32, b[4] as f32, b[5] as f32, 0.0, 0.0]
            })
            .collect();
        let got = eval_boxes_scene(gpu, &lin.field_data(), &boxes).unwrap();
        let mut escapes = 0;
        let mut decided = 0;
        for (b, e) in boxes.iter().zip(&got) {
            let f = b.map(f64::from);
            let (lo, hi) = sampled_range(&scene, &mut rng, &[f[0], f[1], f[2], f[3], f[4], f[5]], 16);
            let slack = 1e-5 * (1.0 + lo.abs().max(hi.abs()));
            escapes += usize::from(!(f64::from(e[0]) <= lo + slack && f64::from(e[1]) >= hi - slack));
            decided += usize::from(e[0] > 0.0 || e[1] < 0.0);
        }
        assert_eq!(escapes, 0, "scene {k} (stack {}): enclosures miss sampled values", lin.stack_depth);
        // Not the whole line everywhere: most boxes are decided.
        assert!(decided * 2 > boxes.len(), "scene {k}: only {decided} of {} boxes decided", boxes.len());
    }
}
