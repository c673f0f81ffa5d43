//! The scene field source on the device: a blobtree in buffers, run by the
//! fixed interpreter, traced by the same sphere tracing traversal as a
//! compiled formula and agreeing with it; edits change buffers only.

use super::common;
use super::scene_common;
use super::scene_pictures;

use common::gpu;
use scene_pictures::{check_against_spheres, ray_ball, same_picture, sphere_grid, sphere_grid_cut, sphere_grid_tree};
use crate::field::SceneData;
use crate::gpu::Renderer;
use crate::render::{SphereOptions, Traversal};
use crate::Formula;
use std::sync::atomic::Ordering;

const LEAF: u32 = 1 << 31;
const LEFT: u32 = 1 << 30;

/// union(sphere(1), translate(dx, 0, 0, box(0.5, 0.5, 0.5))) as buffers,
/// written out in the documented layout (src/scene/linear.rs): a sphere is
/// the rounded-box form with no extent and rounding 1. Each primitive has
/// the identity quaternion, its centre and form, then (extents, rounding).
fn sphere_and_box(dx: f32) -> SceneData {
    let id = [0.0, 0.0, 0.0, 1.0];
    let params = vec![id, [0.0; 4], [0.0, 0.0, 0.0, 1.0], id, [dx, 0.0, 0.0, 0.0], [0.5, 0.5, 0.5, 0.0], [0.0; 4]];
    let nodes = vec![[LEAF | LEFT | (1 << 22) | 2, 0, 2, 0], [LEAF | (2 << 22) | 2, 3, 2, 1], [(32 << 22) | 3, 6, 3, 0]];
    // Each primitive's ball, then its limit (none: a union).
    let none = [0.0, 0.0, 0.0, f32::INFINITY];
    let balls = vec![[0.0, 0.0, 0.0, 1.0], none, [dx, 0.0, 0.0, 0.75f32.sqrt()], none];
    SceneData { nodes, params, prims: vec![0, 1], balls, features: crate::scene::linear::FEATURE_SHAPES, leaves: Vec::new() }
}

#[test]
fn scene_interpreter_agrees_with_the_compiled_formula() {
    let s = common::settings(common::cube(2.5), 64, 48);
    let data = sphere_and_box(1.5);
    let scene = Renderer::new(gpu(), &data, Traversal::Sphere(SphereOptions::default())).unwrap().render(&s).unwrap();
    let f = Formula::compile("<t>", "union(sphere(1), translate(1.5, 0, 0, box(0.5, 0.5, 0.5)))").unwrap();
    let compiled = Renderer::sphere(gpu(), &f.ir, SphereOptions::default()).unwrap().render(&s).unwrap();
    // Both stop within the screen-space criterion, and the fixed-point
    // iterations then take both to the same level set, to within a few
    // per cent of a pixel's footprint; in the crease where the sphere meets
    // the box, where f stays near that level over a stretch of the ray, at
    // depths up to 0.65 footprints apart (measured), both at f within 0.02
    // of the level.
    let (hits, _) = same_picture(&scene, &compiled, 64, 48, 1.0);
    assert!(hits > 100, "{hits}");
    assert_eq!(scene.stats.unresolved, 0);
}

