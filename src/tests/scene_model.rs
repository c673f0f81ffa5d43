//! Blobtree scenes against the oracles of `../shared/guide/blobtree-reference`
//! (ported from test_lip.py, test_roi.py, test_sparse.py): the compact
//! operators' continuity and Lipschitz factor, the per-node ROI property,
//! the sparse traversal = masked evaluation bit for bit (within rounding
//! for folded chains of unary nodes), ABV containment;
//! and primitives against analytic values and against the formula path.

use super::scene_common;

use crate::reference::eval_scalar;
use crate::scene::generate::Rng;
use crate::scene::linear::Linear;
use crate::scene::OpKind;
use crate::sdf::operator::compact;
use crate::scene::roi::{self, Abv};
use crate::scene::sparse::{self, Ancestors};
use crate::scene::{Builder, Node, Operator, Primitive, Scene, Shape};
use crate::Formula;
use scene_common::{assert_sparse_is_masked, random_primitive, random_tree, region_of_interest, surface_points, TreeShape};

const KINDS: [OpKind; 3] = [OpKind::Union, OpKind::Intersection, OpKind::Difference];

/// §4.1: G is continuous across the edge of R_o for r_o ≥ 7β/6, and its
/// Lipschitz constant (sup over |∂a| + |∂b|, from both diagonal
/// differences) is at most 6r_o/(6r_o − β).
#[test]
fn compact_operators_are_continuous_and_raise_lipschitz_by_the_factor() {
    let beta = 1.0;
    for ro in [7.0 / 6.0, 1.25, 1.5, 2.0, 3.0, 5.0] {
        let factor = 6.0 * ro / (6.0 * ro - beta);
        for kind in KINDS {
            let g = |a: f64, b: f64| compact(kind, a, b, beta, ro);
            let (n, h) = (500, 1e-6);
            let mut lmax: f64 = 0.0;
            for i in 0..=n {
                for j in 0..=n {
                    let a = -2.0 * ro + 4.0 * ro * i as f64 / n as f64;
                    let b = -2.0 * ro + 4.0 * ro * j as f64 / n as f64;
                    let d1 = (g(a + h, b + h) - g(a - h, b - h)).abs() / (2.0 * h);
                    let d2 = (g(a + h, b - h) - g(a - h, b + h)).abs() / (2.0 * h);
                    lmax = lmax.max(d1).max(d2);
                }
            }
            assert!(lmax <= factor * (1.0 + 1e-4), "{kind:?} r_o {ro}: L {lmax} > {factor}");
            assert!(edge_jump(kind, beta, ro) < 1e-6, "{kind:?} r_o {ro}: jump at the edge of R_o");
        }
    }
    // Below 7β/6 the union jumps at the edge (the brief: 2.5e-3 at r_o = β).
    let jump = edge_jump(OpKind::Union, beta, 1.0);
    assert!(jump > 1e-3, "expected a jump, got {jump}");
}

/// The largest change of G across the edges of R_o (a or b = ±r_o).
fn edge_jump(kind: OpKind, beta: f64, ro: f64) -> f64 {
    let g = |a: f64, b: f64| compact(kind, a, b, beta, ro);
    let e = 1e-9;
    let mut worst: f64 = 0.0;
    for k in 0..=4000 {
        let t = -3.0 * ro + 6.0 * ro * k as f64 / 4000.0;
        for edge in [ro, -ro] {
            worst = worst.max((g(edge - e, t) - g(edge + e, t)).abs());
            worst = worst.max((g(t, edge - e) - g(t, edge + e)).abs());
        }
    }
    worst
}

/// Node values at every node for a set of active primitives (indexed by scene node).
fn active_by_roi(scene: &Scene, p: [f64; 3], shrink: f64) -> Vec<bool> {
    let r = roi::ranges(scene);
    scene.nodes().iter().enumerate().map(|(i, n)| matches!(n, Node::Primitive(q) if q.distance(p) <= r[i].hi * shrink)).collect()
}

