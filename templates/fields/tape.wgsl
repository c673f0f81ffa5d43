// The tape interpreter, written once against the shared op interface:
// `T` is the number domain's value type and every `op_*` call is the
// domain's operation (src/field/tape/wgsl.rs instantiates this file per
// domain: scalar s_, interval ia_, affine ra_, renaming `op_*`, `T` and
// the `_T` suffix of its own names). The tape (src/field/tape/mod.rs) lives
// in the field group, a texture read by tape_word (a texel fetch is a
// vector gather on lavapipe; a storage load at a per-lane address runs lane
// by lane): a header, then the value and the derivative programs, one
// vec4<u32> per instruction:
//   x: code | flags << 8 | out << 16, y: a | b << 16, z: c | d << 16,
//   w: immediate (input, parameter, power); a constant, and an arithmetic
//   instruction's constant operand: its enclosure's (lo, hi) bits in z, w.
// The operation codes, limits and run results (TAPE_DONE, TAPE_EMPTY,
// TAPE_EXHAUSTED) are generated from Rust (TAPE_* constants).
//
// A min or max carries its choice slot in w, and so does a square root or
// logarithm that restricts f's domain. Bisection's tile pass (with
// tape_tiles.wgsl) notes in the slot which operand the result can be over
// the tile's candidate slabs (or whether the argument stays in its
// domain), and gives the tile a shortened list of the
// instructions it needs (tape_entry: pc | pick << 30); a min or max whose
// pick is 1 or 2 is then a copy of its first or second operand (for Dmin and
// Dmax: of da or db), whose other operand was never computed.

// The register file: module scope, so it is zero-initialised once per
// invocation and not on every call (lavapipe zeroes a function-scope array
// on every call, which made the scene interpreter several times slower).
var<private> g_regs_T: array<T, TAPE_SLOTS>;
// The inputs of input instructions (kernels for tapes whose inputs are not
// pinned in registers 0 to 6: src/field/tape/mod.rs TAPE_INPUTS).
var<private> g_in_T: array<T, 7>; // if INPUTS

// The point x, y, z, t and the ray direction: pinned in registers 0 to 6,
// or where input instructions load them.
fn tape_point_T(x: T, y: T, z: T, t: T) {
    g_regs_T[0] = x; // if PINNED
    g_regs_T[1] = y; // if PINNED
    g_regs_T[2] = z; // if PINNED
    g_regs_T[3] = t; // if PINNED
    g_in_T[0] = x; // if INPUTS
    g_in_T[1] = y; // if INPUTS
    g_in_T[2] = z; // if INPUTS
    g_in_T[3] = t; // if INPUTS
}
fn tape_direction_T(dx: T, dy: T, dz: T) {
    g_regs_T[4] = dx; // if PINNED
    g_regs_T[5] = dy; // if PINNED
    g_regs_T[6] = dz; // if PINNED
    g_in_T[4] = dx; // if INPUTS
    g_in_T[5] = dy; // if INPUTS
    g_in_T[6] = dz; // if INPUTS
}

// Input k of an input instruction: selects over constant indices, where an
// indexed read of the array costs what a register read does (a per-lane
// read of lavapipe's scratch memory) and would run, masked, for every
// instruction.
fn tape_input_T(k: u32) -> T { // if INPUTS
    var v = select(g_in_T[0], g_in_T[1], k == 1u); // if INPUTS
    v = select(v, g_in_T[2], k == 2u); // if INPUTS
    v = select(v, g_in_T[3], k == 3u); // if INPUTS
    v = select(v, g_in_T[4], k == 4u); // if INPUTS
    v = select(v, g_in_T[5], k == 5u); // if INPUTS
    return select(v, g_in_T[6], k >= 6u); // if INPUTS
} // if INPUTS

