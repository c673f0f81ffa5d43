//! The 16 benchmark surfaces of Knoll et al. (Table 1), the catalog's
//! `knoll` suite (their formulas and provenance are in `examples/*.iso`,
//! from /work/shared/knoll-surfaces.txt): the suite is the table in its
//! order, each formula compiles to the expected degree, and every shader
//! generated from it (eval in all three domains, render in both inclusion
//! domains) passes naga validation.

use crate::ir::Domain;
use crate::validate::validate;
use crate::{catalog, Formula};

/// Table 1's rows in its order, with the polynomial degree of the formula
/// isotrace uses (None: not a polynomial). The expected value of
/// `catalog::suite("knoll")`, so this is the one place in the tests that
/// spells the names out.
const TABLE_1: [(&str, Option<u32>); 16] = [
    ("sphere", Some(2)),
    ("steiner", Some(4)),
    ("mitchell", Some(4)),
    ("teardrop", Some(4)),
    ("4-bretzel", Some(12)),
    ("klein-bottle", Some(6)),
    ("tangle", Some(4)),
    ("decocube", Some(12)),
    ("barth-sextic", Some(6)),
    ("barth-decic", Some(10)),
    ("superquadric", Some(200)),
    ("icos.csg", None),
    ("sq.csg", None),
    ("sin.blob", None),
    ("cloth", None),
    ("water", None),
];

/// The suite's surfaces, compiled from their catalog entries.
fn knoll() -> Vec<(&'static str, Formula)> {
    let names = catalog::suite("knoll").expect("the knoll suite");
    let compile = |n: &str| catalog::lookup(n).unwrap_or_else(|e| panic!("{e}")).compile().unwrap_or_else(|e| panic!("{n}: {e}"));
    names.into_iter().map(|n| (n, compile(n))).collect()
}

#[test]
fn the_suite_is_table_1_in_order() {
    let names: Vec<&str> = TABLE_1.iter().map(|r| r.0).collect();
    assert_eq!(catalog::suite("knoll").unwrap(), names);
}

#[test]
fn all_sixteen_compile_with_their_degrees() {
    let surfaces = knoll();
    assert_eq!(surfaces.len(), 16);
    for ((name, f), (_, degree)) in surfaces.iter().zip(TABLE_1) {
        assert_eq!(f.ir.degree(), degree, "{name}");
        assert!(f.ir.params.is_empty(), "{name} has no parameters");
    }
}

#[test]
fn eval_shaders_validate() {
    for (name, f) in knoll() {
        for d in [Domain::Scalar, Domain::Interval, Domain::Affine] {
            let wgsl = crate::field::compiled::eval_shader(&f.ir, d);
            if let Err(e) = validate(&wgsl) {
                panic!("{name}, eval shader in {d:?}:\n{e}");
            }
        }
    }
}

#[test]
fn render_shaders_validate() {
    for (name, f) in knoll() {
        for d in [Domain::Interval, Domain::Affine] {
            let wgsl = crate::kernel::render_shader(&f.ir, d);
            if let Err(e) = validate(&wgsl) {
                panic!("{name}, render shader in {d:?}:\n{e}");
            }
        }
    }
}

#[test]
fn variables() {
    use crate::ir::Var;
    for (name, f) in knoll() {
        let vars = f.ir.variables();
        let animated = matches!(name, "sin.blob" | "water");
        let want: &[Var] = if animated { &[Var::X, Var::Y, Var::Z, Var::T] } else { &[Var::X, Var::Y, Var::Z] };
        assert_eq!(vars, want, "{name}");
    }
}