fn roi_violations(seed: u64, shrink: f64) -> (usize, usize) {
    let mut rng = Rng::new(300 + seed);
    let (mut bad, mut checks) = (0, 0);
    for _ in 0..40 {
        let n = 2 + rng.below(39) as usize;
        let shape = [TreeShape::Random, TreeShape::Left, TreeShape::Balanced][rng.below(3) as usize];
        let scene = random_tree(&mut rng, n, shape, 0.7, true);
        let r = roi::ranges(&scene);
        for p in surface_points(&scene, &mut rng, 60, 0.4) {
            let full = scene.eval_nodes(p);
            let masked = scene.eval_masked_nodes(p, &active_by_roi(&scene, p, shrink));
            for i in 0..scene.len() {
                let (f, s) = (full[i], masked[i].unwrap_or(f64::INFINITY));
                let ok = if f > r[i].hi {
                    s > r[i].hi
                } else if f < r[i].lo {
                    s < r[i].lo
                } else {
                    s == f || (s - f).abs() <= 1e-12 * f.abs().max(1.0)
                };
                checks += 1;
                bad += !ok as usize;
            }
        }
    }
    (bad, checks)
}

/// §4.2: with A = {p : f_p ≤ r_p⁺}, every node of the masked tree equals
/// the full one inside its ROI and stays on the same side outside it.
#[test]
fn masked_evaluation_keeps_every_node_within_its_range_of_interest() {
    let (mut bad, mut checks) = (0, 0);
    for seed in 0..2 {
        let (b, c) = roi_violations(seed, 1.0);
        bad += b;
        checks += c;
    }
    assert!(checks > 50_000, "only {checks} checks");
    assert_eq!(bad, 0, "{bad} violations in {checks} checks");
    // The oracle has teeth: halving r⁺ breaks it.
    let (bad, _) = roi_violations(0, 0.5);
    assert!(bad > 0);
}

/// §4.3: the sparse traversal with parent or fast ancestors, directly or
/// through the pruned view, gives the masked value bit for bit; its sign is
/// the full field's when A holds every needed primitive; the traversal
/// stack stays below the evaluation stack depth.
#[test]
fn sparse_traversal_equals_masked_evaluation_bit_for_bit() {
    let mut rng = Rng::new(11);
    let (mut checks, mut max_stack) = (0, 0);
    for _ in 0..150 {
        let n = 1 + rng.below(40) as usize;
        let shape = [TreeShape::Random, TreeShape::Left, TreeShape::Balanced][rng.below(3) as usize];
        let scene = random_tree(&mut rng, n, shape, 0.6, false);
        let lin = Linear::new(&scene).unwrap();
        let r = roi::ranges(&scene);
        for _ in 0..80 {
            let p = [0, 1, 2].map(|_| rng.range(-4.5, 4.5));
            let mut active = vec![false; scene.len()];
            let mut a = Vec::new();
            for &k in &lin.primitives {
                let i = lin.order[k as usize];
                let Node::Primitive(q) = &scene.nodes()[i] else { unreachable!() };
                if q.distance(p) <= r[i].hi || rng.unit() < 0.3 {
                    active[i] = true;
                    a.push(k);
                }
            }
            let (reference, stack) = assert_sparse_is_masked(&lin, &scene, p, &active, &a);
            max_stack = max_stack.max(stack);
            checks += 2;
            let full = scene.eval(p);
            match reference {
                _ if full.abs() < 1e-9 => {}
                None => assert!(full > 0.0),
                Some(v) => assert_eq!(v > 0.0, full > 0.0, "sign of {v} vs full {full}"),
            }
        }
    }
    assert!(checks >= 20_000 && max_stack >= 2, "{checks} checks, max stack {max_stack}");
}

/// Fast ancestors skip selecting operators: on a left comb of unions the
/// traversal of one active primitive visits a handful of nodes, not the
/// whole spine (the brief's table: 3 vs 2268 at 4000 primitives).
#[test]
fn fast_ancestors_shortcut_left_combs() {
    let mut rng = Rng::new(5);
    let mut b = Builder::default();
    let leaves: Vec<_> = (0..4000)
        .map(|_| {
            let centre = [0, 1, 2].map(|_| rng.range(-9.0, 9.0));
            b.primitive(random_primitive(&mut rng, centre, 1.0, false))
        })
        .collect();
    let root = b.fold(Operator::UNION, &leaves);
    let scene = b.finish(root).unwrap();
    let lin = Linear::new(&scene).unwrap();
    let (mut fast, mut parent) = (0, 0);
    for _ in 0..20 {
        let k = lin.primitives[rng.below(lin.primitives.len() as u64) as usize];
        fast += sparse::build_view(&lin, &scene, &[k], Ancestors::Fast).unwrap().visits;
        parent += sparse::build_view(&lin, &scene, &[k], Ancestors::Parent).unwrap().visits;
    }
    assert!(fast * 100 < parent, "fast {fast} parent {parent}");
}

