//! The one render pipeline: both traversals through the same `Renderer`,
//! the same pixel record and decoder, packed frames for either, options
//! that are uniforms changing without recompiling, and the module
//! boundaries the architecture promises (docs/architecture.md).

use super::common;

use common::gpu;
use crate::ir::Domain;
use crate::gpu::Renderer;
use crate::render::record::PackedFrame;
use crate::render::{Method, SettingsField, SphereOptions, Status, Traversal};
use crate::Formula;

/// Packed frames decode to exactly the frame `render` returns, with the
/// same statistics, for both traversals.
#[test]
fn packed_frames_equal_decoded_frames_for_both_traversals() {
    let f = Formula::compile("<t>", "sphere(1)").unwrap();
    let s = common::settings(common::cube(1.5), 40, 30);
    let sphere = Renderer::sphere(gpu(), &f.ir, SphereOptions::default()).unwrap();
    let bisect = Renderer::bisect(gpu(), &f.ir, Domain::Interval).unwrap();
    for (r, method) in [(&sphere, Method::Sphere), (&bisect, Method::Bisect)] {
        let frame = r.render(&s).unwrap();
        let mut packed = PackedFrame::default();
        r.render_packed(&s, &mut packed).unwrap();
        let decoded = packed.decode();
        let differ: Vec<_> = frame.pixels.iter().zip(&decoded.pixels).enumerate().filter(|(_, (a, b))| a != b).take(3).collect();
        assert!(differ.is_empty(), "{method:?}: {differ:?}");
        assert_eq!(frame.stats.method, method);
        assert_eq!((frame.stats.hits, frame.stats.evals_mean), (decoded.stats.hits, decoded.stats.evals_mean));
        assert!(frame.stats.hits > 50, "{method:?}: {:?}", frame.stats);
    }
}

/// A packed frame rendered again reuses its memory (on lavapipe the
/// kernel's output buffer, left mapped), and a frame still held keeps its
/// records while the renderer draws other frames: into another packed
/// frame, into a decoded frame, at another size, and split into dispatches.
#[test]
fn packed_frames_keep_their_records_across_renders() {
    let f = Formula::compile("<t>", "sphere(1)").unwrap();
    let r = Renderer::bisect(gpu(), &f.ir, Domain::Interval).unwrap();
    let s = common::settings(common::cube(1.5), 40, 30);
    let mut far = s.clone();
    far.camera.eye *= 1.5;
    let mut held = PackedFrame::default();
    r.render_packed(&s, &mut held).unwrap();
    let first = held.decode();
    assert!(first.stats.hits > 50, "{:?}", first.stats);
    let kept = if gpu().map_in_place { "records: \"mapped\"" } else { "records: \"copied\"" };
    assert!(format!("{held:?}").contains(kept), "{held:?}");
    let mut other = PackedFrame::default();
    for (i, t) in [&far, &s, &far].into_iter().enumerate() {
        r.render_packed(t, &mut other).unwrap();
        let decoded = other.decode();
        assert_eq!(decoded.pixels, r.render(t).unwrap().pixels, "render {i} into the second frame");
        // Misses write no normal and depth (the records' tail plane): the
        // hits of the frame before, where this one misses, must not show.
        let stale = decoded.pixels.iter().filter(|p| p.status == Status::Miss && (p.depth != f32::INFINITY || p.normal != [0.0; 3])).count();
        assert_eq!(stale, 0, "render {i}: misses with a depth or a normal");
    }
    let mut small = common::settings(common::cube(1.5), 16, 8);
    r.render_packed(&small, &mut other).unwrap();
    assert_eq!((other.width, other.height, other.len()), (16, 8, 128));
    small.tile = 8;
    r.render_packed(&small, &mut other).unwrap();
    assert_eq!(other.stats.dispatches, 2);
    assert_eq!(other.decode().pixels, r.render(&small).unwrap().pixels);
    assert_eq!(held.decode().pixels, first.pixels, "the held frame changed");
    let copy = held.clone();
    r.render_packed(&far, &mut held).unwrap();
    assert_eq!(copy.decode().pixels, first.pixels, "a clone keeps the records it copied");
    assert_ne!(held.decode().pixels, first.pixels, "the frame rendered again holds the new view");
}

