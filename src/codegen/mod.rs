//! IR → WGSL. One emitter walks the IR once and writes straight-line code
//! (`let v3 = ia_mul(v1, v2);`) against a number-domain library; the domain
//! only decides the prefix, the type and how constants are written.
//! [`compiled`] makes a formula a field source; [`kernel`] assembles a
//! render kernel from a traversal and a field source; [`template`] is the
//! one splicing mechanism both use.

/// The per-pixel hooks of a field source that has no tiles (a compiled
/// formula, a tape): the whole ray is its business (a scene narrows it to
/// the depths its tile's primitives span, templates/fields/scene.wgsl).
pub(crate) const UNTILED_FIELD_HOOKS: &str = "fn field_enter_pixel(px: vec2<u32>) {}\n\
    fn field_ray_range(o: vec3<f32>, d: vec3<f32>) -> vec2<f32> { return vec2<f32>(-F.inf, F.inf); }\n";
/// The hooks of bisection's tile pass for a field that runs the same code in
/// every tile (a tape with min or max shortens itself per tile instead:
/// `templates/fields/tape_tiles.wgsl`).
pub(crate) const UNSHORTENED_FIELD_HOOKS: &str = "fn field_leave_frustum() {}\n\
    fn field_tile_begin(t: u32, tile: vec2<u32>, block: bool) -> vec3<u32> { return vec3<u32>(0xffffffffu, 0xffffffffu, 0u); }\n\
    fn field_slab_begin(record: bool) {}\nfn field_slab_end(hold: bool) {}\n\
    fn field_tile_done(mask: vec2<u32>, n: u32, block: bool) -> u32 { return 0u; }\n\
    fn field_enter_tile(list: u32) {}\nfn field_in_tile(inside: bool) {}\n";

mod balance;
mod loops;
pub mod choice;
pub mod compiled;
pub mod derivative;
pub mod kernel;
pub mod magnitude;
mod ray_forms;
mod ray_polys;

/// Whether an IA kernel bisecting `ir` compiled takes polynomial nodes of
/// degree 3 to 6 from the ray (`ray_polys`): what `choose_algebra` asks.
pub fn takes_ray_polynomials(ir: &Ir) -> bool {
    ray_forms::ray_nodes(ir).is_some_and(|r| r.has_polynomials())
}
pub mod reroll;
pub mod tape;
mod tape_derivative;
pub mod tape_field;
pub mod template;

pub use compiled::inclusion;
pub use kernel::{assemble, assemble_for, ray_cell_eval_shader, render_shader, scene_eval_shader, sphere_shader, FieldSource, Kernel, SceneData, Texels};
pub use choice::{FieldKind, PreparedField};
pub use tape::{TapeData, TapeError};

use crate::ir::{display_limited, Ir, NodeId, Op, Var};
use loops::LoopEmitter;
pub(crate) use loops::Tiles;
use crate::layout::GpuBlock;
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
    libraries_with(domains, true)
}

/// [`libraries`] with the affine library's NaN test on the ranges it reads
/// (`template::AFFINE_RANGE`) on or off: off only in a compiled formula's kernel whose
/// forms cannot overflow within the inputs it admits ([`magnitude`]).
pub(crate) fn libraries_with(domains: &[Domain], guard: bool) -> String {
    let mut need = [true, domains.contains(&Domain::Interval) || domains.contains(&Domain::Affine), domains.contains(&Domain::Affine)];
    need[0] = true; // iso_pow_pos / iso_nan live in the scalar library
    let all = [Domain::Scalar, Domain::Interval, Domain::Affine];
    let text = |d: Domain| match d {
        Domain::Affine => format!("{}\n{}", template::optional(template::AFFINE_RANGE, guard), d.library()),
        _ => d.library().to_string(),
    };
    all.iter().zip(need).filter(|(_, n)| *n).map(|(&d, _)| text(d)).collect::<Vec<_>>().join("\n")
}

/// f32 nearest to `c`, and the f32 interval enclosing it. lavapipe flushes
/// subnormal f32 to zero in arithmetic, so a constant below the smallest
/// normal f32 in magnitude is enclosed by normal ends, [0, 2^-126] or its
/// negative: an end the device reads as 0 could exclude the constant
/// (`x / 1e-40` was enclosed by [f32::MAX, inf] for x near 0.5 before).
pub(crate) fn f32_enclosure(c: f64) -> (f32, f32, f32) {
    let n = c as f32;
    let tiny = f64::from(f32::MIN_POSITIVE);
    if c != 0.0 && c.abs() < tiny {
        return if c > 0.0 { (n, 0.0, f32::MIN_POSITIVE) } else { (n, -f32::MIN_POSITIVE, 0.0) };
    }
    let (mut lo, mut hi) = (n, n);
    if (n as f64) > c {
        lo = n.next_down();
    } else if (n as f64) < c {
        hi = n.next_up();
    }
    (n, lo, hi)
}