/// Every point with f_p ≤ r_p⁺ lies in p's ABV, in f64 and in the f32 rows.
#[test]
fn abvs_contain_the_primitives_region_of_interest() {
    let mut rng = Rng::new(21);
    let mut inside = 0;
    for _ in 0..400 {
        let centre = [0, 1, 2].map(|_| rng.range(-2.0, 2.0));
        let size = rng.range(0.3, 1.5);
        let prim = random_primitive(&mut rng, centre, size, false);
        let (r_plus, abv, points) = region_of_interest(&mut rng, &prim);
        let rows = crate::scene::linear::abv_rows(&abv);
        inside += points.len();
        for p in points {
            assert!(abv.contains(p), "{prim:?} r+ {r_plus}: {p:?} outside {abv:?}");
            assert!(decode_abv(&rows).contains(p), "f32 rows of {abv:?} miss {p:?}");
        }
    }
    assert!(inside > 5_000, "{inside}");
}

/// The ABV the f32 rows describe (the layout of `linear.rs`).
fn decode_abv(rows: &[[f32; 4]; 4]) -> Abv {
    let v = |r: [f32; 4]| [r[0] as f64, r[1] as f64, r[2] as f64];
    match rows[0][3] as u32 {
        1 => Abv::Sphere { centre: v(rows[0]), radius: rows[1][3] as f64 },
        2 => Abv::Box { centre: v(rows[0]), axes: [v(rows[1]), v(rows[2]), v(rows[3])], half: [rows[1][3], rows[2][3], rows[3][3]].map(f64::from) },
        3 => Abv::Capsule { a: v(rows[0]), b: v(rows[1]), radius: rows[1][3] as f64 },
        _ => Abv::Always,
    }
}

#[test]
fn primitive_distances_match_analytic_values() {
    let d = |p: &Primitive, x: [f64; 3]| p.distance(x);
    let sphere = Primitive::new(Shape::Sphere { radius: 1.5 }).translated([1.0, 2.0, 3.0]);
    assert_eq!(d(&sphere, [1.0, 2.0, 7.0]), 2.5);
    assert_eq!(d(&sphere, [1.0, 2.0, 3.0]), -1.5);
    let bx = Primitive::new(Shape::Box { half: [1.0, 2.0, 3.0] });
    assert_eq!(d(&bx, [3.0, 0.0, 0.0]), 2.0);
    assert_eq!(d(&bx, [0.0, 0.0, 0.0]), -1.0);
    assert!((d(&bx, [2.0, 3.0, 4.0]) - 3f64.sqrt()).abs() < 1e-15);
    // A quarter turn about z swaps the x and y extents.
    let turned = bx.clone().rotated([0.0, 0.0, 1.0], std::f64::consts::FRAC_PI_2);
    assert!((d(&turned, [3.0, 0.0, 0.0]) - 1.0).abs() < 1e-12);
    // Scale multiplies distances.
    assert_eq!(d(&Primitive::new(Shape::Sphere { radius: 1.0 }).scaled(2.0), [5.0, 0.0, 0.0]), 3.0);
    let plane = Primitive::new(Shape::Plane { normal: [0.0, 0.0, 2.0], offset: 1.0 });
    assert_eq!(d(&plane, [5.0, 5.0, 3.0]), 2.0);
}

fn formula_value(src: &str, p: [f64; 3]) -> f64 {
    let f = Formula::compile("<scene>", src).unwrap_or_else(|e| panic!("{e}\n{src}"));
    eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[])
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()))
}

