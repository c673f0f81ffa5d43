//! Knoll et al.'s modalities change the picture as expected: shadows darken,
//! layers show hidden surfaces, isovalues are identified, reflections see
//! the environment, colour modes recolour, and each composes with the others.

use super::common;

use common::*;
use crate::ir::Domain;
use crate::gpu::Renderer;
use crate::render::{BisectOptions, Modalities, Traversal};
use crate::render::{Frame, Status};

fn render_with(src: &str, s: &crate::render::Settings, m: Modalities) -> Frame {
    let f = crate::Formula::compile("<test>", src).unwrap();
    let frame = Renderer::new(gpu(), &f.ir, Traversal::Bisect(BisectOptions { modalities: m, ..BisectOptions::new(Domain::Affine) })).unwrap().render(s).unwrap();
    if let Ok(dir) = std::env::var("ISOTRACE_TEST_IMAGES") {
        let name = format!("{dir}/{}.png", src.len() ^ s.width as usize ^ frame.stats.hits as usize);
        crate::output::write_frame(std::path::Path::new(&name), &frame).unwrap();
    }
    frame
}

fn luma(p: &crate::render::PixelOut) -> f32 {
    0.3 * p.color[0] + 0.6 * p.color[1] + 0.1 * p.color[2]
}

/// A ball floating above a floor slab: the ball's shadow falls on the floor.
const BALL_AND_FLOOR: &str = "min(x^2 + y^2 + (z - 0.3)^2 - 0.25, z + 0.6)";

#[test]
fn shadows_darken_the_floor_under_the_ball() {
    let mut s = settings([-1.5, 1.5, -1.5, 1.5, -1.0, 1.0], 48, 48);
    s.camera.eye = glam::DVec3::new(0.0, -4.0, 3.0);
    s.camera.target = glam::DVec3::new(0.0, 0.0, -0.3);
    let light = Some(glam::DVec3::new(0.0, 0.0, 3.0));
    let plain = render_with(BALL_AND_FLOOR, &s, Modalities { light, ..Default::default() });
    let shadowed = render_with(BALL_AND_FLOOR, &s, Modalities { light, shadows: true, ..Default::default() });
    // Pixels on the floor (depth well beyond the ball) under the ball get darker, others do not change.
    let (mut darker, mut same) = (0, 0);
    for (a, b) in plain.pixels.iter().zip(&shadowed.pixels) {
        assert_eq!(a.status, b.status);
        if a.status == Status::Hit {
            if luma(b) < 0.7 * luma(a) { darker += 1 } else if (luma(a) - luma(b)).abs() < 1e-3 { same += 1 }
        }
    }
    assert!(darker > 20, "{darker} shadowed pixels");
    assert!(same > darker, "{same} unchanged pixels");
}

#[test]
fn four_layers_show_the_inner_sphere() {
    // Two concentric spheres: opaque, only the outer one is seen.
    let src = "(x^2 + y^2 + z^2 - 1)*(x^2 + y^2 + z^2 - 0.25)";
    let s = settings(cube(1.5), 32, 32);
    let opaque = render_with(src, &s, Modalities::default());
    let layered = render_with(src, &s, Modalities { layers: 4, opacity: 0.5, ..Default::default() });
    let centre = (16 * 32 + 16) as usize;
    assert_eq!(opaque.pixels[centre].status, Status::Hit);
    // Through the centre the ray crosses 4 surfaces: the blend differs from
    // the opaque colour, and the first-hit depth is unchanged.
    assert_eq!(opaque.pixels[centre].depth, layered.pixels[centre].depth);
    let d: f32 = (0..3).map(|c| (opaque.pixels[centre].color[c] - layered.pixels[centre].color[c]).abs()).sum();
    assert!(d > 0.05, "layers do not change the centre colour ({d})");
    // The inner sphere's back side is blue (inside of the outer sphere seen
    // from within): more blue in the centre than with one layer.
    assert!(layered.pixels[centre].color[2] > opaque.pixels[centre].color[2]);
}

