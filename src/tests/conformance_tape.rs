//! Conformance of the tape field source on the device: the same suite as
//! `src/tests/conformance_device.rs` (every operation, the Knoll surfaces,
//! random trees, on boxes and on ray segments lifted as the render kernel
//! lifts them, and strict emptiness), with every formula flattened into a
//! tape and run by the fixed interpreter (`templates/fields/tape.wgsl`)
//! instead of generated code. Each formula is a buffer; the interpreter
//! kernel is the same for every formula of a domain.

#[path = "conformance/harness.rs"]
mod harness;
#[path = "conformance/segments.rs"]
mod segments;

use harness::*;
use segments::{check_slopes, run_segments, segment_shader, slope_shader};
use crate::ir::Domain;
use crate::field::TapeData;
use crate::gpu::eval::eval_boxes_tape;
use crate::gpu::Gpu;
use crate::ir::Ir;
use std::sync::LazyLock;

static GPU: LazyLock<Gpu> = LazyLock::new(|| Gpu::new().unwrap_or_else(|e| panic!("the tape conformance tests need a GPU or lavapipe: {e}")));

/// The tape interpreter run by the eval kernel.
struct Tape;

fn tape(ir: &Ir) -> TapeData {
    TapeData::new(ir).unwrap_or_else(|e| panic!("the conformance formulas are tapes: {e}"))
}

impl Backend for Tape {
    fn name(&self) -> &'static str {
        "tape"
    }
    fn precision(&self) -> Precision {
        Precision::F32
    }
    fn eval(&self, ir: &Ir, domain: Domain, boxes: &[Box8], params: &[f32]) -> Vec<[f64; 2]> {
        let r = eval_boxes_tape(&GPU, &tape(ir), domain, boxes, params).unwrap_or_else(|e| panic!("eval_boxes_tape failed for {domain:?}: {e}"));
        assert_eq!(r.len(), boxes.len());
        r.into_iter().map(|[lo, hi]| [f64::from(lo), f64::from(hi)]).collect()
    }
    fn eval_segments(&self, ir: &Ir, domain: Domain, segs: &[Seg], params: &[f32]) -> Vec<[f64; 2]> {
        run_segments(&GPU, &segment_shader(&segment_field(domain), domain), segs, params, Some(&tape(ir))).unwrap_or_else(|e| panic!("segment kernel failed for {domain:?}: {e}"))
    }
}

/// The segment kernel (`conformance/segments.rs`) over the tape
/// interpreter, lifted as the render kernel lifts a ray segment.
fn segment_field(domain: Domain) -> String {
    let (ty, surf) = match domain {
        Domain::Interval => ("vec2<f32>", "surf_ia"),
        _ => ("vec3<f32>", "surf_ra"),
    };
    format!("{}\nfn seg_field(x: {ty}, y: {ty}, z: {ty}, t: {ty}) -> vec2<f32> {{ return {surf}(x, y, z, t); }}", tape_interpreter(domain))
}

/// The tape interpreter with every operation group, and what it needs.
fn tape_interpreter(domain: Domain) -> String {
    format!(
        "var<private> g_field_work: u32;\n{}{}\n{}",
        crate::codegen::libraries(&[Domain::Scalar, domain]),
        crate::field::compiled::derivative::library(domain),
        crate::field::tape::wgsl::interpreter(domain, crate::field::tape::features::ALL)
    )
}

/// The tape's slope enclosures (its derivative program, the ray direction
/// an exact f32) hold the f64 slope along random ray segments, as the
/// generated code's do (`src/tests/conformance_device.rs`).
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
        let field = format!("{}\nfn seg_slope(x: {ty}, y: {ty}, z: {ty}, t: {ty}, dir: vec3<f32>) -> vec2<f32> {{ return evald_{p}(x, y, z, t, dir.x, dir.y, dir.z).zw; }}", tape_interpreter(domain));
        run_segments(&GPU, &slope_shader(&field, domain), segs, &case.params, Some(&tape(&case.ir))).unwrap_or_else(|e| panic!("slope kernel failed for {} {domain:?}: {e}", case.name))
    });
}

// The checks every backend runs (`conformance/suite.rs`), with the device's budget.
conformance_suite!(Tape, Budget { trees: 80, boxes_per_tree: 300, segment_trees: 40 });
