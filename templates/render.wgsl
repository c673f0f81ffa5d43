// isotrace render kernel. Assembled by src/kernel.rs from one
// traversal (templates/traverse/) and one field source (src/field/mod.rs)
// around the shared frame, camera, pixel and shading code (templates/shared/).
//
// Bind groups by lifetime:
//   group(0) frame:  uniforms (frame + traversal block) and the traversal's
//                    frame resources (the environment image of bisection);
//   group(1) field:  the field source's buffers (none for a compiled formula);
//   group(2) pass:   per-dispatch outputs: pixel records, then the
//                    traversal's own (tile masks and lists, statistics).

// ---- Uniform declarations and shared constants, generated from src/layout.rs.
//!splice:uniforms

//!splice:shared

// ---- The field source: field(p) for every traversal, and for bisection the
// enclosures of f over ray cells and frustum slabs.
//!splice:field

// ---- The traversal.
//!splice:traversal