#[test]
fn scene_edits_change_buffers_not_pipelines() {
    let s = common::settings(common::cube(2.5), 32, 32);
    let data = sphere_and_box(1.5);
    // A device of its own: the other tests create pipelines concurrently.
    let own = crate::gpu::Gpu::new().unwrap();
    let mut r = Renderer::new(&own, &data, Traversal::Sphere(SphereOptions::default())).unwrap();
    let before = r.render(&s).unwrap();
    let created = own.pipelines_created.load(Ordering::Relaxed);
    r.set_field(&sphere_and_box(-1.5)).unwrap();
    let moved = r.render(&s).unwrap();
    assert_eq!(own.pipelines_created.load(Ordering::Relaxed), created);
    let changed = before.pixels.iter().zip(&moved.pixels).filter(|(a, b)| a.status != b.status).count();
    assert!(changed > 20, "{changed}");
    // Bisected, an edit is a buffer update too, and draws what a new
    // renderer of the edited scene draws.
    let bisect = || Traversal::Bisect(crate::render::BisectOptions::new(crate::ir::Domain::Interval));
    let mut b = Renderer::new(&own, &data, bisect()).unwrap();
    b.render(&s).unwrap();
    let created = own.pipelines_created.load(Ordering::Relaxed);
    b.set_field(&sphere_and_box(-1.5)).unwrap();
    let edited = b.render(&s).unwrap();
    assert_eq!(own.pipelines_created.load(Ordering::Relaxed), created);
    let fresh = Renderer::new(gpu(), &sphere_and_box(-1.5), bisect()).unwrap().render(&s).unwrap();
    assert!(edited.pixels.iter().zip(&fresh.pixels).all(|(a, b)| a.status == b.status && a.depth == b.depth));
    assert!(edited.pixels.iter().zip(&before.pixels).filter(|(a, b)| a.status != b.status).count() > 20);
}

/// The scene with primitive `j` (in post-order primitive order) replaced.
fn with_primitive(scene: &crate::scene::Scene, lin: &crate::scene::linear::Linear, j: usize, p: crate::scene::Primitive) -> crate::scene::Scene {
    let id = lin.order[lin.primitives[j] as usize];
    let mut nodes = scene.nodes().to_vec();
    nodes[id] = crate::scene::Node::Primitive(p);
    crate::scene::Scene::new(nodes, scene.root()).unwrap()
}

#[test]
fn an_edit_in_place_uploads_what_a_rebuild_would_and_draws_the_same_frame() {
    use crate::scene::generate::{generate, Blending, Kind};
    use crate::scene::linear::Linear;
    use crate::scene::{Node, Primitive};
    let scene = generate(Kind::Aggregate, 1, Blending::Smooth, 7).unwrap();
    let mut lin = Linear::new(&scene).unwrap();
    let own = crate::gpu::Gpu::new().unwrap();
    let data = lin.field_data();
    let mut o = SphereOptions::default();
    o.lipschitz = 1.45;
    let r = Renderer::new(&own, &data, Traversal::Sphere(o.clone())).unwrap();
    let s = common::settings(common::cube(1.3), 64, 64);
    let before = r.render(&s).unwrap();
    let created = own.pipelines_created.load(Ordering::Relaxed);

    // Move and grow the first primitive: same type, new rows and ball.
    let j = 0;
    let Node::Primitive(p) = &scene.nodes()[lin.order[lin.primitives[j] as usize]] else { unreachable!() };
    let mut q: Primitive = p.clone();
    q.transform.translate[0] += 0.2;
    q.transform.scale *= 1.3;
    let patch = lin.set_primitive(j, &q).unwrap();
    let edited = with_primitive(&scene, &Linear::new(&scene).unwrap(), j, q.clone());
    let rebuilt = Linear::new(&edited).unwrap();
    assert_eq!((&lin.params, &lin.abv, &lin.nodes), (&rebuilt.params, &rebuilt.abv, &rebuilt.nodes));
    assert_eq!(lin.field_data(), rebuilt.field_data());

    r.edit_field(&patch).unwrap();
    let after = r.render(&s).unwrap();
    assert_eq!(own.pipelines_created.load(Ordering::Relaxed), created, "an edit creates no pipeline");
    let fresh = Renderer::new(gpu(), &rebuilt.field_data(), Traversal::Sphere(o)).unwrap().render(&s).unwrap();
    assert_eq!(after.pixels, fresh.pixels, "patched and rebuilt buffers draw the same frame");
    let changed = before.pixels.iter().zip(&after.pixels).filter(|(a, b)| a.status != b.status).count();
    assert!(changed > 10, "the edit shows: {changed} pixels changed");

    // Another type is not an edit in place.
    let sphere = Primitive::new(crate::scene::Shape::Octahedron { size: 0.1 });
    let e = lin.set_primitive(j, &sphere).unwrap_err();
    assert!(e.reason.contains("keeps the primitive's type"), "{e}");
    assert!(lin.set_primitive(lin.primitives.len(), &q).is_err());
}

