//! Checks of the distance-field language on the CPU shared by the SDF tests:
//! a formula, its f64 value at a point, and a table of expected values.

use crate::Formula;

pub(super) fn f(src: &str) -> Formula {
    Formula::compile("<test>", src).unwrap_or_else(|e| panic!("{src}: {e}"))
}

pub(super) fn at(formula: &Formula, p: [f64; 3]) -> f64 {
    crate::reference::eval_scalar(&formula.ir, [p[0], p[1], p[2], 0.0], &[])
}

pub(super) fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * (1.0 + b.abs())
}

#[track_caller]
pub(super) fn check(src: &str, cases: &[([f64; 3], f64)]) {
    let g = f(src);
    for &(p, want) in cases {
        let got = at(&g, p);
        assert!(close(got, want), "{src} at {p:?}: {got}, expected {want}");
    }
}