/// Each primitive equals the formula built from the same sdf.rs forms.
#[test]
fn primitives_equal_the_formula_path() {
    let written = [
        ("translate(1, 2, 3, rotate(0, 0, 1, 0.5, box(1, 2, 3)))", Primitive::new(Shape::Box { half: [1.0, 2.0, 3.0] }).rotated([0.0, 0.0, 1.0], 0.5).translated([1.0, 2.0, 3.0])),
        ("scale(2, torus(1, 0.25))", Primitive::new(Shape::Torus { major: 1.0, minor: 0.25 }).scaled(2.0)),
        ("plane(0, 1, 1, 0.5)", Primitive::new(Shape::Plane { normal: [0.0, 1.0, 1.0], offset: 0.5 })),
    ];
    let mut rng = Rng::new(4);
    for (src, prim) in written {
        for _ in 0..200 {
            let p = [0, 1, 2].map(|_| rng.range(-4.0, 4.0));
            assert!(close(prim.distance(p), formula_value(src, p)), "{src} at {p:?}");
        }
    }
    for k in 0..8 {
        for _ in 0..10 {
            let (centre, size) = ([0, 1, 2].map(|_| rng.range(-1.0, 1.0)), rng.range(0.5, 1.5));
            let prim = scene_common::primitive_of_kind(&mut rng, k, centre, size);
            let src = crate::scene::formula::primitive_formula(&prim).expect("a basic primitive has a form");
            let f = Formula::compile("<scene>", &src).unwrap();
            for _ in 0..100 {
                let p = [0, 1, 2].map(|_| rng.range(-3.0, 3.0));
                let (a, b) = (prim.distance(p), eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[]));
                assert!(close(a, b), "{src} at {p:?}: scene {a}, formula {b}");
            }
        }
    }
}

/// Sharp operators equal `union`, `intersect` and `subtract`; compact ones
/// equal `compact_union`, `compact_intersect` and `compact_subtract`.
#[test]
fn scenes_equal_their_formula() {
    let mut rng = Rng::new(8);
    for smooth in [0.0, 0.7] {
        for _ in 0..30 {
            let n = 2 + rng.below(8) as usize;
            let scene = random_tree(&mut rng, n, TreeShape::Random, smooth, false);
            let src = crate::scene::formula::to_formula(&scene).unwrap();
            let f = Formula::compile("<scene>", &src).unwrap_or_else(|e| panic!("{e}"));
            for _ in 0..100 {
                let p = [0, 1, 2].map(|_| rng.range(-4.0, 4.0));
                let (a, b) = (scene.eval(p), eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[]));
                assert!(close(a, b) || (a - b).abs() < 1e-9, "{src}\nat {p:?}: scene {a}, formula {b}");
            }
        }
    }
}

/// A leaf is on a union path when every operator above it is a sharp
/// union (a tile's field over such leaves is their least value), and on a
/// comb when it hangs off the left spine of union-style operators (their
/// pruned tree is a chain): the views pass relies on both to let each ray
/// evaluate only its own.
#[test]
fn union_paths_mark_the_leaves_under_sharp_unions_only() {
    use crate::scene::Blend;
    let mut b = Builder::default();
    let ball = |b: &mut Builder, x: f64| b.primitive(Primitive::new(Shape::Sphere { radius: 0.2 }).translated([x, 0.0, 0.0]));
    let [p0, p1, p2, p3, p4, p5] = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0].map(|x| ball(&mut b, x));
    let smooth = b.operator(Operator::smooth(OpKind::Union, Blend { beta: 0.1, range: 0.2 }), p1, p2);
    let cut = b.operator(Operator::INTERSECTION, p3, p4);
    let sharp = b.operator(Operator::UNION, p0, smooth);
    let right = b.operator(Operator::UNION, cut, p5);
    let root = b.operator(Operator::UNION, sharp, right);
    let scene = b.finish(root).unwrap();
    let lin = Linear::new(&scene).unwrap();
    // Union paths: p0 and p5 only. Combs: not p3, p4 (under an
    // intersection) nor p5 (under the root's right operand); the smooth
    // union of p1 and p2 is the larger operand of the union with p0, so it
    // goes left and starts the root's left spine: p0, p1, p2 are on it.
    for &k in &lin.primitives {
        let node = lin.order[k as usize];
        assert_eq!(lin.on_union_path(k), [p0, p5].contains(&node), "scene node {node}: union path");
        assert_eq!(lin.on_comb(k), [p0, p1, p2].contains(&node), "scene node {node}: comb");
    }
    // A left comb of compact smooth unions: every leaf is on it, none on a
    // union path.
    let mut b = Builder::default();
    let items: Vec<_> = (0..6).map(|i| ball(&mut b, i as f64)).collect();
    let root = b.fold(Operator::smooth(OpKind::Union, Blend { beta: 0.1, range: 0.2 }), &items);
    let lin = Linear::new(&b.finish(root).unwrap()).unwrap();
    assert!(lin.primitives.iter().all(|&k| lin.on_comb(k) && !lin.on_union_path(k)));
    // A lone primitive is its own union.
    let mut b = Builder::default();
    let only = ball(&mut b, 0.0);
    let lin = Linear::new(&b.finish(only).unwrap()).unwrap();
    assert!(lin.on_union_path(0));
}