// a^n (n >= 3) by square-and-multiply over the domain's power helpers,
// exactly as the generated code unrolls it.
fn tape_pow_T(a: T, n: u32) -> T {
    let b = op_pw_lift(a);
    var w = b;
    let top = 31u - countLeadingZeros(n);
    for (var k = 0u; k < top; k = k + 1u) {
        w = op_pw_sq(w);
        if (((n >> (top - 1u - k)) & 1u) == 1u) { w = op_pw_mul(w, b); }
    }
    return op_pw_odd(a, w);
}

// a^n for 1 <= n < 8: tape_pow_T written out (at most two squarings), so
// a kernel whose powers are all small has no loop among its cases.
fn tape_pow_small_T(a: T, n: u32) -> T {
    let b = op_pw_lift(a);
    let top = 31u - countLeadingZeros(n);
    var w = b;
    if (top >= 1u) {
        w = op_pw_sq(w);
        if (((n >> ((top - 1u) & 31u)) & 1u) == 1u) { w = op_pw_mul(w, b); }
    }
    if (top == 2u) {
        w = op_pw_sq(w);
        if ((n & 1u) == 1u) { w = op_pw_mul(w, b); }
    }
    return op_pw_odd(a, w);
}

fn tape_reg_T(i: u32) -> T { return g_regs_T[i & TAPE_SLOT_MASK]; }
// The third operand of instruction w (a multiply-add with an immediate
// factor has its addend where the factor's register would be) and the
// fourth.
fn tape_c_T(w: vec4<u32>) -> T { return tape_reg_T(select(w.z, w.y >> 16u, (w.x & TAPE_IMM_B) != 0u)); }
fn tape_d_T(w: vec4<u32>) -> T { return tape_reg_T(w.z >> 16u); }

// Notes in choice slot `slot` what instruction `code` with operands a and b
// can do over the slab being enclosed (only while the tile pass records,
// tape_tiles.wgsl; one call site per step, after the cases): a min or a
// max which operand its result can be (1 the first, 2 the second, 3
// either, also for empty or NaN ranges); a square root or logarithm with a
// slot (it restricts f's domain) whether its argument stays in its domain
// (1) or may not (2).
fn tape_note_T(code: u32, slot: u32, a: T, b: T) {
    if (slot >= TAPE_CHOICE_SLOTS) { return; }
    let i = op_range(a);
    let j = op_range(b);
    var c = 0u;
    if (code == TAPE_MIN || code == TAPE_MAX) {
        let max = code == TAPE_MAX;
        c = 3u;
        if (i.x <= i.y && j.x <= j.y) {
            if (i.y <= j.x) { c = select(1u, 2u, max); }
            else if (j.y <= i.x) { c = select(2u, 1u, max); }
        }
    } else if (code == TAPE_SQRT || code == TAPE_LOG) {
        c = select(2u, 1u, i.x > 0.0 || (code == TAPE_SQRT && i.x == 0.0));
    }
    tape_note_bits(slot, c);
}