/// Moving one sphere of a lens moves its partner's limit ball too: the
/// edit in place uploads both balls, as a rebuild would lay them out, and
/// draws the rebuilt frame.
#[test]
fn an_edit_in_place_moves_the_limits_it_bounds() {
    use crate::scene::generate::{generate, Blending, Kind};
    use crate::scene::linear::Linear;
    use crate::scene::{Node, Primitive};
    let scene = generate(Kind::SpherePairs, 0, Blending::Sharp, 5).unwrap();
    let mut lin = Linear::new(&scene).unwrap();
    let own = crate::gpu::Gpu::new().unwrap();
    let r = Renderer::new(&own, &lin.field_data(), Traversal::Sphere(SphereOptions::default())).unwrap();
    let s = common::settings(common::cube(1.3), 64, 64);
    let j = (0..lin.primitives.len()).find(|&j| lin.bounds_a_limit(lin.primitives[j] as usize)).expect("a lens");
    let Node::Primitive(p) = &scene.nodes()[lin.order[lin.primitives[j] as usize]] else { unreachable!() };
    let mut q: Primitive = p.clone();
    q.transform.translate[1] += 0.05;
    let patch = lin.set_primitive(j, &q).unwrap();
    assert!(patch.balls.iter().any(|&(i, _)| i % 2 == 1), "a limit moves: {:?}", patch.balls);
    let rebuilt = Linear::new(&with_primitive(&scene, &Linear::new(&scene).unwrap(), j, q)).unwrap();
    assert_eq!(lin.field_data(), rebuilt.field_data());
    r.edit_field(&patch).unwrap();
    let fresh = Renderer::new(gpu(), &rebuilt.field_data(), Traversal::Sphere(SphereOptions::default())).unwrap().render(&s).unwrap();
    assert_eq!(r.render(&s).unwrap().pixels, fresh.pixels);
}

#[test]
fn the_dense_baseline_draws_the_sparse_picture() {
    use crate::scene::generate::{generate, Blending, Kind};
    let scene = generate(Kind::Aggregate, 1, Blending::Smooth, 3).unwrap();
    let lin = crate::scene::linear::Linear::new(&scene).unwrap();
    let data = lin.field_data();
    let mut o = SphereOptions::default();
    o.lipschitz = 1.45;
    let own = crate::gpu::Gpu::new().unwrap();
    let mut r = Renderer::new(&own, &data, Traversal::Sphere(o)).unwrap();
    let s = common::settings(common::cube(1.3), 64, 64);
    let sparse = r.render(&s).unwrap();
    let created = own.pipelines_created.load(Ordering::Relaxed);
    r.set_dense(true);
    let dense = r.render(&s).unwrap();
    assert_eq!(own.pipelines_created.load(Ordering::Relaxed), created);
    assert_eq!((sparse.stats.field.overflow_tiles, dense.stats.field.overflow_tiles), (0, 0));
    assert_eq!(sparse.stats.field.tile_active, dense.stats.field.tile_active, "the same active primitives per tile");
    // Away from the surface the pruned views give other (larger) values,
    // and each ray starts where its balls begin, so the march samples
    // other points and stops elsewhere within the hit criterion: the
    // screen-space one, a pixel's footprint at that depth. Where a ray
    // grazes a blend within that criterion in front of the surface, one
    // march may stop at the graze and the other pass it (measured: 2 of
    // 745 hits; pixel (37, 30) passes f = 0.048 at t = 5.21, below its
    // footprint 0.059, and hits at 6.17).
    let (hits, far) = same_picture(&sparse, &dense, 64, 64, f32::INFINITY);
    assert!(hits > 200, "{hits}");
    assert!(far * 100 < hits, "{far} of {hits} depths differ by more than a footprint");
}