/// `ra_from_ia` of a finite, non-empty interval worked out on the host in
/// the device's f32 steps: the form's centre and error term.
fn affine_of(lo: f32, hi: f32) -> Option<(f32, f32)> {
    if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
        return None;
    }
    let d = 0.5 * (hi - lo);
    Some((lo + d, d))
}

/// A literal's affine form, `ra_from_ia` of its enclosing f32 interval
/// worked out here (`affine_of`): a `ra_from_ia` per literal was a tenth of
/// the time lavapipe took to create `@creature`'s RAA pipeline (the RAA op
/// library's helpers are inlined at every use).
fn affine_literal(lo: f32, hi: f32) -> String {
    match affine_of(lo, hi) {
        Some((c, d)) => format!("vec3<f32>({}, 0.0, {})", lit(c), lit(d)),
        None => format!("ra_from_ia(vec2<f32>({}, {}))", lit(lo), lit(hi)),
    }
}

/// `a / c` for a literal `c` in an inclusion domain, as the product with
/// `1 / c` that the domain's division takes for a divisor without 0
/// (`ia_div`, `ra_div`), its reciprocal worked out here in the same f32
/// steps: the same value, without the division's other cases, which
/// lavapipe compiles at every use (a sixth of `@creature`'s RAA pipeline,
/// 48 divisions by its blend radii). `None`: the scalar domain (a plain
/// division), a divisor whose enclosure holds 0, or one whose reciprocal
/// is not a finite f32.
pub(crate) fn divide_by_literal(domain: Domain, a: &str, c: f64) -> Option<String> {
    let (n, lo, hi) = f32_enclosure(c);
    match domain {
        Domain::Scalar => None,
        Domain::Interval => {
            let (lo, hi) = if lo != hi { (lo, hi) } else { (n, n) };
            // A reciprocal past f32 (a divisor below 2^-128) has no WGSL literal.
            let (r_lo, r_hi) = (1.0 / hi, 1.0 / lo);
            let usable = (lo > 0.0 || hi < 0.0) && r_lo.is_finite() && r_hi.is_finite();
            usable.then(|| format!("ia_mul({a}, vec2<f32>({}, {}))", lit(r_lo), lit(r_hi)))
        }
        Domain::Affine => {
            // ra_div: the divisor's form, its range (its radius is d), the
            // reciprocal's form.
            let (c, d) = if lo != hi { affine_of(lo, hi)? } else { (n, 0.0) };
            let (lo, hi) = (c - d, c + d);
            if !(lo > 0.0 || hi < 0.0) {
                return None;
            }
            let (c, d) = affine_of(1.0 / hi, 1.0 / lo)?;
            Some(format!("ra_mul({a}, vec3<f32>({}, 0.0, {}))", lit(c), lit(d)))
        }
    }
}

fn lit(c: f32) -> String {
    let s = format!("{c:?}");
    if s.contains(['.', 'e', 'E']) { s } else { format!("{s}.0") }
}

/// Emits `fn eval_<p>(x, y, z, t) -> T` for the formula in `domain`.
/// Parameters are read with `iso_param(i)`, which the kernel provides.
pub fn emit_evaluator(ir: &Ir, domain: Domain) -> String {
    emit_evaluator_on(ir, domain, None, Tiles::Off)
}

/// [`emit_evaluator`], or with `ray` its version on a ray, `fn
/// eval_<p>_ray(x, y, z, t, tr)`, whose nodes of degree ≤ 2 come from their
/// polynomials along the ray at `tr` ([`emit_body_on`]).
pub(crate) fn emit_evaluator_on(ir: &Ir, domain: Domain, ray: Option<&ray_forms::RayForms>, tiles: Tiles) -> String {
    let p = domain.prefix();
    let ty = domain.ty();
    let mut out = String::new();
    let shown = display_limited(ir, ir.root, 160);
    let _ = writeln!(out, "// f = {shown}");
    let (suffix, extra) = if ray.is_some() { ("_ray", ", tr: f32") } else { ("", "") };
    let _ = writeln!(out, "fn {}{suffix}(x: {ty}, y: {ty}, z: {ty}, t: {ty}{extra}) -> {ty} {{", domain.eval_fn());
    let body = emit_body_tiled(&mut out, ir, domain, ray.map(|r| (r, "tr")), tiles, |_, _| {});
    // A select, not a branch, like the op libraries (their tests say why).
    let mut ret = format!("v{}", ir.root);
    if let Some(empty) = body.empty {
        ret = format!("select({ret}, {p}_empty(), {empty})");
    }
    if body.looped {
        ret = format!("select({ret}, {}, !admitted)", whole(domain));
    }
    let _ = writeln!(out, "    return {ret};");
    out.push_str("}\n");
    out
}

