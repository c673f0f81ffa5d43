//! Conformance of the generated WGSL on the device (Mesa lavapipe here):
//! the interval (IA) and reduced affine (RAA) evaluators of every operation,
//! the Knoll surfaces and random expression trees are run by the `eval`
//! kernel on thousands of boxes — one dispatch per formula and algebra —
//! and every box's enclosure is checked against f64 samples of the strict
//! scalar function (see `conformance/oracle.rs` for the sampling and the
//! f32 rounding margin). Strict emptiness is checked for every operation.
//!
//! The checks are the suite of `conformance/suite.rs`, the one
//! `tests/conformance.rs` runs on the CPU reference. One device is shared by
//! every test.

#[path = "conformance/harness.rs"]
mod harness;

use harness::*;
use isotrace::codegen::{self, Domain};
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
    fn eval_segments(&self, ir: &Ir, domain: Domain, segs: &[Seg], params: &[f32]) -> Vec<[f64; 2]> {
        run_segments(ir, domain, segs, params).unwrap_or_else(|e| panic!("segment kernel failed for {domain:?}: {e}"))
    }
}

/// A kernel that evaluates `cell_range(o, dir, s0, s1)` — the render
/// kernel's inclusion function, lifted exactly as `codegen::inclusion` lifts
/// a ray segment (IA: its bounding box; RAA: x, y, z = c + r·e1 with the
/// one shared symbol e1) — once per segment. The eval kernel cannot do
/// this: it lifts every box side to an independent form.
fn segment_shader(ir: &Ir, domain: Domain) -> String {
    let lib = codegen::libraries(&[domain]);
    let eval = codegen::emit_evaluator(ir, domain);
    let body = match domain {
        Domain::Interval => "let a = o + dir * s0;\n    let b = o + dir * s1;\n    let lo = min(a, b);\n    let hi = max(a, b);\n    \
            return ia_range(eval_ia(vec2<f32>(lo.x, hi.x), vec2<f32>(lo.y, hi.y), vec2<f32>(lo.z, hi.z), ia_const(U.time)));",
        _ => "let sc = 0.5 * (s0 + s1);\n    let sr = 0.5 * (s1 - s0);\n    let c = o + dir * sc;\n    let r = dir * sr;\n    \
            return ra_range(eval_ra(vec3<f32>(c.x, r.x, 0.0), vec3<f32>(c.y, r.y, 0.0), vec3<f32>(c.z, r.z, 0.0), ra_const(U.time)));",
    };
    format!(
        "struct Uniforms {{ inf: f32, time: f32, count: u32, pad: u32, params: array<vec4<f32>, 16> }}
@group(0) @binding(0) var<uniform> U: Uniforms;
@group(0) @binding(1) var<storage, read> segs: array<f32>;
@group(0) @binding(2) var<storage, read_write> results: array<vec2<f32>>;
fn iso_inf() -> f32 {{ return U.inf; }}
fn iso_param(i: u32) -> f32 {{ return U.params[i / 4u][i % 4u]; }}
{lib}
{eval}
fn cell_range(o: vec3<f32>, dir: vec3<f32>, s0: f32, s1: f32) -> vec2<f32> {{
    {body}
}}
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {{
    let i = gid.x;
    if (i >= U.count) {{ return; }}
    let b = i * 8u;
    results[i] = cell_range(vec3<f32>(segs[b], segs[b + 1u], segs[b + 2u]), vec3<f32>(segs[b + 3u], segs[b + 4u], segs[b + 5u]), segs[b + 6u], segs[b + 7u]);
}}
"
    )
}

/// Runs [`segment_shader`] over `segs` in one dispatch.
fn run_segments(ir: &Ir, domain: Domain, segs: &[Seg], params: &[f32]) -> Result<Vec<[f64; 2]>, String> {
    use wgpu::util::DeviceExt;
    let src = segment_shader(ir, domain);
    isotrace::validate::validate(&src).map_err(|e| e.to_string())?;
    let gpu = &*GPU;
    let pipeline = gpu.pipeline("conformance segments", &src).map_err(|e| e.to_string())?;
    let n = segs.len() as u32;
    assert!(n > 0 && n <= 65_535 * 64, "one dispatch of up to 4M segments");
    let mut uniforms = vec![f32::INFINITY.to_bits(), SEG_TIME.to_bits(), n, 0];
    uniforms.extend((0..64).map(|i| params.get(i).copied().unwrap_or(0.0).to_bits()));
    let d = &gpu.device;
    let staging = gpu
        .scoped("segment dispatch", || {
            let ubuf = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("segment uniforms"),
                contents: bytemuck::cast_slice(&uniforms),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let sbuf = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("segments"),
                contents: bytemuck::cast_slice(segs),
                usage: wgpu::BufferUsages::STORAGE,
            });
            let size = u64::from(n) * 8;
            let obuf = d.create_buffer(&wgpu::BufferDescriptor {
                label: Some("segment results"),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("segments"),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: ubuf.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 1, resource: sbuf.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 2, resource: obuf.as_entire_binding() },
                ],
            });
            let mut enc = d.create_command_encoder(&Default::default());
            {
                let mut pass = enc.begin_compute_pass(&Default::default());
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &bind, &[]);
                pass.dispatch_workgroups(n.div_ceil(64), 1, 1);
            }
            let staging = gpu.read_buffer(&mut enc, &obuf, size);
            gpu.queue.submit([enc.finish()]);
            staging
        })
        .map_err(|e| e.to_string())?;
    let bytes = gpu.map_read(&staging).map_err(|e| e.to_string())?;
    Ok(bytemuck::cast_slice::<u8, [f32; 2]>(&bytes).iter().map(|r| [f64::from(r[0]), f64::from(r[1])]).collect())
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