/// The f32 rows of `params` evaluate each primitive as the GPU will:
/// q = M·(p, 1), then s · f_local(q) with the parameters of the rows.
#[test]
fn params_rows_reproduce_each_primitive() {
    let mut rng = Rng::new(17);
    let mut b = Builder::default();
    let prims: Vec<_> = (0..8).map(|k| b.primitive(scene_common::primitive_of_kind(&mut rng, k, [0.3, -0.2, 0.1], 1.0))).collect();
    let root = b.fold(Operator::UNION, &prims);
    let scene = b.finish(root).unwrap();
    let lin = Linear::new(&scene).unwrap();
    for &k in &lin.primitives {
        let word = lin.nodes[k as usize];
        // The type field's top bits are a leaf's union-path and comb flags
        // (the first set for all here).
        assert_ne!(word[0] & crate::scene::linear::NODE_UNION_PATH_BIT, 0);
        let ty = (word[0] >> 22) & 0x3f;
        let rows = &lin.params[word[1] as usize..];
        let Node::Primitive(prim) = &scene.nodes()[lin.order[k as usize]] else { unreachable!() };
        for _ in 0..50 {
            let p = [0, 1, 2].map(|_| rng.range(-3.0, 3.0));
            let gpu = scene_common::eval_rows(ty, rows, p);
            let cpu = prim.distance(p);
            assert!((gpu - cpu).abs() < 2e-5 * (1.0 + cpu.abs()), "type {ty}: rows {gpu} vs {cpu}");
        }
    }
}

/// Node words: flags, type, parent (the root's is n), fast ancestor,
/// offsets, primitive index.
#[test]
fn node_words_follow_the_fixed_layout() {
    let mut rng = Rng::new(3);
    let scene = random_tree(&mut rng, 30, TreeShape::Random, 0.5, false);
    let lin = Linear::new(&scene).unwrap();
    let n = lin.len() as u32;
    let mut next_param = 0;
    for (k, w) in lin.nodes.iter().enumerate() {
        let node = &scene.nodes()[lin.order[k]];
        assert_eq!(w[0] >> 31 == 1, matches!(node, Node::Primitive(_)));
        assert_eq!((w[0] >> 30) & 1 == 1, lin.is_left[k]);
        assert_eq!((w[0] >> 22) & 0xff, crate::scene::linear::type_code(node));
        assert_eq!(w[0] & 0x3f_ffff, lin.parent[k]);
        assert_eq!(w[1], next_param);
        assert_eq!(w[2], lin.fast[k]);
        // A primitive's index among the primitives (its balls'), else 0.
        let prim = lin.primitives.iter().position(|&q| q == k as u32);
        assert_eq!(w[3], prim.unwrap_or(0) as u32);
        assert!(w[2] >= lin.parent[k]);
        next_param += match node {
            Node::Primitive(p) => crate::scene::linear::primitive_rows(p).len() as u32,
            Node::Operator { .. } | Node::Unary { .. } => 1,
        };
        if let Node::Operator { .. } = node {
            let [l, r] = lin.children[k];
            assert!(l < r && r < k as u32 && lin.is_left[l as usize] && !lin.is_left[r as usize]);
        }
    }
    assert_eq!(lin.parent[n as usize - 1], n);
    assert_eq!(lin.fast[n as usize - 1], n);
    assert_eq!(lin.params.len() as u32, next_param);
    assert_eq!(lin.abv.len(), 4 * lin.primitives.len());
}