/// The value that says nothing (an evaluation refused by the work limit).
fn whole(domain: Domain) -> &'static str {
    match domain {
        Domain::Scalar => "iso_nan()",
        Domain::Interval => "vec2<f32>(-iso_inf(), iso_inf())",
        Domain::Affine => "ra_whole()",
    }
}

/// Emits `fn eval_<p>_all(x, y, z, t) -> array<T, N>` returning the values
/// of `outputs` (several surfaces and their conditions share one pass and
/// its common sub-expressions).
pub fn emit_evaluator_all(ir: &Ir, domain: Domain, outputs: &[NodeId]) -> String {
    let p = domain.prefix();
    let ty = domain.ty();
    let n = outputs.len();
    let mut out = String::new();
    let _ = writeln!(out, "fn eval_{p}_all(x: {ty}, y: {ty}, z: {ty}, t: {ty}) -> array<{ty}, {n}> {{");
    let body = emit_body(&mut out, ir, domain, |_, _| {});
    let mut bail = Vec::new();
    if let Some(empty) = body.empty {
        bail.push((empty, format!("{p}_empty()")));
    }
    if body.looped {
        bail.push(("!admitted".to_string(), whole(domain).to_string()));
    }
    for (test, value) in bail {
        let values = vec![value; n].join(", ");
        let _ = writeln!(out, "    if ({test}) {{ return array<{ty}, {n}>({values}); }}");
    }
    let vals: Vec<String> = outputs.iter().map(|o| format!("v{o}")).collect();
    let _ = writeln!(out, "    return array<{ty}, {n}>({});", vals.join(", "));
    out.push_str("}\n");
    out
}

/// What [`emit_body`] tells its hook: a node was written (`let v{id}`), or
/// a rerolled loop's accumulator `v{acc}` was declared from `v{seed}`,
/// stepped to `v{next}`, and its final value named `v{end}`.
pub(crate) enum Hook {
    Node(NodeId, Op),
    Begin { acc: NodeId, seed: NodeId },
    Step { acc: NodeId, next: NodeId },
    End { acc: NodeId, end: NodeId },
}

/// What [`emit_body`] wrote: the test that is true when the function is
/// undefined on the box (every operation is strict, so a sqrt/log/pow node
/// that is empty makes the whole function empty; `None` when the formula
/// has no such node), and whether it has rerolled loops (then `admitted`
/// says whether the work limit let them run).
pub(crate) struct Body {
    pub empty: Option<String>,
    pub looped: bool,
}

/// Writes `let v{id} = …;` for every live node, telling `hook` after each
/// (the derivative emitter adds its `d{id}` there); runs of same-shaped
/// terms become loops ([`reroll`]).
pub(crate) fn emit_body(out: &mut String, ir: &Ir, domain: Domain, hook: impl FnMut(&mut String, Hook)) -> Body {
    emit_body_on(out, ir, domain, None, hook)
}

/// [`emit_body`] on a ray: with `ray` (the forms and the WGSL arguments of
/// their calls, `t0, t1` for a cell, `tr` for a point), a node of degree
/// ≤ 2 in x, y, z that [`ray_forms::ray_nodes`] picked is taken from its
/// polynomial along the ray (`ia_ray`, `s_ray`), where intervals over the
/// cell's box overestimate it.
pub(crate) fn emit_body_on(out: &mut String, ir: &Ir, domain: Domain, ray: Option<(&ray_forms::RayForms, &str)>, hook: impl FnMut(&mut String, Hook)) -> Body {
    emit_body_tiled(out, ir, domain, ray, Tiles::Off, hook)
}

