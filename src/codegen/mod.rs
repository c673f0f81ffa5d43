//! IR → WGSL. One emitter walks the IR once and writes straight-line code
//! (`let v3 = ia_mul(v1, v2);`) against a number-domain library; the domain
//! only decides the prefix, the type and how constants are written.
//! [`template`] splices the result into the kernel templates.

pub mod derivative;
pub mod template;

use crate::ir::{display_limited, Ir, NodeId, Op, Var};
use std::fmt::Write;

/// A number domain with its WGSL op library.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Domain {
    /// Plain f32 (`s_*`).
    Scalar,
    /// Interval arithmetic, `vec2<f32>` (`ia_*`).
    Interval,
    /// Reduced affine arithmetic (AF1, n = 1), `vec3<f32>` (`ra_*`).
    Affine,
}

impl Domain {
    /// Prefix of the library's operations.
    pub fn prefix(self) -> &'static str {
        match self {
            Domain::Scalar => "s",
            Domain::Interval => "ia",
            Domain::Affine => "ra",
        }
    }
    /// The WGSL type of a value.
    pub fn ty(self) -> &'static str {
        match self {
            Domain::Scalar => "f32",
            Domain::Interval => "vec2<f32>",
            Domain::Affine => "vec3<f32>",
        }
    }
    /// Name of the generated evaluator function.
    pub fn eval_fn(self) -> String {
        format!("eval_{}", self.prefix())
    }
    /// Source of the op library.
    pub fn library(self) -> &'static str {
        match self {
            Domain::Scalar => include_str!("../../templates/domains/scalar.wgsl"),
            Domain::Interval => include_str!("../../templates/domains/interval.wgsl"),
            Domain::Affine => include_str!("../../templates/domains/affine.wgsl"),
        }
    }
}

/// The op libraries a shader using `domains` needs, each once, in
/// dependency order (scalar helpers first; affine builds on interval).
pub fn libraries(domains: &[Domain]) -> String {
    let mut need = [true, domains.contains(&Domain::Interval) || domains.contains(&Domain::Affine), domains.contains(&Domain::Affine)];
    need[0] = true; // iso_pow_pos / iso_nan live in the scalar library
    let all = [Domain::Scalar, Domain::Interval, Domain::Affine];
    all.iter().zip(need).filter(|(_, n)| *n).map(|(d, _)| d.library()).collect::<Vec<_>>().join("\n")
}

/// f32 nearest to `c`, and the f32 interval enclosing it.
fn f32_enclosure(c: f64) -> (f32, f32, f32) {
    let n = c as f32;
    let (mut lo, mut hi) = (n, n);
    if (n as f64) > c {
        lo = n.next_down();
    } else if (n as f64) < c {
        hi = n.next_up();
    }
    (n, lo, hi)
}

fn lit(c: f32) -> String {
    let s = format!("{c:?}");
    if s.contains(['.', 'e', 'E']) { s } else { format!("{s}.0") }
}

/// Emits `fn eval_<p>(x, y, z, t) -> T` for the formula in `domain`.
/// Parameters are read with `iso_param(i)`, which the kernel provides.
pub fn emit_evaluator(ir: &Ir, domain: Domain) -> String {
    let p = domain.prefix();
    let ty = domain.ty();
    let mut out = String::new();
    let shown = display_limited(ir, ir.root, 160);
    let _ = writeln!(out, "// f = {shown}");
    let _ = writeln!(out, "fn {}(x: {ty}, y: {ty}, z: {ty}, t: {ty}) -> {ty} {{", domain.eval_fn());
    let mut restricted: Vec<NodeId> = Vec::new();
    for id in ir.live() {
        let op = ir.nodes[id as usize];
        let rhs = value_rhs(&mut out, domain, id, op);
        let _ = writeln!(out, "    let v{id} = {rhs};");
        if op.restricts_domain() {
            restricted.push(id);
        }
    }
    if !restricted.is_empty() {
        // Every operation is strict: an argument outside a domain anywhere
        // makes the whole function undefined (empty) on this box.
        let tests: Vec<String> = restricted.iter().map(|r| format!("{p}_is_empty(v{r})")).collect();
        let _ = writeln!(out, "    if ({}) {{ return {p}_empty(); }}", tests.join(" || "));
    }
    let _ = writeln!(out, "    return v{};", ir.root);
    out.push_str("}\n");
    out
}