#[test]
fn a_formula_lowered_to_a_scene_draws_the_compiled_picture() {
    // @creature: smooth unions and a smooth difference, lowered to compact
    // operators (the same zero set), traced with the bound they need.
    let entry = crate::catalog::lookup("creature").unwrap();
    let f = entry.compile().unwrap();
    let s = entry.settings(&f, 96, 72).unwrap();
    let Traversal::Sphere(o) = entry.traversal(&f) else { panic!("creature is sphere traced") };
    let mut t = Traversal::Sphere(o.clone());
    let scene = crate::choice::choose(crate::field::FieldKind::Scene, &f, &[], &t).unwrap();
    let (_, lipschitz) = crate::choice::scene(&f, &[], &t).unwrap();
    assert_eq!(lipschitz, 1.45);
    if let Traversal::Sphere(o) = &mut t {
        o.lipschitz = lipschitz;
    }
    let a = Renderer::new(gpu(), scene.source(&f.ir), t).unwrap().render(&s).unwrap();
    let b = Renderer::sphere(gpu(), &f.ir, o).unwrap().render(&s).unwrap();
    // Both stop within the screen-space hit criterion, a pixel's footprint
    // from the surface (f / L below it): along a grazing ray that is
    // farther, so a few pixels may differ by more. (Thin parts, the
    // antennae, come within that criterion of rays that pass them, so a
    // pixel can stop on one in one picture and behind it in the other.)
    let (both, far, differ) = scene_common::picture_agreement(&a, &b, &s);
    assert!(both > 1500, "{both}");
    assert!(far * 33 < both, "{far} of {both} pixels differ by more than a footprint (measured: 39 of 2062)");
    assert!(differ * 100 < a.pixels.len(), "{differ} pixels hit in one picture only (measured: 53 of 6912, silhouettes)");
    assert_eq!((a.stats.unresolved, a.stats.field.overflow_tiles), (0, 0));
}

/// A union of 60 balls written as distances, `min(sqrt((x - a)^2 + …) - r,
/// …)`, lowers to a scene (which `auto` takes, sphere traced): its picture
/// is the compiled formula's.
#[test]
fn written_out_distances_draw_the_compiled_picture_as_a_scene() {
    let balls: Vec<String> = (0..60)
        .map(|i| {
            let k = i as f64;
            format!("sqrt((x - {:.3})^2 + (y - {:.3})^2 + (z - {:.3})^2) - {:.3}", 0.9 * (0.7 * k).sin(), 0.9 * (1.3 * k).cos(), 0.8 * (0.37 * k).sin(), 0.08 + 0.002 * k)
        })
        .collect();
    let f = Formula::compile("<balls>", &format!("min({})", balls.join(", "))).unwrap();
    let o = SphereOptions::default();
    let t = Traversal::Sphere(o.clone());
    let (field, lipschitz) = crate::choice::auto_scene(&f, &[], &t).expect("auto takes the scene");
    assert_eq!((field.kind(), lipschitz), (crate::field::FieldKind::Scene, 1.0));
    let s = common::settings(common::cube(1.3), 96, 96);
    let a = Renderer::new(gpu(), field.source(&f.ir), t).unwrap().render(&s).unwrap();
    let b = Renderer::sphere(gpu(), &f.ir, o).unwrap().render(&s).unwrap();
    let (both, far, differ) = scene_common::picture_agreement(&a, &b, &s);
    assert!(both > 1000, "{both}");
    assert!(far * 100 < both, "{far} of {both} pixels differ by more than a footprint (measured: 1 of 1,273)");
    assert!(differ * 200 < a.pixels.len(), "{differ} pixels hit in one picture only (measured: 3 of 9,216)");
    assert_eq!(a.stats.unresolved, 0);
}

