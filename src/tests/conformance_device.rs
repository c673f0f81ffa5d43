//! Conformance of the generated WGSL on the device (Mesa lavapipe here):
//! the interval (IA) and reduced affine (RAA) evaluators of every operation,
//! the Knoll surfaces and random expression trees are run by the `eval`
//! kernel on thousands of boxes — one dispatch per formula and algebra —
//! and every box's enclosure is checked against f64 samples of the strict
//! scalar function (see `conformance/oracle.rs` for the sampling and the
//! f32 rounding margin). Strict emptiness is checked for every operation.
//!
//! The checks are the suite of `conformance/suite.rs`, the one
//! `src/tests/conformance.rs` runs on the CPU reference. One device is shared by
//! every test.

#[path = "conformance/harness.rs"]
mod harness;
#[path = "conformance/segments.rs"]
mod segments;

use harness::*;
use segments::{check_slopes, run_segments, segment_shader, slope_shader};
use crate::ir::Domain;
use crate::gpu::eval::eval_boxes;
use crate::gpu::Gpu;
use crate::ir::Ir;
use std::sync::LazyLock;

static GPU: LazyLock<Gpu> = LazyLock::new(|| Gpu::new().unwrap_or_else(|e| panic!("the device conformance tests need a GPU or lavapipe: {e}")));

/// The generated WGSL evaluators run by the eval kernel.
struct Device;

impl Backend for Device {
    fn name(&self) -> &'static str {
        "device"
    }
    fn precision(&self) -> Precision {
        Precision::F32
    }
    fn eval(&self, ir: &Ir, domain: Domain, boxes: &[Box8], params: &[f32]) -> Vec<[f64; 2]> {
        let r = eval_boxes(&GPU, ir, domain, boxes, params).unwrap_or_else(|e| panic!("eval_boxes failed for {domain:?}: {e}"));
        assert_eq!(r.len(), boxes.len());
        r.into_iter().map(|[lo, hi]| [f64::from(lo), f64::from(hi)]).collect()
    }
    fn eval_segments(&self, ir: &Ir, domain: Domain, segs: &[Seg], params: &[f32]) -> Vec<[f64; 2]> {
        run_segments(&GPU, &segment_shader(&segment_field(ir, domain), domain), segs, params, None).unwrap_or_else(|e| panic!("segment kernel failed for {domain:?}: {e}"))
    }
}

/// The segment kernel (`conformance/segments.rs`) over the generated
/// evaluator of `ir`.
fn segment_field(ir: &Ir, domain: Domain) -> String {
    let (ty, call) = match domain {
        Domain::Interval => ("vec2<f32>", "ia_range(eval_ia(x, y, z, t))"),
        _ => ("vec3<f32>", "ra_range(eval_ra(x, y, z, t))"),
    };
    format!(
        "{}\n{}\nfn seg_field(x: {ty}, y: {ty}, z: {ty}, t: {ty}) -> vec2<f32> {{ return {call}; }}",
        crate::codegen::libraries(&[domain]),
        crate::field::compiled::emit_evaluator(ir, domain)
    )
}

/// The slope enclosures of the generated `evald_*` (the ray direction an
/// exact f32: its first terms are `{p}_scale` products) hold the f64 slope
/// of every Knoll surface, every operation and random trees along random
/// ray segments, in IA and RAA.
#[test]
fn slope_enclosures_hold_the_slope_along_ray_segments() {
    let mut cases = op_cases();
    cases.extend(knoll_cases());
    cases.extend(random_cases(23, 20));
    check_slopes(&cases, 200, 24, &|case, domain, segs| {
        let (ty, p) = match domain {
            Domain::Interval => ("vec2<f32>", "ia"),
            _ => ("vec3<f32>", "ra"),
        };
        let field = format!(
            "{}\n{}\n{}\nfn seg_slope(x: {ty}, y: {ty}, z: {ty}, t: {ty}, dir: vec3<f32>) -> vec2<f32> {{ return evald_{p}(x, y, z, t, dir.x, dir.y, dir.z).zw; }}",
            crate::codegen::libraries(&[Domain::Scalar, domain]),
            crate::field::compiled::derivative::library(domain),
            crate::field::compiled::derivative::emit_evaluator_d(&case.ir, domain)
        );
        run_segments(&GPU, &slope_shader(&field, domain), segs, &case.params, None).unwrap_or_else(|e| panic!("slope kernel failed for {} {domain:?}: {e}", case.name))
    });
}