// Runs the instruction of list entry `e` (pc | pick << 30, or
// TAPE_LIST_NOP); true when its result is empty and it is strict (the whole
// function is then empty).
fn tape_step_T(e: u32) -> bool {
    let w = tape_word(e & TAPE_PC_MASK);
    let code = w.x & 0xffu;
    // A list's padding or a program's no-op runs like any instruction and
    // writes nothing (an early return is a branch around the whole step).
    let live = e != TAPE_LIST_NOP && code != TAPE_NOP;
    // A register read is a per-lane load from lavapipe's scratch memory, so
    // an operand is read only where the instruction has it: behind an `if`
    // that every lane of a bundle takes or none does (they run the same
    // instruction), and the third and fourth operands inside the cases that
    // read them. Lines marked `if GROUP…` stay only in kernels with one of
    // those groups.
    // A constant, or an arithmetic instruction's constant operand (its flags
    // TAPE_IMM_A, TAPE_IMM_B): the enclosure in z, w, the nearest f32 one
    // of its ends.
    let k = op_lit(bitcast<f32>(select(w.z, w.w, (w.x & TAPE_NEAR_HI) != 0u)), bitcast<f32>(w.z), bitcast<f32>(w.w));
    var a = k;
    if ((w.x & TAPE_IMM_A) == 0u) { a = tape_reg_T(w.y); }
    var b = k;
    if ((w.x & (TAPE_IMM_B | TAPE_UNARY)) == 0u) { b = tape_reg_T(w.y >> 16u); }
    // The cases, each behind an `if` on its code (src/field/tape/wgsl.rs
    // keeps those of the kernel's groups and nests them in a binary search
    // on the code, so a step tests a few codes, not every one). A bundle's
    // lanes step through the same instruction, and lavapipe skips an `if`
    // that none of them takes, so a step pays for its own case, not for
    // every case of its groups as a chain of selects would (long
    // transcendental tapes and CSG tapes come sooner; small ones are
    // unchanged). A `switch` runs every case. A code without a case gives
    // the whole line.
    var r = op_whole();
    if (code == TAPE_INPUT) { r = tape_input_T(w.w); }
    if (code == TAPE_CONST) { r = k; }
    if (code == TAPE_PARAM) { r = op_const(iso_param(w.w)); }
    if (code == TAPE_NEG) { r = op_neg(a); }
    if (code == TAPE_ADD) { r = op_add(a, b); }
    if (code == TAPE_SUB) { r = op_sub(a, b); }
    if (code == TAPE_MUL) { r = op_mul(a, b); }
    if (code == TAPE_MAD) { r = op_add(op_mul(a, b), tape_c_T(w)); }
    if (code == TAPE_MSUB) { r = op_sub(op_mul(a, b), tape_c_T(w)); }
    if (code == TAPE_DIV) { r = op_div(a, b); }
    if (code == TAPE_SQR) { r = op_sqr(a); }
    // (Its loop runs no pass for another code's immediate.)
    if (code == TAPE_POWCHAIN) { r = tape_pow_T(a, select(1u, w.w, code == TAPE_POWCHAIN)); }
    if (code == TAPE_POWSMALL) { r = tape_pow_small_T(a, w.w); }
    if (code == TAPE_SQRT) { r = op_sqrt(a); }
    if (code == TAPE_EXP) { r = op_exp(a); }
    if (code == TAPE_LOG) { r = op_log(a); }
    if (code == TAPE_SIN) { r = op_sin(a); }
    if (code == TAPE_COS) { r = op_cos(a); }
    if (code == TAPE_TAN) { r = op_tan(a); }
    if (code == TAPE_ATAN) { r = op_atan(a); }
    if (code == TAPE_SINH) { r = op_sinh(a); }
    if (code == TAPE_COSH) { r = op_cosh(a); }
    if (code == TAPE_TANH) { r = op_tanh(a); }
    if (code == TAPE_ABS) { r = op_abs(a); }
    if (code == TAPE_SIGN) { r = op_sign(a); }
    if (code == TAPE_FLOOR) { r = op_floor(a); }
    if (code == TAPE_POW) { r = op_pow(a, b); }
    if (code == TAPE_ATAN2) { r = op_atan2(a, b); }
    if (code == TAPE_MIN) { r = op_min(a, b); }
    if (code == TAPE_MAX) { r = op_max(a, b); }
    if (code == TAPE_CLAMP) { r = op_clamp(a, b, tape_c_T(w)); }
    if (code == TAPE_MIX) { r = op_mix(a, b, tape_c_T(w)); }
    if (code == TAPE_DMIN) { r = op_dmin(a, b, tape_c_T(w), tape_d_T(w)); }
    if (code == TAPE_DMAX) { r = op_dmax(a, b, tape_c_T(w), tape_d_T(w)); }
    if (code == TAPE_DSIGN) { r = op_dsign(a, b); }
    if (code == TAPE_DFLOOR) { r = op_dfloor(a, b); }
    if (g_tape_record && live) { tape_note_T(code, w.w, a, b); }
    // A list's pick makes a min or max a copy of one operand (a slope's
    // min or max: of that operand's slope).
    let pick = e >> 30u; // if MINMAX
    if (pick == 1u) { r = select(a, tape_c_T(w), code >= TAPE_DMIN); } // if MINMAX
    if (pick == 2u) { r = select(b, tape_d_T(w), code >= TAPE_DMIN); } // if MINMAX
    if (live) { g_regs_T[(w.x >> 16u) & TAPE_SLOT_MASK] = r; }
    return live && (w.x & TAPE_RESTRICTS) != 0u && op_is_empty(r);
}