/// A 5×5×5 grid of small spheres, sharp (cut by a ball that holds it, so
/// that its tiles are not union tiles) or compactly blended in a balanced
/// tree (not comb tiles): every tile sees spheres at several depths, so
/// the views pass cuts its list into depth slabs.
#[test]
fn depth_slabs_draw_the_whole_tree_picture() {
    for smooth in [false, true] {
        let scene = if smooth { sphere_grid_tree() } else { sphere_grid_cut() };
        let lin = crate::scene::linear::Linear::new(&scene).unwrap();
        let data = lin.field_data();
        let mut o = SphereOptions::default();
        o.lipschitz = if smooth { 1.45 } else { 1.0 };
        let own = crate::gpu::Gpu::new().unwrap();
        let mut r = Renderer::new(&own, &data, Traversal::Sphere(o)).unwrap();
        let s = common::settings(common::cube(1.4), 96, 96);
        let sliced = r.render(&s).unwrap();
        r.set_dense(true);
        let dense = r.render(&s).unwrap();
        let f = &sliced.stats.field;
        // The slabs are there (background tiles keep one; measured: 1.75
        // a tile, sharp).
        assert!(f.slabs_mean > 1.5, "smooth {smooth}: {} slabs a tile", f.slabs_mean);
        assert_eq!((f.overflow_tiles, sliced.stats.unresolved, dense.stats.unresolved), (0, 0, 0));
        // As in the dense-baseline test: both stop within a pixel's
        // footprint of the surface.
        let (hits, far) = same_picture(&sliced, &dense, 96, 96, f32::INFINITY);
        assert!(hits > 2000, "{hits}");
        // The slabs' clamped steps sample other points: along a grazing ray
        // the stop within the hit criterion can lie farther (measured: 1 of
        // 2,745 pixels, sharp).
        assert!(far * 200 < hits, "smooth {smooth}: {far} of {hits} depths differ by more than a footprint");
    }
}

/// The sphere tracer's check of how fast f changes along a ray compares
/// values of one view only: where a ray enters a deeper slab, whose view
/// may hold a primitive the shallower one rightly left out, f drops faster
/// than the distance without any bound being broken. The 11,110-primitive
/// aggregate at 512² saw up to 1.12 before (`--stats`), when its tiles had
/// slabs; now every rate is a Lipschitz bound's, and a bound too small is
/// still reported.
#[test]
fn slab_changes_are_not_lipschitz_violations() {
    use crate::scene::generate::{generate, Blending, Kind};
    let scene = generate(Kind::Aggregate, 3, Blending::Sharp, 1).unwrap();
    let lin = crate::scene::linear::Linear::new(&scene).unwrap();
    let data = lin.field_data();
    let own = crate::gpu::Gpu::new().unwrap();
    // At 128² a tile's frustum holds more primitives than a union tile
    // takes (SCENE_UNION_MAX) in many tiles, so those have slabs (at 512²
    // nearly every tile is a union tile, with no slab change at all).
    let s = crate::render::Settings::for_box(lin.bounds.padded().unwrap(), 128, 128);
    let render = |lipschitz: f64| {
        let o = SphereOptions { lipschitz, ..SphereOptions::default() };
        Renderer::new(&own, &data, Traversal::Sphere(o)).unwrap().render(&s).unwrap()
    };
    let right = render(1.0);
    assert!(right.stats.field.slabs_mean > 1.2, "{} slabs a tile", right.stats.field.slabs_mean);
    assert_eq!(right.stats.sphere.lipschitz_violations, 0, "largest rate {}", right.stats.sphere.lipschitz_seen);
    assert!(right.stats.sphere.lipschitz_seen <= 1.0 + 1e-3, "{}", right.stats.sphere.lipschitz_seen);
    // Compact smooth unions raise the bound above 1: traced with 1, the
    // check still sees it within a slab or a ray's own chain (512²).
    let smooth = generate(Kind::Aggregate, 2, Blending::Smooth, 1).unwrap();
    let data = crate::scene::linear::Linear::new(&smooth).unwrap().field_data();
    let o = SphereOptions { lipschitz: 1.0, ..SphereOptions::default() };
    let s = crate::render::Settings::for_box(lin.bounds.padded().unwrap(), 512, 512);
    let wrong = Renderer::new(&own, &data, Traversal::Sphere(o)).unwrap().render(&s).unwrap();
    assert!(wrong.stats.sphere.lipschitz_seen > 1.05, "{:?}", wrong.stats.sphere);
}

