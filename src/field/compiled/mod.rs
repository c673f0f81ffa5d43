//! The compiled field source: a formula's IR generated into WGSL. It
//! provides what a traversal calls: the scalar `field(p)` and, for
//! bisection, the inclusion functions (`cell_range`, `cell_enclosure`,
//! `slab_range`) with level-set CSG selection.
//!
//! The bisection traversal only ever sees ranges (`vec2<f32>`): which
//! number domain produced them, and how several surfaces with `where`
//! conditions were combined, is decided here.

pub(crate) mod balance;
pub(crate) mod derivative;
mod emit;
mod midpoint;
mod ray_forms;
mod ray_polys;
pub(crate) mod source;
pub(crate) mod term_loops;

pub(crate) use emit::{emit_evaluator_all, eval_shader_with};
#[cfg(test)]
pub(crate) use emit::{emit_evaluator, eval_shader};
pub(crate) use emit::{emit_evaluator_on, value_rhs, Hook};
pub(crate) use term_loops::emit::Tiles;

use crate::codegen::{libraries, libraries_with};
use crate::ir::Domain;
use ray_forms::RayForms;

/// Whether an IA kernel bisecting `ir` compiled takes polynomial nodes of
/// degree 3 to 6 from the ray (`ray_polys`): what `choose_algebra` asks.
pub(crate) fn takes_ray_polynomials(ir: &Ir) -> bool {
    ray_forms::ray_nodes(ir).is_some_and(|r| r.has_polynomials())
}
use crate::inline::InlineWgsl;
use crate::ir::{Ir, NodeId, Op};
use std::fmt::Write;

/// The layout of a CSG formula's outputs: every surface's f and its
/// conditions, in one array.
struct Csg {
    outputs: Vec<NodeId>,
    /// Per surface: index of f, and (index of g, less) per condition.
    surfaces: Vec<(usize, Vec<(usize, bool)>)>,
}

fn csg_layout(ir: &Ir) -> Csg {
    let mut outputs = Vec::new();
    let mut surfaces = Vec::new();
    for s in &ir.surfaces {
        outputs.push(s.f);
        let fi = outputs.len() - 1;
        let conds = s
            .conditions
            .iter()
            .map(|&(g, less)| {
                outputs.push(g);
                (outputs.len() - 1, less)
            })
            .collect();
        surfaces.push((fi, conds));
    }
    Csg { outputs, surfaces }
}

/// `surf_<p>(x, y, z, t) -> vec2<f32>`: the enclosure the traversal tests.
/// With CSG it is the range of the first surface whose f may reach an
/// isovalue and whose conditions are not excluded (g's enclosure entirely
/// on the wrong side rejects the surface); it records that surface in
/// `g_surface`; empty when none qualifies.
fn surface_fn(ir: &Ir, domain: Domain, safe: bool) -> String {
    let p = domain.prefix();
    let ty = domain.ty();
    if safe {
        return format!(
            "fn surf_{p}(x: {ty}, y: {ty}, z: {ty}, t: {ty}) -> vec2<f32> {{\n    \
             return select(vec2<f32>(-F.inf, F.inf), {p}_range(eval_{p}(x, y, z, t)), ra_safe(x, y, z, t));\n}}\n"
        );
    }
    if !ir.is_csg() {
        return format!("fn surf_{p}(x: {ty}, y: {ty}, z: {ty}, t: {ty}) -> vec2<f32> {{\n    return {p}_range(eval_{p}(x, y, z, t));\n}}\n");
    }
    let csg = csg_layout(ir);
    let mut out = emit_evaluator_all(ir, domain, &csg.outputs);
    let _ = writeln!(out, "fn surf_{p}(x: {ty}, y: {ty}, z: {ty}, t: {ty}) -> vec2<f32> {{");
    let _ = writeln!(out, "    let a = eval_{p}_all(x, y, z, t);");
    for (k, (fi, conds)) in csg.surfaces.iter().enumerate() {
        let mut test = format!("may_contain_iso({p}_range(a[{fi}]))");
        for &(gi, less) in conds {
            // Keep unless the condition is certainly false (NaN keeps).
            let _ = if less {
                write!(test, " && !({p}_range(a[{gi}]).x >= 0.0)")
            } else {
                write!(test, " && !({p}_range(a[{gi}]).y <= 0.0)")
            };
        }
        let _ = writeln!(out, "    if ({test}) {{ g_surface = {k}u; return {p}_range(a[{fi}]); }}");
    }
    out.push_str("    return vec2<f32>(1.0, -1.0);\n}\n");
    out
}