// Runs program `prog` (0: value, 1: derivative), the whole of it or the
// tile's shortened list (tape_span), TAPE_UNROLL instructions per loop
// iteration (1, 4, 8 or 16: lines marked `each unrolled step K` are
// written once for each K from 1 to TAPE_UNROLL - 1 by
// src/field/tape/wgsl.rs; programs are padded to a multiple of 4, or of
// 8 or 16 for the longest tapes, lists to the kernel's TAPE_UNROLL). Past the work
// limit (tape_admits: the power chains' iterations from the header, the
// loop's, and with the power case one pass of its loop per instruction,
// which lavapipe runs masked for every instruction) it runs nothing and
// says so.
fn tape_run_T(prog: u32) -> u32 {
    let span = tape_span(prog);
    // Refused, the loop runs no iteration (no branch around it).
    let admitted = tape_admits(select(tape_word(2u).x, tape_word(2u).y, prog == 1u) + span.y / TAPE_UNROLL + span.y * TAPE_POW_PASSES);
    g_tape_exhausted = g_tape_exhausted || !admitted;
    let len = select(0u, span.y, admitted);
    var empty = false;
    for (var i = span.x; i < span.x + len; i = i + TAPE_UNROLL) {
        let e0 = tape_step_T(tape_entry(i));
        empty = empty || e0;
        let eK = tape_step_T(tape_entry(i + Ku)); // each unrolled step K
        empty = empty || eK; // each unrolled step K
    }
    return select(select(TAPE_DONE, TAPE_EMPTY, empty), TAPE_EXHAUSTED, !admitted);
}

// The enclosure of f over the box (x, y, z, t) and, with `slope`, of its
// derivative along the ray direction (dx, dy, dz): one interpreter run of
// the value or of the derivative program, whichever is asked, so a
// traversal that needs both inlines one copy of the interpreter (lavapipe
// compiles each inlined copy in full). An evaluation past the work limit
// gives the whole line: the cell is kept, never wrongly rejected, and the
// pixel is reported (field_exhausted).
fn tape_enclosure_T(x: T, y: T, z: T, t: T, dx: T, dy: T, dz: T, slope: bool) -> vec4<f32> {
    tape_point_T(x, y, z, t);
    tape_direction_T(dx, dy, dz);
    let st = tape_run_T(select(0u, 1u, slope));
    let o = tape_word(1u);
    let f = op_range(tape_reg_T(select(o.x, o.y, slope)));
    var r = vec4<f32>(f, -iso_inf(), iso_inf());
    r = select(r, vec4<f32>(f, op_range(tape_reg_T(o.z))), slope);
    r = select(r, vec4<f32>(op_range(op_empty()), 0.0, 0.0), st == TAPE_EMPTY);
    return select(r, vec4<f32>(-iso_inf(), iso_inf(), -iso_inf(), iso_inf()), st == TAPE_EXHAUSTED);
}

// The enclosure of f over the box: what `surf_*` is for a compiled formula,
// so the traversal's cell and slab functions are shared.
fn surf_T(x: T, y: T, z: T, t: T) -> vec2<f32> {
    return tape_enclosure_T(x, y, z, t, x, x, x, false).xy;
}

// f and its derivative along the ray direction (dx, dy, dz, exact f32):
// what `evald_*` is for a compiled formula.
fn evald_T(x: T, y: T, z: T, t: T, dx: f32, dy: f32, dz: f32) -> vec4<f32> {
    return tape_enclosure_T(x, y, z, t, op_const(dx), op_const(dy), op_const(dz), true);
}