/// The right-hand side of `let v{id} = …;` for one node (odd powers first
/// write their square-and-multiply chain into `out`).
pub(crate) fn value_rhs(out: &mut String, domain: Domain, id: NodeId, op: Op) -> String {
    let p = domain.prefix();
    let v = |n: NodeId| format!("v{n}");
    match op {
        Op::Const(c) => {
            let (n, lo, hi) = f32_enclosure(c);
            match domain {
                Domain::Interval if lo != hi => format!("vec2<f32>({}, {})", lit(lo), lit(hi)),
                Domain::Affine if lo != hi => format!("ra_from_ia(vec2<f32>({}, {}))", lit(lo), lit(hi)),
                _ => format!("{p}_const({})", lit(n)),
            }
        }
        Op::Var(var) => match var {
            Var::X => "x".into(),
            Var::Y => "y".into(),
            Var::Z => "z".into(),
            Var::T => "t".into(),
        },
        Op::Param(i) => format!("{p}_const(iso_param({i}u))"),
        Op::Neg(a) => format!("{p}_neg({})", v(a)),
        Op::Add(a, b) => format!("{p}_add({}, {})", v(a), v(b)),
        Op::Sub(a, b) => format!("{p}_sub({}, {})", v(a), v(b)),
        Op::Mul(a, b) => format!("{p}_mul({}, {})", v(a), v(b)),
        Op::Div(a, b) => format!("{p}_div({}, {})", v(a), v(b)),
        Op::PowI(a, 2) => format!("{p}_sqr({})", v(a)),
        Op::PowI(a, n) => emit_odd_power(out, p, &format!("w{id}"), &v(a), n),
        Op::Call1(f, a) => format!("{p}_{}({})", f.name(), v(a)),
        Op::Call2(f, a, b) => format!("{p}_{}({}, {})", f.name(), v(a), v(b)),
        Op::Call3(f, a, b, c) => format!("{p}_{}({}, {}, {})", f.name(), v(a), v(b), v(c)),
    }
}

/// Odd power a^n (n ≥ 3) by square-and-multiply over the domain's power
/// helpers; returns the final expression.
pub(crate) fn emit_odd_power(out: &mut String, p: &str, id: &str, a: &str, n: u32) -> String {
    let _ = writeln!(out, "    let {id}_b = {p}_pw_lift({a});");
    let mut cur = format!("{id}_b");
    let bits = 32 - n.leading_zeros();
    for (k, bit) in (0..bits - 1).rev().enumerate() {
        let _ = writeln!(out, "    let {id}_s{k} = {p}_pw_sq({cur});");
        cur = format!("{id}_s{k}");
        if n >> bit & 1 == 1 {
            let _ = writeln!(out, "    let {id}_m{k} = {p}_pw_mul({cur}, {id}_b);");
            cur = format!("{id}_m{k}");
        }
    }
    format!("{p}_pw_odd({a}, {cur})")
}

/// The body of `box_value` in the eval kernel for `domain`: lifts the box
/// (locals `x y z t` as `vec2<f32>` intervals) into the domain and returns
/// the enclosure as `vec2<f32>`.
pub fn eval_call(domain: Domain) -> String {
    let f = domain.eval_fn();
    match domain {
        Domain::Scalar => format!("    return s_range({f}(x.x, y.x, z.x, t.x));"),
        Domain::Interval => format!("    return ia_range({f}(x, y, z, t));"),
        Domain::Affine => format!("    return ra_range({f}(ra_from_ia(x), ra_from_ia(y), ra_from_ia(z), ra_from_ia(t)));"),
    }
}

/// The complete `isotrace eval` shader for `domain`.
pub fn eval_shader(ir: &Ir, domain: Domain) -> String {
    let lib = libraries(&[domain]);
    let eval = emit_evaluator(ir, domain);
    template::splice(template::EVAL, &[("library", &lib), ("evaluator", &eval), ("call", &eval_call(domain))])
        .expect("the eval template has its markers")
}