/// `field(p)`: the scalar function of the current surface (`g_surface`).
fn scalar_fn(ir: &Ir) -> String {
    if !ir.is_csg() {
        return SCALAR_FIELD.into();
    }
    let csg = csg_layout(ir);
    let mut out = emit_evaluator_all(ir, Domain::Scalar, &csg.outputs);
    out.push_str("fn field(p: vec3<f32>) -> f32 {\n    let a = eval_s_all(p.x, p.y, p.z, F.time);\n    switch (g_surface) {\n");
    for (k, (fi, _)) in csg.surfaces.iter().enumerate().skip(1) {
        let _ = writeln!(out, "        case {k}u: {{ return a[{fi}]; }}");
    }
    let _ = writeln!(out, "        default: {{ return a[{}]; }}\n    }}\n}}", csg.surfaces[0].0);
    out
}

/// The render kernel's inclusion functions for `domain` over a compiled
/// formula: its `surf_<p>` (with CSG selection), its scalar `field(p)`, the
/// `enclosures` and `cell_enclosure` built on them, and the scalar
/// field at a point of a ray, `field_ray(o, dir, s)`, after the ray's
/// `field_begin_ray`: in the interval domain with the nodes of degree ≤ 2
/// taken from the ray (`ray_forms`), elsewhere `field(o + dir s)`.
/// `safe`: the kernel reads ranges without the NaN test and checks its
/// inputs with `ra_safe` ([`safe_radius`]). The per-pixel evaluations run a
/// tile's term lists (`tiles`: [`Tiles::Listed`]) where the kernel has them.
fn inclusion_tiled(ir: &Ir, domain: Domain, safe: bool, tiles: Tiles) -> String {
    let ray = if domain == Domain::Interval { ray_forms::ray_nodes(ir) } else { None };
    let on_ray = match &ray {
        Some(r) => format!("{}{}", emit_evaluator_on(ir, Domain::Scalar, Some(r), tiles), r.setup()),
        None => ray_forms::NO_RAY_FORMS.to_string(),
    };
    format!("{}\n{}\n{}{}{on_ray}", surface_fn(ir, domain, safe), scalar_fn(ir), enclosures(domain, tiles != Tiles::Off), cell_enclosure(ir, domain, ray.as_ref(), safe, tiles))
}

/// The input radius within which the affine forms of `ir` cannot overflow
/// ([`crate::analysis::magnitude`]), where the kernel reads ranges without the NaN
/// test: affine values of a single surface with interval slopes (affine
/// slopes, of polynomials of low degree, would need their own bound).
pub(crate) fn safe_radius(ir: &Ir, domain: Domain) -> Option<f64> {
    let applies = domain == Domain::Affine && !ir.is_csg() && derivative::slope_domain(ir, domain) == Domain::Interval;
    applies.then(|| crate::analysis::magnitude::safe_radius(ir)).flatten()
}

/// `ra_safe(x, y, z, t)`: whether the inputs of an affine evaluation (the
/// forms' R = |x0| + |x1| + x2, and every parameter the formula reads) are
/// within `radius`, where no form can overflow ([`safe_radius`]). Compared
/// on the bits of the non-negative magnitudes, so that a NaN input is not
/// within (lavapipe folds NaN comparisons).
fn safe_fn(ir: &Ir, radius: f64) -> String {
    let bits = (radius as f32).to_bits();
    let mut params: Vec<u32> = ir.live().iter().filter_map(|&n| if let Op::Param(i) = ir.nodes[n as usize] { Some(i) } else { None }).collect();
    params.sort_unstable();
    params.dedup();
    let p: String = params.iter().map(|i| format!(" && bitcast<u32>(abs(iso_param({i}u))) <= {bits}u")).collect();
    format!(
        "// Inputs within {radius:e} keep every form of this formula finite (src/analysis/magnitude.rs):\n\
         // ranges are read without the NaN test (affine_range_bounded.wgsl), and past it an enclosure is the whole line.\n\
         fn ra_safe(x: vec3<f32>, y: vec3<f32>, z: vec3<f32>, t: vec3<f32>) -> bool {{\n    \
         let m = abs(vec4<f32>(x.x, y.x, z.x, t.x)) + abs(vec4<f32>(x.y, y.y, z.y, t.y)) + abs(vec4<f32>(x.z, y.z, z.z, t.z));\n    \
         return all(bitcast<vec4<u32>>(m) <= vec4<u32>({bits}u)){p};\n}}\n"
    )
}

