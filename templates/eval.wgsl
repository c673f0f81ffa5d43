// isotrace `eval` kernel: evaluates the generated evaluator of one number
// domain on a batch of boxes (or points), one invocation per box, all boxes
// in one dispatch. This is both a user feature and the hook the conformance
// tests use to check the inclusion property on the device.

// The uniform block (generated from src/layout.rs: EvalBlock).
//!splice:uniforms

// Uniforms from a read-only storage buffer, copied to a private variable at
// the entry point (why: see shared/frame.wgsl).
@group(0) @binding(0) var<storage, read> Ubuf: Eval;
var<private> U: Eval;
// 8 floats per box: x0 x1 y0 y1 z0 z1 t0 t1 (a point has lo == hi).
@group(0) @binding(1) var<storage, read> boxes: array<f32>;
// lo, hi per box (empty: lo > hi; a scalar result: lo == hi).
@group(0) @binding(2) var<storage, read_write> results: array<vec2<f32>>;

fn iso_inf() -> f32 { return U.inf; }
fn iso_param(i: u32) -> f32 { return U.params[i / 4u][i % 4u]; }

//!splice:library

//!splice:inline

//!splice:evaluator

fn box_value(i: u32) -> vec2<f32> {
    let b = i * 8u;
    let x = vec2<f32>(boxes[b], boxes[b + 1u]);
    let y = vec2<f32>(boxes[b + 2u], boxes[b + 3u]);
    let z = vec2<f32>(boxes[b + 4u], boxes[b + 5u]);
    let t = vec2<f32>(boxes[b + 6u], boxes[b + 7u]);
    //!splice:call
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    U = Ubuf;
    let i = gid.x + gid.y * U.row;
    if (i >= U.count) { return; }
    results[i] = box_value(i);
}
