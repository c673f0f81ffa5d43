//! Formulas of the conformance suites: one per operation, the 16 Knoll et
//! al. surfaces (from the catalog), random expression trees and the
//! emptiness cases.

use super::{Case, Rng};
use crate::catalog;

/// One formula per operation of the language, as (name, source).
pub const OPS: &[(&str, &str)] = &[
    ("neg", "-x"), ("add", "x + y"), ("sub", "x - y"), ("mul", "x * y"), ("div", "x / y"),
    ("sq", "x^2"), ("cube", "x^3"), ("pow5", "x^5"), ("recip", "x^-1"), ("half", "x^0.5"),
    ("real-exp", "x^1.7"), ("neg-real-exp", "x^-2.5"), ("sqrt", "sqrt(x)"), ("exp", "exp(x)"),
    ("log", "log(x)"), ("sin", "sin(x)"), ("cos", "cos(x)"), ("tan", "tan(x)"), ("atan", "atan(x)"),
    ("sinh", "sinh(x)"), ("cosh", "cosh(x)"), ("tanh", "tanh(x)"), ("abs", "abs(x)"),
    ("sign", "sign(x)"), ("floor", "floor(x)"), ("pow", "pow(x, y)"), ("atan2", "atan2(y, x)"),
    ("min", "min(x, y)"), ("max", "max(x, y)"), ("clamp", "clamp(x, y, z)"), ("mix", "mix(x, y, z)"),
    // the same variable twice: dependency must not break inclusion
    ("x*x", "x * x"), ("x-x", "x - x"), ("x/x", "x / x"), ("pow4", "x^4"), ("pow6", "x^6"),
    ("pow7", "x^7"), ("param", "x^2 + y^2 - r^2"), ("time", "x + sin(t)"),
    // division by a literal: the product with its reciprocal, worked out on the host
    ("div-literal", "x / 0.3"), ("div-neg-literal", "(x - y) / -7.1"), ("div-tiny-literal", "y / 3e-20"),
    ("div-huge-literal", "x / 7e25"), ("div-exact-literal", "(x * y) / 0.125"), ("div-subnormal-literal", "x / 1e-40"),
];

/// The operation cases.
pub fn op_cases() -> Vec<Case> {
    OPS.iter().map(|(n, s)| if *n == "param" { Case::new(n, s).with_params(&[1.25]) } else { Case::new(n, s) }).collect()
}

/// The catalog's `knoll` suite (the 16 surfaces of Knoll et al.'s Table
/// 1) as the renderer gets them: each entry's compiled formula, parameter
/// values and box.
pub fn knoll_cases() -> Vec<Case> {
    catalog::suite("knoll").expect("the knoll suite").into_iter().map(catalog_case).collect()
}

/// The built-in entry `name` as a case.
pub fn catalog_case(name: &str) -> Case {
    let e = catalog::lookup(name).unwrap_or_else(|err| panic!("{err}"));
    let f = e.compile().unwrap_or_else(|err| panic!("{name}: {err}"));
    let (params, _) = crate::sema::bind_params(&f.ir, &e.header.params).unwrap_or_else(|d| panic!("{name}: {}", d.message));
    Case { name: e.name.clone(), source: formula_lines(&e.formula), ir: f.ir, params, domain: Some(e.header.bbox) }
}

/// The formula of an `.iso` text on one line, without its header and
/// comments: what a failure message quotes.
fn formula_lines(text: &str) -> String {
    let lines = text.lines().map(|l| l.split('#').next().unwrap_or_default().trim());
    lines.filter(|l| !l.is_empty()).collect::<Vec<_>>().join(" ")
}

/// A random expression over x, y, z, t of depth ≤ `depth`.
pub fn random_expr(rng: &mut Rng, depth: u32) -> String {
    if depth == 0 || rng.chance(0.2) {
        return match rng.below(6) {
            0 => "x".into(),
            1 => "y".into(),
            2 => "z".into(),
            3 => "t".into(),
            4 => format!("{}", rng.below(7) as i32 - 3),
            _ => format!("{:.3}", rng.range(-4.0, 4.0)),
        };
    }
    let sub = |rng: &mut Rng| random_expr(rng, depth - 1);
    match rng.below(30) {
        0 => format!("(-{})", sub(rng)),
        1..=3 => format!("({} + {})", sub(rng), sub(rng)),
        4..=5 => format!("({} - {})", sub(rng), sub(rng)),
        6..=8 => format!("({} * {})", sub(rng), sub(rng)),
        9 => format!("({} / {})", sub(rng), sub(rng)),
        10 => format!("({})^{}", sub(rng), rng.pick(&["2", "3", "4", "5", "-1", "-2", "0.5", "1.7", "-0.5"])),
        11..=22 => {
            let f = rng.pick(&["sqrt", "exp", "log", "sin", "cos", "tan", "atan", "sinh", "cosh", "tanh", "abs", "sign", "floor"]);
            format!("{f}({})", sub(rng))
        }
        23..=27 => {
            let f = rng.pick(&["pow", "atan2", "min", "max"]);
            format!("{f}({}, {})", sub(rng), sub(rng))
        }
        _ => {
            let f = rng.pick(&["clamp", "mix"]);
            format!("{f}({}, {}, {})", sub(rng), sub(rng), sub(rng))
        }
    }
}

/// `n` random formulas that the front end accepts (constant parts that fold
/// to a non-finite value are rejected there and skipped here).
pub fn random_cases(seed: u64, n: usize) -> Vec<Case> {
    let mut rng = Rng::new(seed);
    let mut out = Vec::new();
    while out.len() < n {
        let depth = 2 + rng.below(3) as u32;
        let src = random_expr(&mut rng, depth);
        if let Ok(c) = Case::try_new(&format!("random#{}", out.len()), &src) {
            if !c.ir.variables().is_empty() {
                out.push(c);
            }
        }
    }
    out
}

/// Formulas that are undefined everywhere through one argument of each
/// operation: `u = sqrt(-1 - x^2)` (and log / real-power variants) in every
/// operand position.
pub fn empty_cases() -> Vec<Case> {
    let mut v = Vec::new();
    for u in ["sqrt(-1 - x^2)", "log(-1 - x^2)", "(-1 - x^2)^0.5", "pow(-2 - y^2, x)"] {
        let forms = [
            format!("-{u}"), format!("{u} + x"), format!("x + {u}"), format!("{u} - x"), format!("x - {u}"),
            format!("{u} * x"), format!("0 * {u}"), format!("{u} / x"), format!("x / {u}"), format!("({u})^2"),
            format!("({u})^3"), format!("({u})^5"), format!("({u})^-1"), format!("({u})^0.5"), format!("({u})^1.7"),
            format!("pow({u}, x)"), format!("pow(x, {u})"), format!("atan2({u}, x)"), format!("atan2(x, {u})"),
            format!("min({u}, x)"), format!("max(x, {u})"), format!("clamp({u}, x, y)"), format!("clamp(x, {u}, y)"),
            format!("clamp(x, y, {u})"), format!("mix({u}, x, y)"), format!("mix(x, {u}, y)"), format!("mix(x, y, {u})"),
        ];
        for f in forms {
            v.push(Case::new(&f, &f));
        }
        for g in ["sqrt", "exp", "log", "sin", "cos", "tan", "atan", "sinh", "cosh", "tanh", "abs", "sign", "floor"] {
            let f = format!("{g}({u})");
            v.push(Case::new(&f, &f));
        }
    }
    v
}