/// The traversal's enclosures in `domain`, over any field that provides
/// `surf_<p>(x, y, z, t) -> vec2<f32>` (the compiled and the tape field
/// both do): `cell_range(o, dir, s0, s1)`, the enclosure of f over the ray
/// segment o + dir·[s0, s1], and `slab_range(eye, f, r, u, s, su, sv)`, the
/// enclosure over the frustum slab eye + s·(f + su·r + sv·u). In the affine
/// domain the ray depth s is the symbol e1, so x, y, z along a ray are
/// exact affine forms; across a slab su and sv go into e2. With `pad`, the
/// slab's box is widened by twice the gradient's step (`gradient_step_size`
/// in the bisection kernel) on every side: a hit's gradient stencil then
/// lies inside the boxes its tile's term lists were made over
/// (`templates/fields/loop_tiles.wgsl`).
pub fn enclosures(domain: Domain, pad: bool) -> String {
    let p = domain.prefix();
    let (forms, lift) = segment_forms(domain);
    let s_form = match domain {
        Domain::Affine => "vec3<f32>(0.5 * (s.x + s.y), 0.5 * (s.y - s.x), 0.0)",
        _ => "s",
    };
    let axis = |c: &str| {
        let a = format!("{p}_add({p}_const(eye.{c}), {p}_mul(S, {p}_add({p}_const(f.{c}), {p}_add({p}_mul(U_, {p}_const(r.{c})), {p}_mul(V_, {p}_const(u.{c}))))))");
        if pad { format!("{p}_add({a}, PAD)") } else { a }
    };
    let pad = if pad { format!("let PAD = {lift}(vec2<f32>(-2.0, 2.0) * gradient_step_size());\n    ") } else { String::new() };
    format!(
        "fn cell_range(o: vec3<f32>, dir: vec3<f32>, s0: f32, s1: f32) -> vec2<f32> {{\n{forms}\n    return surf_{p}(X, Y, Z, {p}_const(F.time));\n}}\n\n\
fn slab_range(eye: vec3<f32>, f: vec3<f32>, r: vec3<f32>, u: vec3<f32>, s: vec2<f32>, su: vec2<f32>, sv: vec2<f32>) -> vec2<f32> {{\n    \
let S = {s_form};\n    let U_ = {lift}(su);\n    let V_ = {lift}(sv);\n    {pad}\
return surf_{p}({}, {}, {}, {p}_const(F.time));\n}}\n",
        axis("x"),
        axis("y"),
        axis("z"),
    )
}

/// The box X, Y, Z of the ray segment o + dir·[s0, s1] in `domain` (WGSL
/// statements), and the function lifting an interval into it.
pub(crate) fn segment_forms(domain: Domain) -> (&'static str, &'static str) {
    match domain {
        Domain::Interval => (
            "    let a = o + dir * s0;\n    let b = o + dir * s1;\n    let lo = min(a, b);\n    let hi = max(a, b);\n    \
             let X = vec2<f32>(lo.x, hi.x);\n    let Y = vec2<f32>(lo.y, hi.y);\n    let Z = vec2<f32>(lo.z, hi.z);",
            "vec2<f32>",
        ),
        Domain::Affine => (
            "    let sc = 0.5 * (s0 + s1);\n    let sr = 0.5 * (s1 - s0);\n    let c = o + dir * sc;\n    let r = dir * sr;\n    \
             let X = vec3<f32>(c.x, r.x, 0.0);\n    let Y = vec3<f32>(c.y, r.y, 0.0);\n    let Z = vec3<f32>(c.z, r.z, 0.0);",
            "ra_from_ia",
        ),
        Domain::Scalar => unreachable!("the traversal needs an inclusion domain"),
    }
}

