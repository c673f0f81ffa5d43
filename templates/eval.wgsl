// isotrace `eval` kernel: evaluates the generated evaluator of one number
// domain on a batch of boxes (or points), one invocation per box, all boxes
// in one dispatch. This is both a user feature and the hook the conformance
// tests use to check the inclusion property on the device.

// The uniform block (generated from src/layout.rs: EvalBlock).
//!splice:uniforms

// Uniforms (Ubuf) from a read-only storage buffer, copied to a private
// variable at the entry point (why: see shared/frame.wgsl); the boxes and
// results (src/codegen/template.rs says their layout).
//!splice:bindings
var<private> U: Eval;

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