#[test]
fn isovalues_are_identified() {
    // Nested spheres x²+y²+z² = 0.25, 1, 2.25 through one traversal.
    // The box cuts the outer sphere away near its face centres, so the
    // middle sphere shows there.
    let s = settings(cube(1.2), 40, 40);
    let m = Modalities { isovalues: vec![0.25, 1.0, 2.25], ..Default::default() };
    let frame = render_with("x^2 + y^2 + z^2", &s, m);
    // Which isovalue each hit is, as the EXR `iso` channel tells it.
    let iso_channel = exr_channel(&frame, "iso");
    let cf = s.camera.frame().unwrap();
    let mut seen = [0; 3];
    for (k, p) in frame.pixels.iter().enumerate() {
        if p.status != Status::Hit {
            assert_eq!(iso_channel[k], -1.0);
            continue;
        }
        let iso = iso_channel[k] as usize;
        seen[iso] += 1;
        // The hit point lies on the sphere of that isovalue.
        let d = crate::render::Camera::ray(&cf, k as u32 % 40, k as u32 / 40, 40, 40);
        let q = s.camera.eye + d * p.depth as f64;
        let r2 = q.length_squared();
        assert!((r2 - [0.25, 1.0, 2.25][iso]).abs() < 0.05, "pixel {k}: iso {iso} at r² = {r2}");
    }
    assert!(seen[2] > 0 && seen[1] > 0, "{seen:?}");
}

#[test]
fn level_set_conditions_cut_and_colour_surfaces() {
    // A dome (sphere where z > 0) closed by a disc (z = 0 inside the sphere),
    // seen from below: the centre shows the disc (surface 1) at the plane's depth.
    let src = "x^2 + y^2 + z^2 - 1 where z > 0; z where x^2 + y^2 + z^2 - 1 < 0";
    let mut s = settings(cube(1.5), 32, 32);
    s.camera.eye = glam::DVec3::new(0.5, 0.3, -4.0);
    s.camera.target = glam::DVec3::ZERO;
    let frame = render_with(src, &s, Modalities::default());
    let cf = s.camera.frame().unwrap();
    let centre = (16 * 32 + 16) as usize;
    let p = frame.pixels[centre];
    assert_eq!((p.status, p.iso), (Status::Hit, 1));
    let d = crate::render::Camera::ray(&cf, 16, 16, 32, 32);
    let t = -s.camera.eye.z / d.z;
    assert!((p.depth as f64 - t).abs() <= s.eps, "disc depth {} vs {t}", p.depth);
    // Every hit lies on one of the two pieces, inside its condition (to eps).
    for (k, px) in frame.pixels.iter().enumerate().filter(|(_, p)| p.status == Status::Hit) {
        let d = crate::render::Camera::ray(&cf, k as u32 % 32, k as u32 / 32, 32, 32);
        let q = s.camera.eye + d * px.depth as f64;
        match px.iso {
            0 => assert!(q.z > -2.0 * s.eps && (q.length() - 1.0).abs() < 0.02, "dome pixel {k} at {q}"),
            1 => assert!(q.z.abs() < 0.02 && q.length() < 1.0 + 2.0 * s.eps, "disc pixel {k} at {q}"),
            other => panic!("surface {other}"),
        }
    }
    // From above only the dome is seen.
    s.camera.eye = glam::DVec3::new(0.5, 0.3, 4.0);
    let top = render_with(src, &s, Modalities::default());
    assert!(top.pixels.iter().all(|p| p.status != Status::Hit || p.iso == 0));
}

#[test]
fn a_condition_removes_part_of_a_surface() {
    let s = settings(cube(1.5), 32, 32);
    let whole = render_with("x^2 + y^2 + z^2 - 1", &s, Modalities::default());
    let cut = render_with("x^2 + y^2 + z^2 - 1 where x > 0.3", &s, Modalities::default());
    let count = |f: &Frame| f.pixels.iter().filter(|p| p.status == Status::Hit).count();
    assert!(count(&cut) < count(&whole) && count(&cut) > 0);
    let cf = s.camera.frame().unwrap();
    for (k, px) in cut.pixels.iter().enumerate().filter(|(_, p)| p.status == Status::Hit) {
        let d = crate::render::Camera::ray(&cf, k as u32 % 32, k as u32 / 32, 32, 32);
        let q = s.camera.eye + d * px.depth as f64;
        assert!(q.x > 0.3 - 2.0 * s.eps, "pixel {k} at {q} violates x > 0.3");
    }
}

