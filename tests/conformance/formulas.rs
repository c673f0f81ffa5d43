//! Formulas of the conformance suites: one per operation, the 16 Knoll et
//! al. surfaces, random expression trees and the emptiness cases.

use super::{Case, Rng};

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
];

/// The 16 Knoll et al. surfaces of /work/shared/knoll-surfaces.txt: (name,
/// formula, box x0 x1 y0 y1 z0 z1).
pub const KNOLL: &[(&str, &str, [f64; 6])] = &[
    ("sphere", "x^2 + y^2 + z^2 - 1", [-1.5, 1.5, -1.5, 1.5, -1.5, 1.5]),
    ("steiner", "x^2*y^2 + y^2*z^2 + z^2*x^2 - x*y*z", [-1.0, 1.0, -1.0, 1.0, -1.0, 1.0]),
    ("mitchell", "4*(x^4 + (y^2 + z^2)^2) + 17*x^2*(y^2 + z^2) - 20*(x^2 + y^2 + z^2) + 17", [-2.5, 2.5, -2.5, 2.5, -2.5, 2.5]),
    ("teardrop", "x^4 - x^3 + y^2 + z^2", [-0.25, 1.25, -0.5, 0.5, -0.5, 0.5]),
    ("4-bretzel", "((x^2 + y^2)^3 - 4*x^2*y^2)^2 + z^2 - 0.0005", [-1.2, 1.2, -1.2, 1.2, -0.1, 0.1]),
    ("klein bottle", "(x^2 + y^2 + z^2 + 2*y - 1)*((x^2 + y^2 + z^2 - 2*y - 1)^2 - 8*z^2) + 16*x*z*(x^2 + y^2 + z^2 - 2*y - 1)", [-3.0, 3.0, -3.1, 3.1, -4.0, 4.0]),
    ("tangle", "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8", [-3.0, 3.0, -3.0, 3.0, -3.0, 3.0]),
    ("decocube", "((x^2 + y^2 - 0.64)^2 + (z^2 - 1)^2)*((y^2 + z^2 - 0.64)^2 + (x^2 - 1)^2)*((z^2 + x^2 - 0.64)^2 + (y^2 - 1)^2) - 0.04", [-1.5, 1.5, -1.5, 1.5, -1.5, 1.5]),
    ("barth sextic", "4*(1.618033988749895^2*x^2 - y^2)*(1.618033988749895^2*y^2 - z^2)*(1.618033988749895^2*z^2 - x^2) - (1 + 2*1.618033988749895)*(x^2 + y^2 + z^2 - 1)^2", [-2.0, 2.0, -2.0, 2.0, -2.0, 2.0]),
    ("barth decic", "8*(x^2 - 1.618033988749895^4*y^2)*(y^2 - 1.618033988749895^4*z^2)*(z^2 - 1.618033988749895^4*x^2)*(x^4 + y^4 + z^4 - 2*x^2*y^2 - 2*x^2*z^2 - 2*y^2*z^2) + (3 + 5*1.618033988749895)*(x^2 + y^2 + z^2 - 1)^2*(x^2 + y^2 + z^2 - (2 - 1.618033988749895))^2", [-2.0, 2.0, -2.0, 2.0, -2.0, 2.0]),
    ("superquadric", "x^200 + y^200 + z^200 - 1", [-1.5, 1.5, -1.5, 1.5, -1.5, 1.5]),
    ("icos.csg", "max(max(max(max(max(max(max(max(max(max(abs(0.5773502691896258*(x+y+z)), abs(0.5773502691896258*(x+y-z))), abs(0.5773502691896258*(x-y+z))), abs(0.5773502691896258*(-x+y+z))), abs(0.35682208977308993*y+0.9341723589627158*z)), abs(0.35682208977308993*y-0.9341723589627158*z)), abs(0.9341723589627158*x+0.35682208977308993*z)), abs(0.9341723589627158*x-0.35682208977308993*z)), abs(0.35682208977308993*x+0.9341723589627158*y)), abs(0.35682208977308993*x-0.9341723589627158*y)) - 1, 1.1025 - (x^2 + y^2 + z^2))", [-1.4, 1.4, -1.4, 1.4, -1.4, 1.4]),
    ("sq.csg", "max(x^8 + y^8 + z^8 - 1, -min(min(y^2 + z^2 - 0.25, x^2 + z^2 - 0.25), x^2 + y^2 - 0.25))", [-1.5, 1.5, -1.5, 1.5, -1.5, 1.5]),
    ("sin.blob", "x^2 + y^2 + z^2 + sin(4*x + t) + sin(4*y + t) + sin(4*z + t) - 1", [-2.0, 2.0, -2.0, 2.0, -2.0, 2.0]),
    ("cloth", "z - sin(3*sqrt(x^2 + y^2 + 0.000001))/(3*sqrt(x^2 + y^2 + 0.000001))", [-4.0, 4.0, -4.0, 4.0, -0.5, 1.2]),
    ("water", "z - 0.1*sin(4*x + t)*cos(3*y + 0.7*t) - 0.05*sin(7*x - 5*y + 1.3*t)", [-4.0, 4.0, -4.0, 4.0, -0.5, 0.5]),
];

/// The operation cases.
pub fn op_cases() -> Vec<Case> {
    OPS.iter().map(|(n, s)| if *n == "param" { Case::new(n, s).with_params(&[1.25]) } else { Case::new(n, s) }).collect()
}

/// The Knoll cases.
pub fn knoll_cases() -> Vec<Case> {
    KNOLL.iter().map(|(n, s, _)| Case::new(n, s)).collect()
}

/// The domain box of a Knoll case.
pub fn knoll_box(name: &str) -> [f64; 6] {
    KNOLL.iter().find(|k| k.0 == name).map(|k| k.2).unwrap_or([-2.0, 2.0, -2.0, 2.0, -2.0, 2.0])
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