/// A frame split into several dispatches (each with its own tile lists,
/// slabs and views) draws the one-dispatch picture.
#[test]
fn a_scene_split_into_dispatches_draws_the_same_frame() {
    let lin = crate::scene::linear::Linear::new(&sphere_grid(true)).unwrap();
    let data = lin.field_data();
    let mut o = SphereOptions::default();
    o.lipschitz = 1.45;
    let r = Renderer::new(gpu(), &data, Traversal::Sphere(o)).unwrap();
    let mut s = common::settings(common::cube(1.4), 80, 72);
    let whole = r.render(&s).unwrap();
    s.tile = 24;
    let split = r.render(&s).unwrap();
    assert!(split.stats.dispatches > 1 && whole.stats.dispatches == 1);
    assert_eq!(whole.stats.hits, split.stats.hits);
    for (a, b) in whole.pixels.iter().zip(&split.pixels) {
        assert_eq!((a.status, a.depth), (b.status, b.depth));
    }
}

/// Two small spheres far apart: most 8×8 tiles meet no primitive, so the
/// sphere tracer's tile pass writes them as background and leaves them out
/// of `main` (tiles.wgsl). No hit is lost to it: every pixel away from the
/// silhouettes has the status of the analytic ray–sphere test, and hits
/// its depth.
#[test]
fn a_sparse_scene_leaves_its_empty_tiles_to_the_tile_pass_and_misses_no_sphere() {
    let f = Formula::compile("<t>", "union(translate(-1, 0, 0, sphere(0.3)), translate(1, 0, 0, sphere(0.3)))").unwrap();
    let scene = crate::scene::from_formula(&f, &[]).unwrap();
    let data = crate::scene::linear::Linear::new(&scene).unwrap().field_data();
    let (w, h) = (192, 144);
    let s = common::settings(common::cube(1.5), w, h);
    let frame = Renderer::new(gpu(), &data, Traversal::Sphere(SphereOptions::default())).unwrap().render(&s).unwrap();
    assert!(frame.stats.tile_ms > 0.0, "the tile pass ran");
    let (hits, misses) = check_against_spheres(&frame, &s, |eye, d, foot| {
        let mut nearest: Option<(f64, glam::DVec3, f64)> = None;
        let mut grazing = false;
        for c in [glam::DVec3::new(-1.0, 0.0, 0.0), glam::DVec3::new(1.0, 0.0, 0.0)] {
            grazing |= (((eye - c) - d * (eye - c).dot(d)).length() - 0.3).abs() < 2.0 * foot;
            if let Some((t, _)) = ray_ball(eye, d, c, 0.3) {
                if nearest.is_none_or(|(n, _, _)| t < n) {
                    nearest = Some((t, c, 0.3));
                }
            }
        }
        (nearest, grazing)
    });
    assert!(hits > 150 && misses > 20000, "hits {hits}, misses {misses}");
}