/// [`emit_body_on`] with what its loops do with per-tile term lists
/// ([`Tiles`]; nothing for a formula without listed loops).
pub(crate) fn emit_body_tiled(out: &mut String, ir: &Ir, domain: Domain, ray: Option<(&ray_forms::RayForms, &str)>, tiles: Tiles, mut hook: impl FnMut(&mut String, Hook)) -> Body {
    let p = domain.prefix();
    let plan = reroll::plan(ir);
    let looped = !plan.loops.is_empty();
    let lists = match tiles {
        Tiles::Off => None,
        _ => reroll::lists::lists(ir, &plan),
    };
    if looped {
        let work = match (&lists, tiles) {
            (Some(x), Tiles::Listed) => format!("loop_work({}u, {}u)", plan.iterations(), x.fallback_iterations[usize::from(domain != Domain::Scalar)]),
            // The tile pass's notes take a second pass over the listed loops.
            (Some(x), Tiles::Record) => format!("{}u", plan.iterations() + x.notes_iterations),
            _ => format!("{}u", plan.iterations()),
        };
        let _ = writeln!(out, "    let admitted = field_admits({work});");
    }
    let nn = nonneg(ir);
    let mut loops = LoopEmitter { ir, domain, nn: &nn, fresh: ir.nodes.len() as NodeId };
    let mut restricted: Vec<String> = Vec::new();
    for id in ir.live() {
        if plan.skips(id) {
            continue;
        }
        if let Some(l) = plan.loop_at(id) {
            let listed = lists.as_ref().and_then(|x| x.of(l.end));
            restricted.extend(loops.emit(out, l, listed, tiles, &mut hook));
            continue;
        }
        let op = ir.nodes[id as usize];
        let rhs = match ray {
            Some((forms, args)) if forms.takes(id, p) => forms.rhs(id, p, args),
            _ => value_rhs(out, domain, id, op, ir, &nn),
        };
        let _ = writeln!(out, "    let v{id} = {rhs};");
        if op.restricts_domain() {
            restricted.push(format!("{p}_is_empty(v{id})"));
        }
        hook(out, Hook::Node(id, op));
    }
    Body { empty: (!restricted.is_empty()).then(|| restricted.join(" || ")), looped }
}

/// Which nodes are never negative, by their form: even powers, |a|,
/// sqrt, exp and cosh, non-negative constants, and sums, products, minima
/// and quotients by positive constants of such nodes (a maximum needs one).
/// An interval product of two such values is [lo·lo, hi·hi], and of any
/// interval d by such a v two products, not four and six comparisons
/// (`ia_mul_nonneg`, `ia_mul_by_nonneg`): the decocube's three factors,
/// sums of squares, and their product's slope.
pub(crate) fn nonneg(ir: &Ir) -> Vec<bool> {
    use crate::ir::{Func1, Func2};
    let mut nn: Vec<bool> = Vec::with_capacity(ir.nodes.len());
    for op in &ir.nodes {
        let g = |n: &NodeId| nn.get(*n as usize).copied().unwrap_or(false);
        let konst = |n: &NodeId| match ir.nodes.get(*n as usize) {
            Some(Op::Const(c)) => Some(*c),
            _ => None,
        };
        let v = match op {
            Op::Const(c) => *c >= 0.0,
            Op::PowI(a, n) => n % 2 == 0 || g(a),
            Op::Add(a, b) | Op::Mul(a, b) => g(a) && g(b),
            Op::Div(a, b) => g(a) && konst(b).is_some_and(|c| c > 0.0),
            Op::Call1(Func1::Abs | Func1::Sqrt | Func1::Exp | Func1::Cosh, _) => true,
            Op::Call2(Func2::Min, a, b) => g(a) && g(b),
            Op::Call2(Func2::Max, a, b) => g(a) || g(b),
            _ => false,
        };
        nn.push(v);
    }
    nn
}

