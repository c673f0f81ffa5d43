//! Conformance of the tape field source on the device: the same suite as
//! `tests/conformance_device.rs` (every operation, the Knoll surfaces,
//! random trees, on boxes and on ray segments lifted as the render kernel
//! lifts them, and strict emptiness), with every formula flattened into a
//! tape and run by the fixed interpreter (`templates/fields/tape.wgsl`)
//! instead of generated code. Each formula is a buffer; the interpreter
//! kernel is the same for every formula of a domain.

#[path = "conformance/harness.rs"]
mod harness;

use harness::*;
use isotrace::codegen::{self, Domain, TapeData};
use isotrace::gpu::eval::eval_boxes_tape;
use isotrace::gpu::Gpu;
use isotrace::ir::Ir;
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
        run_segments(&tape(ir), domain, segs, params).unwrap_or_else(|e| panic!("segment kernel failed for {domain:?}: {e}"))
    }
}

/// `cell_range(o, dir, s0, s1)` over the tape, lifted as the render kernel
/// lifts a ray segment (`codegen::compiled::enclosures`), once per segment.
fn segment_shader(domain: Domain) -> String {
    let lib = format!("{}{}", codegen::libraries(&[Domain::Scalar, domain]), codegen::derivative::library(domain));
    let interp = codegen::tape_field::interpreter(domain);
    let body = match domain {
        Domain::Interval => "let a = o + dir * s0;\n    let b = o + dir * s1;\n    let lo = min(a, b);\n    let hi = max(a, b);\n    \
            return surf_ia(vec2<f32>(lo.x, hi.x), vec2<f32>(lo.y, hi.y), vec2<f32>(lo.z, hi.z), ia_const(U.time));",
        _ => "let sc = 0.5 * (s0 + s1);\n    let sr = 0.5 * (s1 - s0);\n    let c = o + dir * sc;\n    let r = dir * sr;\n    \
            return surf_ra(vec3<f32>(c.x, r.x, 0.0), vec3<f32>(c.y, r.y, 0.0), vec3<f32>(c.z, r.z, 0.0), ra_const(U.time));",
    };
    format!(
        "struct Uniforms {{ inf: f32, time: f32, count: u32, pad: u32, params: array<vec4<f32>, 16> }}
@group(0) @binding(0) var<uniform> U: Uniforms;
@group(0) @binding(1) var<storage, read> segs: array<f32>;
@group(0) @binding(2) var<storage, read_write> results: array<vec2<f32>>;
fn iso_inf() -> f32 {{ return U.inf; }}
fn iso_param(i: u32) -> f32 {{ return U.params[i / 4u][i % 4u]; }}
var<private> g_field_work: u32;
{lib}
{interp}
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

/// Runs [`segment_shader`] over `segs` with the tape bound, in one dispatch.
fn run_segments(t: &TapeData, domain: Domain, segs: &[Seg], params: &[f32]) -> Result<Vec<[f64; 2]>, String> {
    use wgpu::util::DeviceExt;
    let src = segment_shader(domain);
    isotrace::validate::validate(&src).map_err(|e| e.to_string())?;
    let gpu = &*GPU;
    let pipeline = gpu.pipeline("tape conformance segments", &src).map_err(|e| e.to_string())?;
    let n = segs.len() as u32;
    assert!(n > 0 && n <= 65_535 * 64, "one dispatch of up to 4M segments");
    let mut uniforms = vec![f32::INFINITY.to_bits(), SEG_TIME.to_bits(), n, 0];
    uniforms.extend((0..64).map(|i| params.get(i).copied().unwrap_or(0.0).to_bits()));
    let d = &gpu.device;
    let staging = gpu
        .scoped("segment dispatch", || {
            let init = |label, contents: &[u8], usage| d.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage });
            let ubuf = init("segment uniforms", bytemuck::cast_slice(&uniforms), wgpu::BufferUsages::UNIFORM);
            let sbuf = init("segments", bytemuck::cast_slice(segs), wgpu::BufferUsages::STORAGE);
            let tbuf = init("tape", bytemuck::cast_slice(&t.words), wgpu::BufferUsages::STORAGE);
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
            let field = d.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("tape"),
                layout: &pipeline.get_bind_group_layout(1),
                entries: &[wgpu::BindGroupEntry { binding: 0, resource: tbuf.as_entire_binding() }],
            });
            let mut enc = d.create_command_encoder(&Default::default());
            {
                let mut pass = enc.begin_compute_pass(&Default::default());
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &bind, &[]);
                pass.set_bind_group(1, &field, &[]);
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

// The checks every backend runs (`conformance/suite.rs`), with the device's budget.
conformance_suite!(Tape, Budget { trees: 80, boxes_per_tree: 300, segment_trees: 40 });