/// `cell_enclosure(o, dir, s0, s1, slope)`, the one enclosure call of the
/// bisection: f and its slope along the ray over the segment, the slope
/// dropped (the whole line) without `slope` or for a formula of several
/// surfaces, which has no single slope. Always the derivative form, because
/// lavapipe runs both arms of a branch under a mask: a `cell_range` arm
/// beside it was paid for on every cell (the Barth decic's frame is a
/// sixth shorter without it). With slopes it is `evald_<p>`'s code under this name
/// ([`derivative::emit_cell_enclosure`]). (The tape field has its own: one
/// interpreter run.)
fn cell_enclosure(ir: &Ir, domain: Domain, ray: Option<&RayForms>, safe: bool, tiles: Tiles) -> String {
    let p = domain.prefix();
    let (forms, _) = segment_forms(domain);
    if ir.is_csg() {
        return format!(
            "fn cell_enclosure(o: vec3<f32>, dir: vec3<f32>, s0: f32, s1: f32, slope: bool) -> vec4<f32> {{\n{forms}\n    \
             return vec4<f32>(surf_{p}(X, Y, Z, {p}_const(F.time)), -F.inf, F.inf);\n}}\n"
        );
    }
    derivative::emit_cell_enclosure(ir, domain, forms, ray, safe, tiles)
}

/// The scalar field of a single-surface formula.
const SCALAR_FIELD: &str = "fn field(p: vec3<f32>) -> f32 { return eval_s(p.x, p.y, p.z, F.time); }\n";

/// What an evaluation of the compiled field costs the traversal: the loop
/// iterations of its rerolled runs ([`term_loops`]; none for a formula
/// written out, which adds nothing to an invocation's loop count; the
/// sphere tracer keeps its steps within the cap with it), and whether the
/// work limit refused one (the pixel is then reported). It is one field
/// everywhere (`field_tree`: the scene's changes with its slab).
/// `bundle`: the loops' work is counted per SIMD bundle ([`term_loops::support`]).
fn field_cost(ir: &Ir, bundle: bool) -> String {
    let plan = term_loops::plan(ir);
    let (support, iters, exhausted) = match plan.is_empty() {
        true => ("fn field_entry(li: u32) {}\n".to_string(), 0, "false"),
        false => (term_loops::support(bundle), plan.iterations(), "g_field_exhausted"),
    };
    format!(
        "{support}fn field_cost() -> u32 {{ return {iters}u; }}\nfn field_exhausted() -> bool {{ return {exhausted}; }}\n\
         fn field_tree() -> u32 {{ return 0u; }}\n"
    )
}

/// `ir` as the compiled field and the `eval` kernel generate it, where it
/// differs: the monomials of a sum that mixes many of them with other
/// terms gathered into one polynomial node ([`term_loops::monomials`]), long
/// sums as balanced trees ([`super::balance`]) unless a loop computes part
/// of them.
pub(crate) fn generated_ir(ir: &Ir) -> Option<Ir> {
    let (gathered, plan) = term_loops::written_plan(ir);
    let written = gathered.as_ref().unwrap_or(ir);
    balance::balanced(written, |n| plan.skips(n) || plan.loop_at(n).is_some() || plan.horner_at(n).is_some()).or(gathered)
}

