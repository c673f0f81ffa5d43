//! Conformance of the CPU reference (`crate::reference`): the inclusion
//! property of `eval_interval` / `eval_affine` for every operation, the
//! Knoll surfaces and random expression trees, strict emptiness (the suite
//! of `conformance/suite.rs`, which `src/tests/conformance_device.rs` runs on
//! the generated WGSL), and the IA-vs-RAA enclosure widths along ray
//! segments (which only the CPU can measure: the device's eval kernel takes
//! boxes, and a box lifts each coordinate to an independent form, so
//! ray-segment RAA — x, y, z affine in one shared symbol — cannot be
//! expressed through it).

#[path = "conformance/harness.rs"]
mod harness;

use harness::*;
use crate::reference::{affine_range, eval_affine, eval_interval};

// The checks both backends run; the CPU affords more random trees.
conformance_suite!(Cpu, Budget { trees: 400, boxes_per_tree: 200, segment_trees: 200 });

/// Mean width of the IA and RAA enclosures of each Knoll surface over
/// random ray segments p + d·[0, L] inside its box, for three lengths L
/// (fractions of the box diagonal). RAA gets x, y, z as forms of one shared
/// symbol e1 — (c, r, 0) — exactly as the render kernel builds them.
#[test]
fn raa_is_tighter_along_ray_segments() {
    let mut rng = Rng::new(15);
    let fractions = [0.25, 1.0 / 16.0, 1.0 / 64.0];
    let mut table = String::from("\nmean enclosure width along random ray segments (CPU reference, 400 segments per cell)\n");
    table.push_str(&format!("{:<14}", "surface"));
    for f in fractions {
        table.push_str(&format!(" | {:>10} {:>10} {:>6}", format!("IA L=d/{}", (1.0 / f) as u32), "RAA", "RAA/IA"));
    }
    table.push('\n');
    let mut checked = Vec::new();
    for case in knoll_cases() {
        let (name, bx) = (case.name.as_str(), case.domain.expect("a catalog case"));
        let params: Vec<f64> = case.params.iter().map(|&p| f64::from(p)).collect();
        let diag = ((bx[1] - bx[0]).powi(2) + (bx[3] - bx[2]).powi(2) + (bx[5] - bx[4]).powi(2)).sqrt();
        table.push_str(&format!("{name:<14}"));
        for f in fractions {
            let (mut ia, mut ra, mut n) = (0.0, 0.0, 0usize);
            for _ in 0..400 {
                let p: [f64; 3] = std::array::from_fn(|i| rng.range(bx[2 * i], bx[2 * i + 1]));
                let d = loop {
                    let d: [f64; 3] = std::array::from_fn(|_| rng.range(-1.0, 1.0));
                    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                    if l > 0.1 && l <= 1.0 {
                        break d.map(|c| c / l);
                    }
                };
                let half = 0.5 * f * diag;
                let c: [f64; 3] = std::array::from_fn(|i| p[i] + d[i] * half);
                let r: [f64; 3] = std::array::from_fn(|i| d[i] * half);
                let t = 0.7;
                let boxes = [[c[0] - r[0].abs(), c[0] + r[0].abs()], [c[1] - r[1].abs(), c[1] + r[1].abs()], [c[2] - r[2].abs(), c[2] + r[2].abs()], [t, t]];
                let forms = [[c[0], r[0], 0.0], [c[1], r[1], 0.0], [c[2], r[2], 0.0], [t, 0.0, 0.0]];
                let a = eval_interval(&case.ir, boxes, &params);
                let b = affine_range(eval_affine(&case.ir, forms, &params));
                let (wa, wb) = (a[1] - a[0], b[1] - b[0]);
                if wa.is_finite() && wb.is_finite() && wa >= 0.0 && wb >= 0.0 {
                    ia += wa;
                    ra += wb;
                    n += 1;
                }
            }
            let (ia, ra) = (ia / n.max(1) as f64, ra / n.max(1) as f64);
            table.push_str(&format!(" | {ia:>10.4e} {ra:>10.4e} {:>6.3}", ra / ia));
            if matches!(name, "barth-sextic" | "mitchell") {
                checked.push((name.to_string(), f, ia, ra));
            }
        }
        table.push('\n');
    }
    eprintln!("{table}");
    for (name, f, ia, ra) in checked {
        assert!(ra <= 1.05 * ia, "{name}, L = d·{f}: RAA mean width {ra:e} is not within 1.05 × IA's {ia:e}");
    }
}
