//! The emitter: IR → straight-line WGSL (`let v3 = ia_mul(v1, v2);`)
//! against a number domain's op library; the domain only decides the
//! prefix, the type and how constants are written. Runs of same-shaped
//! terms become loops ([`super::term_loops`]) and, on a ray, nodes of low
//! degree come from their polynomials along it ([`super::ray_forms`]).

use super::ray_forms;
use super::term_loops::{self, emit::LoopEmitter, emit::Tiles};
use crate::codegen::{affine_literal, divide_by_literal, f32_enclosure, libraries, lit, template};
use crate::ir::{display_limited, Domain, Ir, NodeId, Op};
use crate::layout::GpuBlock;
use std::fmt::Write;

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
    /// A value a loop reads from its table (`let v{id}`), whose slope is 0;
    /// `point` is its f32 value (what the scalar domain reads) where the
    /// table gives it ([`super::term_loops::Loop::point_first`]).
    Slot { id: NodeId, point: Option<String> },
    Begin { acc: NodeId, seed: Option<NodeId> },
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
/// terms become loops ([`term_loops`]).
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
    let plan = term_loops::plan(ir);
    let looped = !plan.is_empty();
    let lists = match tiles {
        Tiles::Off => None,
        _ => term_loops::lists::lists(ir, &plan),
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
    let nn = crate::analysis::nonneg::nonneg(ir);
    let mut loops = LoopEmitter { ir, domain, nn: &nn, fresh: ir.nodes.len() as NodeId };
    let mut restricted: Vec<String> = Vec::new();
    for id in ir.live() {
        if plan.skips(id) {
            continue;
        }
        if let Some(h) = plan.horner_at(id) {
            loops.emit_horner(out, h, &mut hook);
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


/// The right-hand side of `let v{id} = …;` for one node (odd powers first
/// write their square-and-multiply chain into `out`); `nn` says which
/// nodes are never negative ([`nonneg`]; ids past it are not known to be).
pub(crate) fn value_rhs(out: &mut String, domain: Domain, id: NodeId, op: Op, ir: &Ir, nn: &[bool]) -> String {
    named_rhs(out, domain, id, op, ir, nn, &Names::VALUES)
}

/// The names a node's right-hand side reads and writes: `{node}{id}` for
/// node `id`, `{temp}{id}_…` for its power chain's steps, and the
/// variables x, y, z and t.
pub(crate) struct Names {
    pub node: &'static str,
    pub temp: &'static str,
    pub vars: [&'static str; 4],
}

impl Names {
    /// The evaluator's own values, `v{id}`.
    pub const VALUES: Names = Names { node: "v", temp: "w", vars: ["x", "y", "z", "t"] };
}

/// [`value_rhs`] under other names.
pub(crate) fn named_rhs(out: &mut String, domain: Domain, id: NodeId, op: Op, ir: &Ir, nn: &[bool], names_of: &Names) -> String {
    let names = &ir.externs;
    let p = domain.prefix();
    let v = |n: NodeId| format!("{}{n}", names_of.node);
    let w = names_of.temp;
    match op {
        Op::Const(c) => {
            let (n, lo, hi) = f32_enclosure(c);
            match domain {
                Domain::Interval if lo != hi => format!("vec2<f32>({}, {})", lit(lo), lit(hi)),
                Domain::Affine if lo != hi => affine_literal(lo, hi),
                _ => format!("{p}_const({})", lit(n)),
            }
        }
        Op::Var(var) => names_of.vars[var as usize].into(),
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
            let _ = writeln!(out, "    let {w}{id}_q = {p}_sqr({});", v(a));
            if n == 4 { format!("{p}_sqr({w}{id}_q)") } else { emit_odd_power(out, p, &format!("{w}{id}"), &format!("{w}{id}_q"), n / 2) }
        }
        Op::PowI(a, n) => emit_odd_power(out, p, &format!("{w}{id}"), &v(a), n),
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
#[cfg(test)]
pub fn eval_shader(ir: &Ir, domain: Domain) -> String {
    eval_shader_with(ir, domain, None)
}

/// [`eval_shader`] with user WGSL (`--inline`). Its three versions of each
/// function need every op library, so all are included then.
pub fn eval_shader_with(ir: &Ir, domain: Domain, inline: Option<&crate::inline::InlineWgsl>) -> String {
    // The code render's compiled field runs (long sums balanced).
    let balanced = super::generated_ir(ir);
    let ir = balanced.as_ref().unwrap_or(ir);
    let lib = match inline {
        Some(_) => libraries(&[Domain::Scalar, Domain::Interval, Domain::Affine]),
        None => libraries(&[domain]),
    };
    let mut eval = emit_evaluator(ir, domain);
    if !term_loops::plan(ir).is_empty() {
        eval = format!("var<private> g_field_work: u32;\n{}{eval}", term_loops::support(false));
    }
    let user = inline.map_or(String::new(), |i| i.text.clone());
    let uniforms = crate::layout::EvalBlock::wgsl();
    template::eval(&[("uniforms", &uniforms), ("library", &lib), ("inline", &user), ("evaluator", &eval), ("call", &eval_call(domain))])
}

