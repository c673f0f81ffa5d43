//! The 16 benchmark surfaces of Knoll et al. (Table 1), as recorded in
//! /work/shared/knoll-surfaces.txt: each compiles, has the expected degree,
//! and every shader generated from it (eval in all three domains, render in
//! both inclusion domains) passes naga validation.

use isotrace::Formula;
use isotrace::codegen::{self, Domain};
use isotrace::validate::validate;

/// (name, formula, polynomial degree or None).
const KNOLL: &[(&str, &str, Option<u32>)] = &[
    ("sphere", "x^2 + y^2 + z^2 - 1", Some(2)),
    ("steiner", "x^2*y^2 + y^2*z^2 + z^2*x^2 - x*y*z", Some(4)),
    ("mitchell", "4*(x^4 + (y^2 + z^2)^2) + 17*x^2*(y^2 + z^2) - 20*(x^2 + y^2 + z^2) + 17", Some(4)),
    ("teardrop", "x^4 - x^3 + y^2 + z^2", Some(4)),
    ("4-bretzel", "((x^2 + y^2)^3 - 4*x^2*y^2)^2 + z^2 - 0.0005", Some(12)),
    ("klein bottle", "(x^2 + y^2 + z^2 + 2*y - 1)*((x^2 + y^2 + z^2 - 2*y - 1)^2 - 8*z^2) + 16*x*z*(x^2 + y^2 + z^2 - 2*y - 1)", Some(6)),
    ("tangle", "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8", Some(4)),
    ("decocube", "((x^2 + y^2 - 0.64)^2 + (z^2 - 1)^2)*((y^2 + z^2 - 0.64)^2 + (x^2 - 1)^2)*((z^2 + x^2 - 0.64)^2 + (y^2 - 1)^2) - 0.04", Some(12)),
    ("barth sextic", "4*(1.618033988749895^2*x^2 - y^2)*(1.618033988749895^2*y^2 - z^2)*(1.618033988749895^2*z^2 - x^2) - (1 + 2*1.618033988749895)*(x^2 + y^2 + z^2 - 1)^2", Some(6)),
    ("barth decic", "8*(x^2 - 1.618033988749895^4*y^2)*(y^2 - 1.618033988749895^4*z^2)*(z^2 - 1.618033988749895^4*x^2)*(x^4 + y^4 + z^4 - 2*x^2*y^2 - 2*x^2*z^2 - 2*y^2*z^2) + (3 + 5*1.618033988749895)*(x^2 + y^2 + z^2 - 1)^2*(x^2 + y^2 + z^2 - (2 - 1.618033988749895))^2", Some(10)),
    ("superquadric", "x^200 + y^200 + z^200 - 1", Some(200)),
    ("icos.csg", "max(max(max(max(max(max(max(max(max(max(abs(0.5773502691896258*(x+y+z)), abs(0.5773502691896258*(x+y-z))), abs(0.5773502691896258*(x-y+z))), abs(0.5773502691896258*(-x+y+z))), abs(0.35682208977308993*y+0.9341723589627158*z)), abs(0.35682208977308993*y-0.9341723589627158*z)), abs(0.9341723589627158*x+0.35682208977308993*z)), abs(0.9341723589627158*x-0.35682208977308993*z)), abs(0.35682208977308993*x+0.9341723589627158*y)), abs(0.35682208977308993*x-0.9341723589627158*y)) - 1, 1.1025 - (x^2 + y^2 + z^2))", None),
    ("sq.csg", "max(x^8 + y^8 + z^8 - 1, -min(min(y^2 + z^2 - 0.25, x^2 + z^2 - 0.25), x^2 + y^2 - 0.25))", None),
    ("sin.blob", "x^2 + y^2 + z^2 + sin(4*x + t) + sin(4*y + t) + sin(4*z + t) - 1", None),
    ("cloth", "z - sin(3*sqrt(x^2 + y^2 + 0.000001))/(3*sqrt(x^2 + y^2 + 0.000001))", None),
    ("water", "z - 0.1*sin(4*x + t)*cos(3*y + 0.7*t) - 0.05*sin(7*x - 5*y + 1.3*t)", None),
];

fn compile(name: &str, src: &str) -> Formula {
    Formula::compile(name, src).unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn all_sixteen_compile_with_their_degrees() {
    assert_eq!(KNOLL.len(), 16);
    for &(name, src, degree) in KNOLL {
        let f = compile(name, src);
        assert_eq!(f.ir.degree(), degree, "{name}");
        assert!(f.ir.params.is_empty(), "{name} has no parameters");
    }
}

#[test]
fn eval_shaders_validate() {
    for &(name, src, _) in KNOLL {
        let f = compile(name, src);
        for d in [Domain::Scalar, Domain::Interval, Domain::Affine] {
            let wgsl = codegen::eval_shader(&f.ir, d);
            if let Err(e) = validate(&wgsl) {
                panic!("{name}, eval shader in {d:?}:\n{e}");
            }
        }
    }
}

#[test]
fn render_shaders_validate() {
    for &(name, src, _) in KNOLL {
        let f = compile(name, src);
        for d in [Domain::Interval, Domain::Affine] {
            let wgsl = codegen::render_shader(&f.ir, d);
            if let Err(e) = validate(&wgsl) {
                panic!("{name}, render shader in {d:?}:\n{e}");
            }
        }
    }
}

#[test]
fn variables() {
    use isotrace::ir::Var;
    for &(name, src, _) in KNOLL {
        let vars = compile(name, src).ir.variables();
        let animated = matches!(name, "sin.blob" | "water");
        let want: &[Var] = if animated { &[Var::X, Var::Y, Var::Z, Var::T] } else { &[Var::X, Var::Y, Var::Z] };
        assert_eq!(vars, want, "{name}");
    }
}
