//! The synchronised walk of a scene's tiles (`SphereOptions::synchronized`,
//! `render --scene-walk tile`; Zanni et al.'s Algorithm 3): the rays of an
//! 8×8 tile trace its depth slabs together, each slab's view copied into
//! workgroup memory. It must draw what the per-ray walk draws, and miss no
//! surface at the slabs' seams.

use super::common;
use super::scene_pictures;

use glam::DVec3;
use crate::gpu::Renderer;
use crate::render::{SphereOptions, Traversal};
use scene_pictures::{check_against_spheres, ray_ball, same_picture, sphere_grid, sphere_grid_cut, sphere_grid_tree};

fn walk(synchronized: bool, lipschitz: f64) -> Traversal {
    Traversal::Sphere(SphereOptions { synchronized, lipschitz, ..SphereOptions::default() })
}

/// Sharp (cut by a ball that holds them) and compactly blended (a
/// balanced tree) sphere grids, whose tiles have several slabs, and the
/// plain sharp and smooth-comb grids, whose tiles are union and comb tiles
/// (one slab; each ray evaluates its own members): the two walks agree
/// pixel by pixel (statuses but on silhouettes, depths within a
/// footprint), and the synchronised one reports what it did.
#[test]
fn the_synchronised_walk_draws_the_per_ray_picture() {
    let own = crate::gpu::Gpu::new().unwrap();
    let grids = [("cut", sphere_grid_cut(), 1.0), ("tree", sphere_grid_tree(), 1.45), ("union", sphere_grid(false), 1.0), ("comb", sphere_grid(true), 1.45)];
    for (name, scene, l) in grids {
        let data = crate::scene::linear::Linear::new(&scene).unwrap().field_data();
        let s = common::settings(common::cube(1.4), 120, 96);
        let ray = Renderer::new(&own, &data, walk(false, l)).unwrap().render(&s).unwrap();
        let tile = Renderer::new(&own, &data, walk(true, l)).unwrap().render(&s).unwrap();
        let slabs = tile.stats.field.slabs_mean;
        // (A chain tile holds at most 64 members: a few of the comb's tiles
        // have more, and slabs.)
        assert!(if matches!(name, "cut" | "tree") { slabs > 1.5 } else { slabs < 1.1 }, "{name}: {slabs} slabs a tile");
        assert_eq!((tile.stats.unresolved, tile.stats.field.overflow_tiles), (0, 0));
        // As between the slabs and the whole tree (src/tests/scene_gpu.rs): a
        // ray that grazes one sphere within the screen-space criterion on
        // its way to another may stop at either, depending on where its
        // march samples, and the synchronised march restarts at each slab
        // (measured: 1 such pixel of 2,310 sharp).
        let (hits, far) = same_picture(&ray, &tile, 120, 96, f32::INFINITY);
        assert!(hits > 2000, "{hits}");
        assert!(far * 200 < hits, "{name}: {far} of {hits} depths differ by more than a footprint");
        // Restarting at each slab costs steps; it never saves all of them.
        assert!(tile.stats.evals_mean >= ray.stats.evals_mean * 0.9, "{} against {}", tile.stats.evals_mean, ray.stats.evals_mean);
    }
}

/// The sharp grid (cut, so that its tiles have slabs) against the
/// analytic ray test: every pixel away from a silhouette hits the nearest
/// sphere at its depth with its normal, though most rays cross from one
/// slab's view into the next.
#[test]
fn the_synchronised_walk_misses_no_sphere_at_a_slab_seam() {
    let data = crate::scene::linear::Linear::new(&sphere_grid_cut()).unwrap().field_data();
    let (frame, hits, misses) = analytic_grid(&data, true);
    eprintln!("hits {hits}, misses {misses}, slabs {}", frame.stats.field.slabs_mean);
    assert!(frame.stats.field.slabs_mean > 1.2 && hits > 1000 && misses > 30000, "hits {hits}, misses {misses}");
    assert_eq!(frame.stats.field.chain_share, 0.0, "no union or comb tile under the cut");
}

/// The plain sharp grid: every tile is a union tile (one slab; each ray
/// evaluates only the spheres whose balls it meets), and both walks draw
/// the analytic spheres, status, depth and normal, on every pixel away
/// from a silhouette. A ray that dropped a sphere it meets would miss it
/// or stop behind it.
#[test]
fn union_tiles_draw_the_analytic_spheres() {
    let data = crate::scene::linear::Linear::new(&sphere_grid(false)).unwrap().field_data();
    for synchronized in [false, true] {
        let (frame, hits, misses) = analytic_grid(&data, synchronized);
        let f = &frame.stats.field;
        assert_eq!((f.slabs_mean, f.chain_share, f.overflow_tiles, frame.stats.unresolved), (1.0, 1.0, 0, 0), "sync {synchronized}");
        assert!(hits > 1000 && misses > 30000, "sync {synchronized}: hits {hits}, misses {misses}");
    }
}

/// The 125-sphere grid's scene `data` rendered at 320×240 with the walk
/// asked for, checked against the analytic ray test: the frame, the hit
/// and the miss pixels checked.
fn analytic_grid(data: &crate::field::SceneData, synchronized: bool) -> (crate::render::Frame, usize, usize) {
    let (w, h) = (320, 240);
    let s = common::settings(common::cube(1.4), w, h);
    let frame = Renderer::new(common::gpu(), data, walk(synchronized, 1.0)).unwrap().render(&s).unwrap();
    let centres: Vec<DVec3> = (0..125).map(|i| DVec3::new((i % 5) as f64, (i / 5 % 5) as f64, (i / 25) as f64) * 0.5 - DVec3::ONE).collect();
    let (hits, misses) = check_against_spheres(&frame, &s, |eye, d, foot| {
        let mut nearest: Option<(f64, DVec3, f64)> = None;
        let mut grazing = false;
        for &c in &centres {
            grazing |= (((eye - c) - d * (eye - c).dot(d)).length() - 0.17).abs() < 2.0 * foot;
            if let Some((t, _)) = ray_ball(eye, d, c, 0.17) {
                if nearest.is_none_or(|(n, _, _)| t < n) {
                    nearest = Some((t, c, 0.17));
                }
            }
        }
        (nearest, grazing)
    });
    (frame, hits, misses)
}

/// The walk is part of the kernel: a renderer built for one refuses
/// options asking for the other, and a formula's field ignores nothing
/// silently (the CLI refuses the flag there, tests/scene_cli.rs).
#[test]
fn the_walk_is_compiled_in() {
    let data = crate::scene::linear::Linear::new(&sphere_grid(false)).unwrap().field_data();
    let mut r = Renderer::new(common::gpu(), &data, walk(false, 1.0)).unwrap();
    let e = r.set_sphere_options(SphereOptions { synchronized: true, ..SphereOptions::default() }).unwrap_err();
    assert!(e.to_string().contains("the kernel was compiled for the other walk"), "{e}");
    let wgsl = crate::kernel::assemble(&data, &walk(true, 1.0)).wgsl;
    assert!(wgsl.contains("var<workgroup> scene_sync_pruned") && wgsl.contains("workgroupUniformLoad"));
    let per_ray = crate::kernel::assemble(&data, &walk(false, 1.0)).wgsl;
    assert!(!per_ray.contains("var<workgroup>"));
}
