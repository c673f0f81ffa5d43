//! Conformance of the generated WGSL on the device (Mesa lavapipe here):
//! the interval (IA) and reduced affine (RAA) evaluators of every operation,
//! the Knoll surfaces and random expression trees are run by the `eval`
//! kernel on thousands of boxes — one dispatch per formula and algebra —
//! and every box's enclosure is checked against f64 samples of the strict
//! scalar function (see `conformance/oracle.rs` for the sampling and the
//! f32 rounding margin). Strict emptiness is checked for every operation.
//!
//! One device is shared by every test.

#[path = "conformance/harness.rs"]
mod harness;

use harness::*;
use isotrace::codegen::Domain;
use isotrace::gpu::eval::eval_boxes;
use isotrace::gpu::Gpu;
use isotrace::ir::Ir;
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
}

#[test]
fn every_operation_encloses() {
    check_all(&Device, &op_cases(), &mut |_, rng| random_boxes(rng, 3000), 11);
}

#[test]
fn knoll_surfaces_enclose() {
    check_all(
        &Device,
        &knoll_cases(),
        &mut |c, rng| {
            let mut b = domain_cells(rng, knoll_box(&c.name), 1000);
            b.extend(random_boxes(rng, 500));
            b
        },
        12,
    );
}

#[test]
fn random_trees_enclose() {
    check_all(&Device, &random_cases(13, 80), &mut |_, rng| random_boxes(rng, 300), 13);
}

#[test]
fn emptiness_propagates() {
    check_emptiness(&Device, &empty_cases(), 14);
}

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
