//! The ray-segment kernel of the device conformance tests: it evaluates
//! `cell_range(o, dir, s0, s1)`, the render kernel's inclusion function,
//! lifted exactly as `field::compiled::inclusion` lifts a ray segment (IA: its
//! bounding box; RAA: x, y, z = c + r·e1 with the one shared symbol e1),
//! once per segment. The eval kernel cannot do this: it lifts every box side
//! to an independent form. The field under test is the caller's WGSL; a
//! field kept as data (a tape) binds its texture at `@group(1) @binding(0)`.

use super::{Seg, SEG_TIME};
use crate::ir::Domain;
use crate::gpu::Gpu;

/// The kernel over `field`: WGSL that defines `seg_field(x, y, z, t)` in
/// the domain's representation (`vec2<f32>` intervals for IA, `vec3<f32>`
/// reduced affine forms for RAA) returning the enclosure `[lo, hi]`, and
/// whatever it needs (libraries, evaluators, an interpreter).
pub fn segment_shader(field: &str, domain: Domain) -> String {
    segment_kernel(field, domain, "seg_field(X, Y, Z, T)")
}

/// The same kernel over `seg_slope(x, y, z, t, dir)`, which returns the
/// enclosure of the derivative of f along `dir` (`evald_*`'s slope).
pub fn slope_shader(field: &str, domain: Domain) -> String {
    segment_kernel(field, domain, "seg_slope(X, Y, Z, T, dir)")
}