/// The two traversals agree on a sphere's depth through the shared record
/// (depth in f32, normals octahedral): the same pixels hit away from the
/// silhouette (sphere tracing's screen-space criterion also accepts rays
/// that pass within half a pixel).
#[test]
fn traversals_share_the_record() {
    let f = Formula::compile("<t>", "sphere(1)").unwrap();
    let s = common::settings(common::cube(1.5), 32, 32);
    // An absolute threshold (technique 2 off): depth within eps / cos θ.
    let o = SphereOptions { screen_space: false, ..Default::default() };
    let a = Renderer::sphere(gpu(), &f.ir, o).unwrap().render(&s).unwrap();
    let b = Renderer::bisect(gpu(), &f.ir, Domain::Interval).unwrap().render(&s).unwrap();
    let mut compared = 0;
    let w = s.width as usize;
    let interior = |i: usize| [i.wrapping_sub(1), i + 1, i.wrapping_sub(w), i + w].iter().all(|&k| b.pixels.get(k).is_some_and(|n| n.status == b.pixels[i].status));
    for (i, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate().filter(|(i, _)| interior(*i)) {
        assert_eq!(p.status, q.status, "pixel {i}");
        if p.status == crate::render::Status::Hit {
            compared += 1;
            assert!((p.depth - q.depth).abs() < 2e-2, "{} vs {}", p.depth, q.depth);
            let dot: f32 = (0..3).map(|k| p.normal[k] * q.normal[k]).sum();
            assert!(dot > 0.999, "normals {:?} {:?}", p.normal, q.normal);
        }
    }
    assert!(compared > 50, "{compared}");
}

/// Sphere tracing's options are uniforms: changing them keeps the shader;
/// asking for secondary rays the kernel lacks is a typed error.
#[test]
fn sphere_options_change_without_recompiling() {
    let f = Formula::compile("<t>", "sphere(1)").unwrap();
    let s = common::settings(common::cube(1.5), 24, 24);
    let mut r = Renderer::sphere(gpu(), &f.ir, SphereOptions::default()).unwrap();
    let wgsl = r.wgsl().to_string();
    let before = r.render(&s).unwrap();
    r.set_sphere_options(SphereOptions { omega: 1.0, ..Default::default() }).unwrap();
    let after = r.render(&s).unwrap();
    assert_eq!(r.wgsl(), wgsl);
    assert_eq!(before.stats.hits, after.stats.hits);
    assert_eq!(after.stats.sphere.sor_fallbacks, 0);
    assert!(matches!(r.traversal(), Traversal::Sphere(o) if o.omega == 1.0));
    let err = r.set_sphere_options(SphereOptions { glass: true, ..Default::default() }).unwrap_err();
    assert!(matches!(err, crate::gpu::RenderError::Settings(ref e) if e.field == SettingsField::Features), "{err}");
    let mut b = Renderer::bisect(gpu(), &f.ir, Domain::Interval).unwrap();
    assert!(b.set_sphere_options(SphereOptions::default()).is_err());
    assert!(b.optimizations_mut().is_some() && r.optimizations_mut().is_none());
}

/// gpu code runs shaders, it does not build them: no template, splice or
/// emitter is used under src/gpu (codegen assembles every kernel).
#[test]
fn gpu_modules_do_not_assemble_shaders() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/gpu");
    for e in std::fs::read_dir(&dir).unwrap() {
        let p = e.unwrap().path();
        let text = std::fs::read_to_string(&p).unwrap();
        for banned in ["template::", "splice(", "emit_evaluator", "include_str!(\"../../templates"] {
            assert!(!text.contains(banned), "{} uses {banned}", p.display());
        }
    }
}

/// A new renderer sends its small passes (the tile pass, a field's
/// pre-passes) to the device in a dispatch of no workgroups while its
/// per-pixel pass is being created, so that lavapipe compiles them then
/// (`gpu::binding`): every kind of kernel binds that dispatch without an
/// error, and a kernel without small passes sends none.
#[test]
fn new_renderers_warm_their_small_passes_up() {
    use crate::field::FieldSource;
    use crate::render::BisectOptions;
    use std::sync::atomic::Ordering::Relaxed;
    let own = crate::gpu::Gpu::new().unwrap();
    let f = Formula::compile("<t>", "sphere(1)").unwrap();
    let tape = crate::field::TapeData::new(&f.ir).unwrap();
    let scene = crate::scene::format::load(std::path::Path::new("examples/blobs.scene.json")).unwrap();
    let data = crate::scene::linear::Linear::new(&scene).unwrap().field_data();
    let bisect = || Traversal::Bisect(BisectOptions::new(Domain::Affine));
    let sphere = || Traversal::Sphere(SphereOptions::default());
    let s = common::settings(common::cube(1.5), 40, 30);
    let kernels: [(&str, &dyn FieldSource, Traversal, u64); 4] = [
        ("compiled, bisected", &f.ir, bisect(), 1),
        ("compiled, sphere traced", &f.ir, sphere(), 0),
        ("tape, bisected", &tape, bisect(), 1),
        ("scene, sphere traced", &data, sphere(), 1),
    ];
    for (name, field, traversal, sent) in kernels {
        let before = own.warm_ups[0].load(Relaxed);
        let r = Renderer::new(&own, field, traversal).unwrap();
        assert_eq!(own.warm_ups[1].load(Relaxed), 0, "{name}: a warm-up failed");
        assert_eq!(own.warm_ups[0].load(Relaxed) - before, sent, "{name}");
        // The frame after it draws as ever.
        assert!(r.render(&s).unwrap().stats.hits > 50, "{name}");
    }
}