/// A division by a literal is generated as the product with its
/// reciprocal, worked out on the host in the device's f32 steps
/// (`codegen::divide_by_literal`), where the library's division also
/// carries its divisor-with-zero cases. Its enclosures are the library's,
/// bit for bit: the same formula with the divisor given as a parameter
/// (which takes `ia_div` / `ra_div`) on 3,000 boxes, for divisors exact in
/// f32 (an inexact literal is its enclosing interval, a parameter its
/// nearest f32; `div-literal` and the next cases of the operation suite
/// check those enclosures against f64). Boxes where either
/// overflows are left out: there lavapipe folds `inf * 0` with a constant
/// 0 (an exact reciprocal's error term) to 0, and a literal gave `[inf,
/// inf]` where a parameter gives the whole line, before this too.
#[test]
fn a_division_by_a_literal_is_the_librarys_division() {
    let mut rng = Rng::new(41);
    let boxes = random_boxes(&mut rng, 3000);
    for (src, k) in [("(x*y - z) / 0.25", 0.25f32), ("(x + y) / -3", -3.0), ("x*x / 1024", 1024.0), ("(y - 1) / 0.375", 0.375)] {
        let literal = Case::new(src, src);
        let param = Case::new(src, &src.replace(&format!("/ {k}"), "/ k")).with_params(&[k]);
        assert_ne!(literal.source, param.source);
        for domain in [Domain::Interval, Domain::Affine] {
            let a = eval_boxes(&GPU, &literal.ir, domain, &boxes, &[]).unwrap();
            let b = eval_boxes(&GPU, &param.ir, domain, &boxes, &param.params).unwrap();
            let finite = |e: &[f32; 2]| e[0].is_finite() && e[1].is_finite();
            let compared: Vec<_> = a.iter().zip(&b).zip(&boxes).filter(|((p, q), _)| finite(p) && finite(q)).collect();
            assert!(compared.len() > 1500, "{src} {domain:?}: {} boxes compared", compared.len());
            let differ: Vec<_> = compared.iter().filter(|((p, q), _)| p != q).take(3).collect();
            assert!(differ.is_empty(), "{src} {domain:?}: {differ:?}");
        }
    }
}

// The checks both backends run (`conformance/suite.rs`); the device checks
// fewer random trees, each on more boxes (one dispatch per tree and algebra).
conformance_suite!(Device, Budget { trees: 80, boxes_per_tree: 300, segment_trees: 40 });

/// Measures the device's f32 library functions against f64 (20 000 points
/// per function and range, one dispatch each) and prints the largest
/// absolute / relative error: the evidence behind the paddings of
/// `interval.wgsl` (which are about twice these on lavapipe). Asserted only
/// loosely; the conformance tests above check that the padding suffices.
#[test]
fn library_function_accuracy() {
    type F = fn(f64) -> f64;
    let table: &[(&str, &str, f64, f64, bool, F)] = &[
        ("sin", "sin(x)", -10.0, 10.0, false, f64::sin),
        ("sin", "sin(x)", -1e6, 1e6, false, f64::sin),
        ("cos", "cos(x)", -1e6, 1e6, false, f64::cos),
        ("tan", "tan(x)", -1.5, 1.5, false, f64::tan),
        ("tan near pole", "tan(x)", 1.5707863, 1.5708063, false, f64::tan),
        ("atan", "atan(x)", -10.0, 10.0, false, f64::atan),
        ("atan", "atan(x)", 10.0, 1e30, true, f64::atan),
        ("exp", "exp(x)", -87.0, 88.0, false, f64::exp),
        ("exp", "exp(x)", -1.0, 1.0, false, f64::exp),
        ("log", "log(x)", 1e-37, 1e38, true, f64::ln),
        ("log", "log(x)", 0.5, 2.0, false, f64::ln),
        ("sinh", "sinh(x)", -88.0, 88.0, false, f64::sinh),
        ("sinh", "sinh(x)", -1e-3, 1e-3, false, f64::sinh),
        ("cosh", "cosh(x)", -88.0, 88.0, false, f64::cosh),
        ("tanh", "tanh(x)", -10.0, 10.0, false, f64::tanh),
        ("sqrt", "sqrt(x)", 0.0, 100.0, false, f64::sqrt),
        ("1/x", "1/x", 1e-6, 1e6, true, |x| 1.0 / x),
        ("x^1.7", "x^1.7", 1e-15, 1e20, true, |x| x.powf(1.7)),
        ("x^-2.5", "x^-2.5", 1e-15, 1e15, true, |x| x.powf(-2.5)),
    ];
    let mut rng = Rng::new(99);
    let mut report = String::from("\nf32 library functions on the device vs f64 (max over 20000 points)\n");
    for &(name, src, lo, hi, log_spaced, f) in table {
        let case = Case::new(name, src);
        let xs: Vec<f32> = (0..20000).map(|_| (if log_spaced { rng.log_range(lo, hi) } else { rng.range(lo, hi) }) as f32).collect();
        let boxes: Vec<Box8> = xs.iter().map(|&x| [x, x, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]).collect();
        let r = eval_boxes(&GPU, &case.ir, Domain::Scalar, &boxes, &[]).expect("scalar eval");
        let (mut abs_err, mut rel_err) = (0.0f64, 0.0f64);
        for (&x, v) in xs.iter().zip(&r) {
            let exact = f(f64::from(x));
            let d = (f64::from(v[0]) - exact).abs();
            // Results in the subnormal range are flushed to 0 by lavapipe.
            if d.is_finite() && exact.abs() > f64::from(f32::MIN_POSITIVE) {
                abs_err = abs_err.max(d);
                rel_err = rel_err.max(d / exact.abs());
            }
        }
        report.push_str(&format!("  {name:<14} x in [{lo:e}, {hi:e}]: abs {abs_err:.2e}, rel {rel_err:.2e}\n"));
        assert!(rel_err < 1e-3 || abs_err < 1e-5, "{name}: the device's {src} is far off (abs {abs_err:e}, rel {rel_err:e})");
    }
    eprintln!("{report}");
}