/// The distance from the line eye + t d to the circle where the spheres
/// (ca, ra) and (cb, rb) meet (infinite if they do not), by sampling it.
fn ray_rim_distance(eye: glam::DVec3, d: glam::DVec3, (ca, ra): (glam::DVec3, f64), (cb, rb): (glam::DVec3, f64)) -> f64 {
    let dist = (cb - ca).length();
    let x = (dist * dist + ra * ra - rb * rb) / (2.0 * dist);
    if ra * ra < x * x {
        return f64::INFINITY;
    }
    let u = (cb - ca) / dist;
    let (e1, e2) = u.any_orthonormal_pair();
    let h = (ra * ra - x * x).sqrt();
    (0..1024)
        .map(|k| {
            let phi = k as f64 * std::f64::consts::TAU / 1024.0;
            let q = ca + u * x + (e1 * phi.cos() + e2 * phi.sin()) * h - eye;
            (q - d * q.dot(d)).length()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Intersections and a difference of spheres, which the tile passes list
/// only where both operands can be (a lens's ball, `scene::reach`), and
/// whose rays each take the range of their tile's balls: a thin lens, a
/// sphere mostly inside the other, a thick lens and a bitten sphere. Every
/// pixel away from the silhouettes and rims has the status of the analytic
/// ray test, and hits its depth with the sphere's normal there; and each
/// operand of an intersection, and the bite, has a limit ball.
#[test]
fn intersected_spheres_are_listed_where_their_lens_is_and_miss_no_pixel() {
    use glam::DVec3;
    let pairs = [
        ((DVec3::new(-0.9, 0.5, 0.0), 0.5), (DVec3::new(-0.1, 0.5, 0.0), 0.45)),
        ((DVec3::new(0.8, 0.5, 0.0), 0.4), (DVec3::new(0.9, 0.5, 0.1), 0.6)),
        ((DVec3::new(-0.5, -0.6, 0.0), 0.6), (DVec3::new(0.3, -0.6, 0.0), 0.6)),
    ];
    let bitten = ((DVec3::new(0.9, -0.6, 0.0), 0.4), (DVec3::new(1.15, -0.45, 0.2), 0.35));
    let sphere = |(c, r): (DVec3, f64)| format!("translate({}, {}, {}, sphere({r}))", c.x, c.y, c.z);
    let lenses: Vec<String> = pairs.iter().map(|&(a, b)| format!("intersect({}, {})", sphere(a), sphere(b))).collect();
    let src = format!("union({}, subtract({}, {}))", lenses.join(", "), sphere(bitten.0), sphere(bitten.1));
    let f = Formula::compile("<t>", &src).unwrap();
    let scene = crate::scene::from_formula(&f, &[]).unwrap();
    let lin = crate::scene::linear::Linear::new(&scene).unwrap();
    let data = lin.field_data();
    let (w, h) = (240, 180);
    let s = common::settings(common::cube(1.5), w, h);
    let frame = Renderer::new(gpu(), &data, Traversal::Sphere(SphereOptions::default())).unwrap().render(&s).unwrap();
    let (hits, misses) = check_against_spheres(&frame, &s, |eye, d, foot| {
        let mut nearest: Option<(f64, DVec3, f64)> = None;
        let mut grazing = false;
        let mut hit = |t: f64, c: DVec3, r: f64| {
            if nearest.is_none_or(|(n, _, _)| t < n) {
                nearest = Some((t, c, r));
            }
        };
        for &(a, b) in pairs.iter().chain(std::iter::once(&bitten)) {
            for (c, r) in [a, b] {
                let miss_by = ((eye - c) - d * (eye - c).dot(d)).length() - r;
                grazing |= miss_by.abs() < 2.0 * foot;
            }
            grazing |= ray_rim_distance(eye, d, a, b) < 2.0 * foot;
        }
        for &((ca, ra), (cb, rb)) in &pairs {
            if let (Some(a), Some(b)) = (ray_ball(eye, d, ca, ra), ray_ball(eye, d, cb, rb)) {
                let (t0, t1) = (a.0.max(b.0), a.1.min(b.1));
                if t0 <= t1 {
                    if a.0 >= b.0 { hit(t0, ca, ra) } else { hit(t0, cb, rb) }
                }
            }
        }
        let ((ca, ra), (cb, rb)) = bitten;
        if let Some(a) = ray_ball(eye, d, ca, ra) {
            match ray_ball(eye, d, cb, rb) {
                Some(b) if a.0 >= b.0 && a.0 <= b.1 => {
                    if b.1 < a.1 {
                        hit(b.1, cb, -rb);
                    }
                }
                _ => hit(a.0, ca, ra),
            }
        }
        (nearest, grazing)
    });
    assert!(hits > 400 && misses > 30000, "hits {hits}, misses {misses}");
    // Each lens's limit is its other sphere; the bitten sphere's bite is
    // limited to the sphere; the sphere it bites is not limited.
    let limits: Vec<f32> = data.balls.iter().skip(1).step_by(2).map(|b| b[3]).collect();
    assert_eq!(limits.len(), 8);
    assert_eq!(limits.iter().filter(|r| r.is_finite()).count(), 7, "{limits:?}");
}