/// The compact forms check β and r_o like a scene file does.
#[test]
fn compact_forms_refuse_a_discontinuous_range() {
    let e = Formula::compile("<f>", "compact_union(sphere(1), box(1, 1, 1), 0.6, 0.6)").unwrap_err().to_string();
    assert!(e.contains("r_o must be at least 7/6 of beta (0.7), got 0.6: below it the compact blend is discontinuous"), "{e}");
    let e = Formula::compile("<f>", "compact_subtract(sphere(1), box(1, 1, 1), 0)").unwrap_err().to_string();
    assert!(e.contains("the blend range beta must be positive, got 0"), "{e}");
    let e = Formula::compile("<f>", "compact_intersect(sphere(1), box(1, 1, 1))").unwrap_err().to_string();
    assert!(e.contains("wrong number of arguments to 'compact_intersect': expected 3 or 4, found 2"), "{e}");
    // The default range is 2β: the same field as giving it.
    let a = Formula::compile("<f>", "compact_union(sphere(1), translate(1.5, 0, 0, sphere(1)), 0.5)").unwrap();
    let b = Formula::compile("<f>", "compact_union(sphere(1), translate(1.5, 0, 0, sphere(1)), 0.5, 1)").unwrap();
    for x in [0.5, 0.75, 1.0, 2.0] {
        let p = [x, 0.3, 0.1, 0.0];
        assert_eq!(eval_scalar(&a.ir, p, &[]), eval_scalar(&b.ir, p, &[]));
    }
}

/// Chains of unary nodes are laid out folded (`scene/fold.rs`): the GPU
/// tree is shorter, the sparse traversal over it gives the scene's values
/// (up to the rounding of the merged parameters), and errors still name
/// the scene's own nodes.
#[test]
fn unary_chains_are_laid_out_folded_with_the_scene_values_and_names() {
    use crate::scene::Unary;
    let mut b = Builder::default();
    let mut s = b.primitive(Primitive::new(Shape::Sphere { radius: 0.5 }));
    for _ in 0..1000 {
        s = b.unary(Unary::Offset { distance: 0.0002 }, s);
    }
    s = b.unary(Unary::Shell { thickness: 0.1 }, s);
    for _ in 0..100 {
        s = b.unary(Unary::Offset { distance: 0.001 }, s);
    }
    let c = b.primitive(Primitive::new(Shape::Box { half: [0.3, 0.3, 0.3] }).translated([0.6, 0.0, 0.0]));
    let c = b.unary(Unary::Offset { distance: 0.0 }, c);
    let root = b.operator(Operator::UNION, s, c);
    let scene = b.finish(root).unwrap();
    let lin = Linear::new(&scene).unwrap();
    // The sphere, one offset of 0.2, one shell of 0.3, the box, the union.
    assert_eq!(lin.len(), 5);
    assert_eq!(lin.order, [0, 1000, 1101, 1102, 1104]);
    let mut rng = Rng::new(7);
    for _ in 0..200 {
        let p = [rng.range(-1.5, 1.5), rng.range(-1.5, 1.5), rng.range(-1.5, 1.5)];
        let active = sparse::active_at(&lin, p);
        let mut mask = vec![false; scene.len()];
        for &k in &active {
            mask[lin.order[k as usize]] = true;
        }
        let t = sparse::traverse(&lin, &scene, p, &active, Ancestors::Fast).unwrap();
        match (t.value, scene.eval_masked(p, &mask)) {
            (Some(v), Some(w)) => assert!((v - w).abs() < 1e-9, "{v} vs {w} at {p:?}"),
            (v, w) => assert_eq!(v.is_some(), w.is_some(), "at {p:?}"),
        }
    }
    // 32 differences nested on their right above three folded offsets of
    // 0: the stack error names the scene's node, not the folded tree's.
    let mut b = Builder::default();
    let mut acc = b.primitive(Primitive::new(Shape::Sphere { radius: 1.0 }));
    for _ in 0..3 {
        acc = b.unary(Unary::Offset { distance: 0.0 }, acc);
    }
    for _ in 0..32 {
        let l = b.primitive(Primitive::new(Shape::Sphere { radius: 1.0 }));
        acc = b.operator(Operator::DIFFERENCE, l, acc);
    }
    let e = Linear::new(&b.finish(acc).unwrap()).unwrap_err().to_string();
    assert!(e.starts_with("nodes[67]: evaluating it needs a stack of 33 values"), "{e}");
}