/// The compiled field for a traversal that needs enclosures in `domain`
/// (bisection) or, with `None`, only the scalar field (sphere tracing).
/// `inline` user functions need every op library (their three versions
/// call into all of them), so all are included then. `bundle`: its loops'
/// work is counted per SIMD bundle (bisection on a device with subgroups).
/// `lists`: a bisection kernel with the tile pass, where rerolled `min` and
/// `max` loops run per-tile term lists ([`term_loops::lists`]; not with
/// `inline` WGSL, whose hooks the kernel leaves to the user).
pub(crate) fn field_code(ir: &Ir, domain: Option<Domain>, inline: Option<&InlineWgsl>, bundle: bool, lists: bool) -> String {
    let balanced = generated_ir(ir);
    let ir = balanced.as_ref().unwrap_or(ir);
    let lists = match (lists, domain, inline) {
        (true, Some(_), None) => term_loops::lists::lists(ir, &term_loops::plan(ir)),
        _ => None,
    };
    let (listed, record) = match lists {
        Some(_) => (Tiles::Listed, Tiles::Record),
        None => (Tiles::Off, Tiles::Off),
    };
    let all = [Domain::Scalar, Domain::Interval, Domain::Affine];
    // Where the affine forms cannot overflow, ranges are read without the NaN test.
    let radius = match (inline, domain) {
        (None, Some(d)) => safe_radius(ir, d),
        _ => None,
    };
    let mut out = match (inline, domain) {
        (Some(_), _) => libraries(&all),
        (None, Some(d)) => libraries_with(&[Domain::Scalar, d], radius.is_none()),
        (None, None) => libraries(&[Domain::Scalar]),
    };
    if let Some(d) = domain {
        out.push_str(&derivative::library(d));
    }
    if let Some(user) = inline {
        let _ = write!(out, "\n// ---- User WGSL (--inline {}): functions callable from the formula and hooks.\n{}\n", user.path, user.text);
    }
    out.push_str(&field_cost(ir, bundle));
    out.push_str(&emit_evaluator_on(ir, Domain::Scalar, None, listed));
    out.push_str(super::UNTILED_FIELD_HOOKS);
    match &lists {
        Some(l) => out.push_str(&l.support()),
        None => out.push_str(super::UNSHORTENED_FIELD_HOOKS),
    }
    let Some(d) = domain else {
        out.push_str(SCALAR_FIELD);
        return out;
    };
    if let Some(radius) = radius {
        out.push_str(&safe_fn(ir, radius));
    }
    // The domain's evaluator serves the tile pass's slab enclosures.
    out.push_str(&emit_evaluator_on(ir, d, None, record));
    out.push_str(&inclusion_tiled(ir, d, radius.is_some(), listed));
    out
}

/// The `eval` kernel over bisection's interval cells on rays (the hook the
/// tests use to check the cell enclosure, with the nodes it takes from the
/// ray, against f64 samples on the device). Four boxes a query, 32
/// floats: o, dir, s_ref, len (the ray and what `field_begin_ray` gets),
/// then the cell's s0, s1. Results: box 4k the value's range over the
/// cell, 4k + 1 the slope's along dir, 4k + 2 the scalar field on the ray
/// at s0 and at s1, 4k + 3 f at the midpoint from the enclosure's pass
/// (`g_cell_f_mid`, where [`midpoint::fused`]; else 0) and from the scalar
/// field `field` there. The render kernel's frame block is replaced by the
/// fields the field code reads and writes.
#[cfg(test)]
pub(crate) fn ray_cell_eval_shader(ir: &Ir) -> String {
    use crate::layout::GpuBlock;
    let frame = "struct CellEvalFrame { time: f32, inf: f32 }\nvar<private> F: CellEvalFrame;\nvar<private> g_field_work: u32;\nvar<private> g_cell_s_mid: f32;\nvar<private> g_cell_f_mid: f32;\n";
    let evaluator = format!("{frame}{}", field_code(ir, Some(Domain::Interval), None, false, false));
    let call = "    F = CellEvalFrame(0.0, iso_inf());\n    let k = (i / 4u) * 32u;\n    \
                let o = vec3<f32>(boxes[k], boxes[k + 1u], boxes[k + 2u]);\n    \
                let dir = vec3<f32>(boxes[k + 3u], boxes[k + 4u], boxes[k + 5u]);\n    \
                field_begin_ray(o, dir, boxes[k + 6u], boxes[k + 7u]);\n    let s0 = boxes[k + 8u];\n    let s1 = boxes[k + 9u];\n    \
                let m = 0.5 * (s0 + s1);\n    g_cell_s_mid = m;\n    g_cell_f_mid = 0.0;\n    let c = cell_enclosure(o, dir, s0, s1, true);\n    \
                let mid = vec2<f32>(g_cell_f_mid, field(o + dir * m));\n    \
                let ends = select(vec2<f32>(field_ray(o, dir, s0), field_ray(o, dir, s1)), mid, i % 4u == 3u);\n    \
                return select(select(ends, c.zw, i % 4u == 1u), c.xy, i % 4u == 0u);";
    crate::codegen::template::eval(&[("uniforms", crate::layout::EvalBlock::wgsl().as_str()), ("library", ""), ("inline", ""), ("evaluator", &evaluator), ("call", call)])
}

