//! The scene field source on the device: a blobtree in buffers, run by the
//! fixed interpreter, traced by the same sphere tracing traversal as a
//! compiled formula and agreeing with it; edits change buffers only.

mod common;

use common::gpu;
use isotrace::codegen::{FieldSource, SceneData};
use isotrace::gpu::Renderer;
use isotrace::render::{SphereOptions, Status, Traversal};
use isotrace::Formula;
use std::sync::atomic::Ordering;

const LEAF: u32 = 1 << 31;
const LEFT: u32 = 1 << 30;

/// union(sphere(1), translate(dx, 0, 0, box(0.5, 0.5, 0.5))) as buffers.
fn sphere_and_box(dx: f32) -> SceneData {
    let id = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]];
    let mut params: Vec<[f32; 4]> = id.to_vec();
    params.push([1.0, 1.0, 0.0, 0.0]);
    params.extend([[1.0, 0.0, 0.0, -dx], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [1.0, 0.5, 0.5, 0.5]]);
    params.push([0.0; 4]);
    let nodes = vec![[LEAF | LEFT | (1 << 22) | 2, 0, 2, 0], [LEAF | (2 << 22) | 2, 4, 2, 0], [(32 << 22) | 3, 8, 3, 0]];
    let balls = vec![[0.0, 0.0, 0.0, 1.0], [dx, 0.0, 0.0, 0.75f32.sqrt()]];
    SceneData { nodes, params, prims: vec![0, 1], balls }
}

#[test]
fn scene_interpreter_agrees_with_the_compiled_formula() {
    let s = common::settings(common::cube(2.5), 64, 48);
    let data = sphere_and_box(1.5);
    let scene = Renderer::new(gpu(), FieldSource::Scene(&data), Traversal::Sphere(SphereOptions::default())).unwrap().render(&s).unwrap();
    let f = Formula::compile("<t>", "union(sphere(1), translate(1.5, 0, 0, box(0.5, 0.5, 0.5)))").unwrap();
    let compiled = Renderer::sphere(gpu(), &f.ir, SphereOptions::default()).unwrap().render(&s).unwrap();
    let mut hits = 0;
    for (a, b) in scene.pixels.iter().zip(&compiled.pixels) {
        assert_eq!(a.status, b.status);
        if a.status == Status::Hit {
            hits += 1;
            assert!((a.depth - b.depth).abs() < 1e-3, "{} vs {}", a.depth, b.depth);
        }
    }
    assert!(hits > 100, "{hits}");
    assert_eq!(scene.stats.unresolved, 0);
}

#[test]
fn scene_edits_change_buffers_not_pipelines() {
    let s = common::settings(common::cube(2.5), 32, 32);
    let data = sphere_and_box(1.5);
    // A device of its own: the other tests create pipelines concurrently.
    let own = isotrace::gpu::Gpu::new().unwrap();
    let mut r = Renderer::new(&own, FieldSource::Scene(&data), Traversal::Sphere(SphereOptions::default())).unwrap();
    let before = r.render(&s).unwrap();
    let created = own.pipelines_created.load(Ordering::Relaxed);
    r.set_field(FieldSource::Scene(&sphere_and_box(-1.5))).unwrap();
    let moved = r.render(&s).unwrap();
    assert_eq!(own.pipelines_created.load(Ordering::Relaxed), created);
    let changed = before.pixels.iter().zip(&moved.pixels).filter(|(a, b)| a.status != b.status).count();
    assert!(changed > 20, "{changed}");
    // A scene is sphere traced: asking to bisect it is a typed error.
    let err = Renderer::new(gpu(), FieldSource::Scene(&data), Traversal::Bisect(isotrace::render::BisectOptions::new(isotrace::codegen::Domain::Interval)));
    assert!(err.is_err());
}