/// The render kernel's two inclusion functions for `domain`:
/// `cell_range(o, dir, s0, s1)`, the enclosure of f over the ray segment
/// o + dir·[s0, s1]; and `slab_range(eye, f, r, u, s, su, sv)`, the enclosure
/// over the frustum slab eye + s·(f + su·r + sv·u), s, su, sv in ranges.
/// In the affine domain the ray depth s is the symbol e1, so x, y, z along a
/// ray are exact affine forms; across a slab su and sv go into e2.
pub fn inclusion(domain: Domain) -> String {
    let p = domain.prefix();
    let (cell, lift) = match domain {
        Domain::Interval => (
            "    let a = o + dir * s0;\n    let b = o + dir * s1;\n    let lo = min(a, b);\n    let hi = max(a, b);\n    \
             return ia_range(eval_ia(vec2<f32>(lo.x, hi.x), vec2<f32>(lo.y, hi.y), vec2<f32>(lo.z, hi.z), ia_const(U.time)));",
            "vec2<f32>",
        ),
        Domain::Affine => (
            "    let sc = 0.5 * (s0 + s1);\n    let sr = 0.5 * (s1 - s0);\n    let c = o + dir * sc;\n    let r = dir * sr;\n    \
             return ra_range(eval_ra(vec3<f32>(c.x, r.x, 0.0), vec3<f32>(c.y, r.y, 0.0), vec3<f32>(c.z, r.z, 0.0), ra_const(U.time)));",
            "ra_from_ia",
        ),
        Domain::Scalar => unreachable!("the traversal needs an inclusion domain"),
    };
    let s_form = match domain {
        Domain::Affine => "vec3<f32>(0.5 * (s.x + s.y), 0.5 * (s.y - s.x), 0.0)".to_string(),
        _ => "s".to_string(),
    };
    let cell_d = match domain {
        Domain::Interval => "    let a = o + dir * s0;\n    let b = o + dir * s1;\n    let lo = min(a, b);\n    let hi = max(a, b);\n    \
            return evald_ia(vec2<f32>(lo.x, hi.x), vec2<f32>(lo.y, hi.y), vec2<f32>(lo.z, hi.z), ia_const(U.time), ia_const(dir.x), ia_const(dir.y), ia_const(dir.z));",
        _ => "    let sc = 0.5 * (s0 + s1);\n    let sr = 0.5 * (s1 - s0);\n    let c = o + dir * sc;\n    let r = dir * sr;\n    \
            return evald_ra(vec3<f32>(c.x, r.x, 0.0), vec3<f32>(c.y, r.y, 0.0), vec3<f32>(c.z, r.z, 0.0), ra_const(U.time), ra_const(dir.x), ra_const(dir.y), ra_const(dir.z));",
    };
    format!(
        "fn cell_range(o: vec3<f32>, dir: vec3<f32>, s0: f32, s1: f32) -> vec2<f32> {{\n{cell}\n}}\n\n\
fn cell_range_d(o: vec3<f32>, dir: vec3<f32>, s0: f32, s1: f32) -> vec4<f32> {{\n{cell_d}\n}}\n\n\
fn slab_range(eye: vec3<f32>, f: vec3<f32>, r: vec3<f32>, u: vec3<f32>, s: vec2<f32>, su: vec2<f32>, sv: vec2<f32>) -> vec2<f32> {{\n    \
let S = {s_form};\n    let U_ = {lift}(su);\n    let V_ = {lift}(sv);\n    \
let x = {p}_add({p}_const(eye.x), {p}_mul(S, {p}_add({p}_const(f.x), {p}_add({p}_mul(U_, {p}_const(r.x)), {p}_mul(V_, {p}_const(u.x))))));\n    \
let y = {p}_add({p}_const(eye.y), {p}_mul(S, {p}_add({p}_const(f.y), {p}_add({p}_mul(U_, {p}_const(r.y)), {p}_mul(V_, {p}_const(u.y))))));\n    \
let z = {p}_add({p}_const(eye.z), {p}_mul(S, {p}_add({p}_const(f.z), {p}_add({p}_mul(U_, {p}_const(r.z)), {p}_mul(V_, {p}_const(u.z))))));\n    \
return {p}_range(eval_{p}(x, y, z, {p}_const(U.time)));\n}}\n"
    )
}

/// Compile-time choices of the render kernel (Knoll et al.'s modalities):
/// each generates code only when asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RenderConfig {
    /// Shadow rays towards the point light.
    pub shadows: bool,
    /// Surface layers per pixel (1: opaque; more: transparency).
    pub layers: u32,
    /// Reflection bounces.
    pub reflect: u32,
    /// Number of isovalues (1: just f = 0).
    pub iso_count: u32,
    /// Colour mode: 0 Phong, 1 gradient magnitude, 2 depth, 3 normal, 4 evaluations.
    pub color_mode: u32,
    /// Environment: 0 sky, 1 checkered ground, 2 image.
    pub env_mode: u32,
}

impl Default for RenderConfig {
    fn default() -> Self {
        RenderConfig { shadows: false, layers: 1, reflect: 0, iso_count: 1, color_mode: 0, env_mode: 0 }
    }
}

/// The complete render shader with the inclusion function in `domain`.
pub fn render_shader(ir: &Ir, domain: Domain) -> String {
    render_shader_with(ir, domain, &RenderConfig::default())
}

/// The render shader for `domain` with the modalities of `cfg`.
pub fn render_shader_with(ir: &Ir, domain: Domain, cfg: &RenderConfig) -> String {
    let lib = format!("{}\n{}", libraries(&[Domain::Scalar, domain]), derivative::library(domain));
    let evals = format!(
        "{}\n{}\n{}",
        emit_evaluator(ir, Domain::Scalar),
        emit_evaluator(ir, domain),
        derivative::emit_evaluator_d(ir, domain)
    );
    let layers = cfg.layers.max(1);
    let config = format!(
        "const SHADOWS: bool = {};\nconst LAYERS: u32 = {layers}u;\nconst REFLECT: u32 = {}u;\n\
         const ISO_COUNT: u32 = {}u;\nconst COLOR_MODE: u32 = {}u;\nconst ENV_MODE: u32 = {}u;\n",
        cfg.shadows,
        cfg.reflect,
        cfg.iso_count.clamp(1, 8),
        cfg.color_mode,
        cfg.env_mode
    );
    let mut modalities = String::new();
    modalities.push_str(template::part(template::MODALITIES, if cfg.shadows { "shadows" } else { "no_shadows" }));
    modalities.push_str(template::part(template::MODALITIES, if cfg.reflect > 0 { "reflections" } else { "no_reflections" }));
    template::splice(
        template::BISECT,
        &[
            ("library", &lib),
            ("evaluators", &evals),
            ("inclusion", &inclusion(domain)),
            ("config", &config),
            ("shading", template::SHADE),
            ("modalities", &modalities),
        ],
    )
    .expect("the render template has its markers")
}