/// The right-hand side of `let v{id} = …;` for one node (odd powers first
/// write their square-and-multiply chain into `out`); `nn` says which
/// nodes are never negative ([`nonneg`]; ids past it are not known to be).
pub(crate) fn value_rhs(out: &mut String, domain: Domain, id: NodeId, op: Op, ir: &Ir, nn: &[bool]) -> String {
    let names = &ir.externs;
    let p = domain.prefix();
    let v = |n: NodeId| format!("v{n}");
    match op {
        Op::Const(c) => {
            let (n, lo, hi) = f32_enclosure(c);
            match domain {
                Domain::Interval if lo != hi => format!("vec2<f32>({}, {})", lit(lo), lit(hi)),
                Domain::Affine if lo != hi => affine_literal(lo, hi),
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
        Op::Mul(a, b) if domain == Domain::Interval && [a, b].iter().all(|n| nn.get(*n as usize) == Some(&true)) => format!("ia_mul_nonneg({}, {})", v(a), v(b)),
        Op::Mul(a, b) => format!("{p}_mul({}, {})", v(a), v(b)),
        Op::Div(a, b) => match ir.nodes.get(b as usize) {
            // (A loop's table slots have fresh ids, past the IR's nodes.)
            Some(&Op::Const(c)) => divide_by_literal(domain, &v(a), c).unwrap_or_else(|| format!("{p}_div({}, {})", v(a), v(b))),
            _ => format!("{p}_div({}, {})", v(a), v(b)),
        },
        Op::PowI(a, 2) => format!("{p}_sqr({})", v(a)),
        // sema writes even powers as powers of the square; an even n > 2
        // reaching here is still handled exactly: (a^2)^(n/2) of a
        // non-negative base.
        Op::PowI(a, n) if n % 2 == 0 => {
            let _ = writeln!(out, "    let w{id}_q = {p}_sqr({});", v(a));
            if n == 4 { format!("{p}_sqr(w{id}_q)") } else { emit_odd_power(out, p, &format!("w{id}"), &format!("w{id}_q"), n / 2) }
        }
        Op::PowI(a, n) => emit_odd_power(out, p, &format!("w{id}"), &v(a), n),
        Op::Call1(f, a) => format!("{p}_{}({})", f.name(), v(a)),
        Op::Call2(f, a, b) => format!("{p}_{}({}, {})", f.name(), v(a), v(b)),
        Op::Call3(f, a, b, c) => format!("{p}_{}({}, {}, {})", f.name(), v(a), v(b), v(c)),
        Op::User(u, args, n) => {
            let a: Vec<String> = args[..n as usize].iter().map(|&x| v(x)).collect();
            format!("{p}_{}({})", names[u as usize].0, a.join(", "))
        }
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
    eval_shader_with(ir, domain, None)
}

/// [`eval_shader`] with user WGSL (`--inline`). Its three versions of each
/// function need every op library, so all are included then.
pub fn eval_shader_with(ir: &Ir, domain: Domain, inline: Option<&crate::inline::InlineWgsl>) -> String {
    // The code render's compiled field runs (long sums balanced).
    let balanced = compiled::generated_ir(ir);
    let ir = balanced.as_ref().unwrap_or(ir);
    let lib = match inline {
        Some(_) => libraries(&[Domain::Scalar, Domain::Interval, Domain::Affine]),
        None => libraries(&[domain]),
    };
    let mut eval = emit_evaluator(ir, domain);
    if !reroll::plan(ir).loops.is_empty() {
        eval = format!("var<private> g_field_work: u32;\n{}{eval}", reroll::support(false));
    }
    let user = inline.map_or(String::new(), |i| i.text.clone());
    let uniforms = crate::layout::EvalBlock::wgsl();
    template::splice(template::EVAL, &[("uniforms", &uniforms), ("library", &lib), ("inline", &user), ("evaluator", &eval), ("call", &eval_call(domain))])
        .expect("the eval template has its markers")
}

#[cfg(test)]
mod tests {
    use super::Domain;

    /// A constant's f32 ends enclose it, and are normal f32 (lavapipe
    /// flushes subnormals to zero): a tiny constant gets [0, 2^-126].
    #[test]
    fn constant_enclosures_have_normal_ends() {
        for c in [0.3, -7.1, 1e-30, 3e38, 1.5, 0.0, -2e-39, 1e-40, 1e-45] {
            let (_, lo, hi) = super::f32_enclosure(c);
            assert!(f64::from(lo) <= c && c <= f64::from(hi), "{c}: [{lo}, {hi}]");
            for e in [lo, hi] {
                assert!(e == 0.0 || e.is_normal() || e.is_infinite(), "{c}: end {e} is subnormal");
            }
        }
        assert_eq!(super::f32_enclosure(1e-40).1..super::f32_enclosure(1e-40).2, 0.0..f32::MIN_POSITIVE);
    }

    /// The op libraries choose with `select`, never branch: lavapipe runs
    /// both sides of a branch anyway, and branches cost its compiler far
    /// more (`@city` compiled in RAA: 145 s at 256² with a branchy affine
    /// min and max, 16 s without; README, "Compiled or tape").
    #[test]
    fn the_op_libraries_are_branch_free() {
        let derivative = [include_str!("../../templates/domains/derivative.wgsl"), include_str!("../../templates/domains/derivative_affine.wgsl")];
        let libraries = [Domain::Scalar, Domain::Interval, Domain::Affine].map(Domain::library);
        for (i, lib) in libraries.iter().chain(&derivative).enumerate() {
            for line in lib.lines().map(|l| l.split("//").next().unwrap_or("")) {
                let words: Vec<&str> = line.split(|c: char| !c.is_alphanumeric() && c != '_').collect();
                for branch in ["if", "else", "switch", "loop", "for", "while"] {
                    assert!(!words.contains(&branch), "library {i} branches: {line}");
                }
            }
        }
    }
}
