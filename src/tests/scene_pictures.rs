//! Checks of scene pictures shared by the scene tests on the device: two
//! paths' pictures against each other, a picture of spheres against the
//! analytic ray test, and a grid of spheres that gives tiles several depth
//! slabs.
#![allow(dead_code)]

use crate::render::Status;

/// Two pictures of one surface drawn by different paths (the scene's
/// pruned views and per-ray ranges against the whole tree or the compiled
/// formula), at the default 40° field of view and `h` rows: the statuses
/// agree except on silhouettes (a pixel with a 4-neighbour of the other
/// status in either picture), where whether a grazing ray comes within the
/// screen-space criterion depends on the points the march samples, so on
/// where it starts; those are fewer than 1 % of the hits. Hit depths agree
/// within `tol` footprints (a pixel's width at that depth). Returns the
/// hits and the hits whose depths differ by more than a footprint.
pub fn same_picture(a: &crate::render::Frame, b: &crate::render::Frame, w: usize, h: usize, tol: f32) -> (usize, usize) {
    let (mut hits, mut far, mut edge) = (0, 0, 0);
    for j in 0..h {
        for i in 0..w {
            let (p, q) = (a.pixels[j * w + i], b.pixels[j * w + i]);
            if p.status != q.status {
                let near = [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)].iter().any(|&(di, dj)| {
                    let (x, y) = (i as i64 + di, j as i64 + dj);
                    let k = (y * w as i64 + x) as usize;
                    x >= 0 && y >= 0 && (x as usize) < w && (y as usize) < h && (b.pixels[k].status != q.status || a.pixels[k].status != p.status)
                });
                assert!(near, "pixel ({i}, {j}): {:?} against {:?} away from a silhouette", p.status, q.status);
                edge += 1;
                continue;
            }
            if p.status == Status::Hit {
                hits += 1;
                let footprint = 2.0 * p.depth * (20f32).to_radians().tan() / h as f32;
                assert!((p.depth - q.depth).abs() < tol * footprint, "pixel ({i}, {j}): depth {} against {}", p.depth, q.depth);
                far += ((p.depth - q.depth).abs() > footprint) as usize;
            }
        }
    }
    assert!(edge * 100 <= hits, "{edge} silhouette pixels differ, of {hits} hits");
    (hits, far)
}

/// Checks a scene frame of spheres pixel by pixel against the analytic
/// ray test `expect(eye, d, footprint)`: the nearest hit (depth, the sphere
/// hit: centre and radius, negative where the sphere bounds the solid from
/// inside) and whether the ray passes near an edge, where a pixel may go
/// either way (skipped). Elsewhere the status agrees; a hit's depth is
/// within the screen-space criterion (a footprint, along the ray 1/cos of
/// it) and its normal is the sphere's radial direction where the ray
/// stopped (the tracer's forward differences from its last fixed-point
/// value). Returns the hits and misses checked.
pub fn check_against_spheres(frame: &crate::render::Frame, s: &crate::render::Settings, mut expect: impl FnMut(glam::DVec3, glam::DVec3, f64) -> (Option<(f64, glam::DVec3, f64)>, bool)) -> (usize, usize) {
    use glam::DVec3;
    let (w, h) = (s.width, s.height);
    let cf = s.camera.frame().unwrap();
    let eye = s.camera.eye;
    // A pixel's footprint at the scene's distance, in world units.
    let foot = 2.0 * cf.tan_half_fov * eye.length() / h as f64;
    let (mut hits, mut misses) = (0, 0);
    for j in 0..h {
        for i in 0..w {
            let d = crate::render::Camera::ray(&cf, i, j, w, h);
            let (nearest, grazing) = expect(eye, d, foot);
            if grazing {
                continue;
            }
            let p = frame.pixels[(j * w + i) as usize];
            match nearest {
                Some((t, c, r)) => {
                    assert_eq!(p.status, Status::Hit, "pixel ({i}, {j}) should hit at {t}");
                    let tol = foot / ((eye + d * t - c) / r).dot(d).abs().max(0.2);
                    assert!((p.depth as f64 - t).abs() < tol, "pixel ({i}, {j}): depth {} against {t} (tolerance {tol})", p.depth);
                    let n = (eye + d * p.depth as f64 - c).normalize() * r.signum();
                    let got = DVec3::new(p.normal[0] as f64, p.normal[1] as f64, p.normal[2] as f64);
                    assert!(got.dot(n) > 0.9995, "pixel ({i}, {j}): normal {got} against {n}");
                    hits += 1;
                }
                None => {
                    assert_eq!(p.status, Status::Miss, "pixel ({i}, {j}) should miss");
                    misses += 1;
                }
            }
        }
    }
    (hits, misses)
}

/// The ray's interval in the ball (c, r), if it meets it.
pub fn ray_ball(eye: glam::DVec3, d: glam::DVec3, c: glam::DVec3, r: f64) -> Option<(f64, f64)> {
    let oc = eye - c;
    let b = oc.dot(d);
    let disc = b * b - (oc.length_squared() - r * r);
    (disc >= 0.0).then(|| (-b - disc.sqrt(), -b + disc.sqrt()))
}

/// The 125 spheres of radius 0.17 on a 5×5×5 grid of spacing 0.5 in
/// [−1, 1]³, added to `b`.
fn grid_spheres(b: &mut crate::scene::Builder) -> Vec<crate::scene::NodeId> {
    use crate::scene::{Primitive, Shape};
    (0..125)
        .map(|i| {
            let c = [i % 5, i / 5 % 5, i / 25].map(|k| -1.0 + 0.5 * k as f64);
            b.primitive(Primitive::new(Shape::Sphere { radius: 0.17 }).translated(c))
        })
        .collect()
}

/// The compact smooth union of the grids below (β 0.1).
fn grid_blend() -> crate::scene::Operator {
    use crate::scene::{Blend, OpKind, Operator};
    Operator::smooth(OpKind::Union, Blend { beta: 0.1, range: 0.2 })
}

/// The grid's spheres combined as a left comb of sharp or compact smooth
/// unions.
pub fn sphere_grid(smooth: bool) -> crate::scene::Scene {
    let mut b = crate::scene::Builder::default();
    let items = grid_spheres(&mut b);
    let op = if smooth { grid_blend() } else { crate::scene::Operator::UNION };
    let root = b.fold(op, &items);
    b.finish(root).unwrap()
}

/// The compactly blended grid as a balanced tree of smooth unions (the
/// fold of `sphere_grid` is a left comb): its leaves are on no comb, so
/// its tiles are cut into depth slabs where the comb's are comb tiles.
pub fn sphere_grid_tree() -> crate::scene::Scene {
    let mut b = crate::scene::Builder::default();
    let mut items = grid_spheres(&mut b);
    while items.len() > 1 {
        items = items.chunks(2).map(|p| if p.len() == 2 { b.operator(grid_blend(), p[0], p[1]) } else { p[0] }).collect();
    }
    b.finish(items[0]).unwrap()
}

/// The sharp grid cut by a ball that holds it (the same surface): no leaf
/// is on a union path, so its tiles are cut into depth slabs where the
/// plain sharp grid's tiles are union tiles.
pub fn sphere_grid_cut() -> crate::scene::Scene {
    use crate::scene::{Operator, Primitive, Shape};
    let mut b = crate::scene::Builder::default();
    let items = grid_spheres(&mut b);
    let grid = b.fold(Operator::UNION, &items);
    let hull = b.primitive(Primitive::new(Shape::Sphere { radius: 2.5 }));
    let root = b.operator(Operator::INTERSECTION, grid, hull);
    b.finish(root).unwrap()
}