/// The segment kernel returning `call` on the segment's lifted X, Y, Z, T.
fn segment_kernel(field: &str, domain: Domain, call: &str) -> String {
    let lift = match domain {
        Domain::Interval => "let a = o + dir * s0;\n    let b = o + dir * s1;\n    let lo = min(a, b);\n    let hi = max(a, b);\n    \
            let X = vec2<f32>(lo.x, hi.x);\n    let Y = vec2<f32>(lo.y, hi.y);\n    let Z = vec2<f32>(lo.z, hi.z);\n    let T = ia_const(U.time);",
        _ => "let sc = 0.5 * (s0 + s1);\n    let sr = 0.5 * (s1 - s0);\n    let c = o + dir * sc;\n    let r = dir * sr;\n    \
            let X = vec3<f32>(c.x, r.x, 0.0);\n    let Y = vec3<f32>(c.y, r.y, 0.0);\n    let Z = vec3<f32>(c.z, r.z, 0.0);\n    let T = ra_const(U.time);",
    };
    format!(
        "struct Uniforms {{ inf: f32, time: f32, count: u32, pad: u32, params: array<vec4<f32>, 16> }}
@group(0) @binding(0) var<uniform> U: Uniforms;
@group(0) @binding(1) var<storage, read> segs: array<f32>;
@group(0) @binding(2) var<storage, read_write> results: array<vec2<f32>>;
fn iso_inf() -> f32 {{ return U.inf; }}
fn iso_param(i: u32) -> f32 {{ return U.params[i / 4u][i % 4u]; }}
{field}
fn cell_range(o: vec3<f32>, dir: vec3<f32>, s0: f32, s1: f32) -> vec2<f32> {{
    {lift}
    return {call};
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

/// Validates `src` (a [`segment_shader`]) and runs it over `segs` in one
/// dispatch, with `tape` bound at `@group(1) @binding(0)` (as the texture
/// the interpreter reads) if given.
pub fn run_segments(gpu: &Gpu, src: &str, segs: &[Seg], params: &[f32], tape: Option<&crate::field::TapeData>) -> Result<Vec<[f64; 2]>, String> {
    use wgpu::util::DeviceExt;
    crate::validate::validate(src).map_err(|e| e.to_string())?;
    let pipeline = gpu.pipeline("conformance segments", src, crate::gpu::Author::Isotrace).map_err(|e| e.to_string())?;
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
            let field = tape.map(|t| {
                let (texture, view) = gpu.texture("tape", &t.texels(), wgpu::TextureFormat::Rgba32Uint).expect("the tape fits a texture");
                let group = d.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("field"),
                    layout: &pipeline.get_bind_group_layout(1),
                    entries: &[wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&view) }],
                });
                (group, texture)
            });
            let mut enc = d.create_command_encoder(&Default::default());
            {
                let mut pass = enc.begin_compute_pass(&Default::default());
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &bind, &[]);
                if let Some((f, _)) = &field {
                    pass.set_bind_group(1, f, &[]);
                }
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

/// Checks the slope enclosures `slopes` returns (the derivative of f along
/// each segment's direction over the segment, as `evald_*` computes it for
/// the bisection's monotonicity test and mean-value form) against f64
/// central differences at 16 points inside each of `n` random segments per
/// case (starting within 100 of the origin): the slope there must lie in
/// the enclosure, up to the f32 rounding of its ends. Points where halving
/// the difference step changes the estimate (a kink or jump of f within the
/// step) or where the difference's own rounding could move it (f huge
/// against its change over the step) prove nothing and are skipped, as are
/// enclosures with an unbounded end.
pub fn check_slopes(cases: &[super::Case], n: usize, seed: u64, slopes: &dyn Fn(&super::Case, Domain, &[Seg]) -> Vec<[f64; 2]>) {
    let mut rng = super::Rng::new(seed);
    let mut failures = Vec::new();
    let mut compared = 0usize;
    for case in cases {
        // Near the origin only: far from it an f32 ray point is off its f64
        // point by more than the slope's tolerance allows for (the value
        // checks model that rounding; this one compares slopes).
        let segs: Vec<Seg> = std::iter::repeat_with(|| super::random_segments(&mut rng, 1)[0]).filter(|s| s[..3].iter().all(|c| c.abs() < 100.0)).take(n).collect();
        let params: Vec<f64> = case.params.iter().map(|&p| f64::from(p)).collect();
        for domain in super::ALGEBRAS {
            for (s, [lo, hi]) in segs.iter().zip(slopes(case, domain, &segs)) {
                if !(lo.is_finite() && hi.is_finite()) {
                    continue;
                }
                let s = s.map(f64::from);
                let f = |u: f64| crate::reference::eval_scalar(&case.ir, [s[0] + s[3] * u, s[1] + s[4] * u, s[2] + s[5] * u, f64::from(SEG_TIME)], &params);
                let h = (s[7] - s[6]) * 1e-4;
                for j in 0..16 {
                    let u = s[6] + 2.0 * h + (s[7] - s[6] - 4.0 * h) * (j as f64 + 0.5) / 16.0;
                    let d1 = (f(u + h) - f(u - h)) / (2.0 * h);
                    let d2 = (f(u + 0.5 * h) - f(u - 0.5 * h)) / h;
                    // The difference's own f64 rounding: far from the origin f
                    // is huge and the step tiny, and the estimate is noise.
                    let noise = 1e-15 * f(u).abs() / h;
                    if !(d1.is_finite() && d2.is_finite()) || (d1 - d2).abs() > 1e-3 * (d1.abs() + 1.0) || noise > 1e-5 * d1.abs() {
                        continue;
                    }
                    compared += 1;
                    let tol = 1e-3 * (lo.abs() + hi.abs() + d1.abs()) + 1e-6;
                    if d1 < lo - tol || d1 > hi + tol {
                        failures.push(format!("{} ({domain:?}): slope {d1:e} at s = {u:e} outside [{lo:e}, {hi:e}] on segment {s:?}", case.name));
                    }
                }
            }
        }
    }
    eprintln!("slopes: {} formulas, {n} segments each, {compared} slopes compared", cases.len());
    assert!(compared > cases.len() * n, "too few slopes compared: {compared}");
    assert!(failures.is_empty(), "{} slope enclosures miss f64 slopes:\n{}", failures.len(), failures.iter().take(20).cloned().collect::<Vec<_>>().join("\n"));
}
