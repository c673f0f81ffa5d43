//! The tape field source's WGSL: the interpreter of
//! `templates/fields/tape.wgsl` instantiated for the scalar domain (the
//! field `field(p)`) and for the traversal's inclusion domain (the
//! enclosures), around the tape buffer of the field group. Nothing here
//! depends on the formula itself: the code is a function of the domain and
//! of the operation groups and register file the kernel is built for
//! ([`features`]), so every formula within them is a buffer
//! ([`super`]).

use super::{features, Code};
use crate::codegen::{libraries, template};
use crate::field::compiled::{self, derivative};
use crate::ir::Domain;

/// The interpreter template, written against `T` and `op_*`.
pub const TAPE: &str = include_str!("../../../templates/fields/tape.wgsl");
/// Bisection's per-tile shortening of a tape with min or max.
pub const TAPE_TILES: &str = include_str!("../../../templates/fields/tape_tiles.wgsl");

/// Bisection's per-tile lists: their bindings and `TAPE_TILES`, its
/// backward pass taking [`features::keep_step`] entries an iteration.
fn tape_tiles(features: u32) -> String {
    use super::source::{TAPE_LISTS, TAPE_LIST_COUNTS, TAPE_NOTES};
    let body: String = written_out(TAPE_TILES, EACH_KEEP_STEP, features::keep_step(features)).map(|line| line + "\n").collect();
    format!("{}{body}", crate::bindings::declarations(&[&TAPE_LISTS, &TAPE_LIST_COUNTS, &TAPE_NOTES]))
}

/// The marker of the backward pass's lines written once for each entry K
/// of an iteration after the first.
const EACH_KEEP_STEP: &str = "// each backward step K";

/// The interpreter for `domain`: `T` becomes the domain's type, `op_x` its
/// operation `<p>_x`, and a name ending in `_T` ends in `_<p>` instead, so
/// several domains' interpreters live in one module. The step keeps the
/// cases of the operation groups in `features` only.
pub fn instantiate(domain: Domain, features: u32) -> String {
    let (p, ty) = (domain.prefix(), domain.ty());
    let mut out = String::with_capacity(TAPE.len() + 512);
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        if word == "T" {
            out.push_str(ty);
        } else if let Some(rest) = word.strip_prefix("op_") {
            out.push_str(&format!("{p}_{rest}"));
        } else if let Some(stem) = word.strip_suffix("_T") {
            out.push_str(&format!("{stem}_{p}"));
        } else {
            out.push_str(word);
        }
        word.clear();
    };
    let kept: Vec<String> = unrolled(features).filter(|l| keeps_line(l, features)).collect();
    for line in case_tree(kept) {
        let line = line.as_str();
        // Comments pass through untouched.
        let (code, comment) = line.find("//").map_or((line, ""), |i| line.split_at(i));
        for ch in code.chars() {
            if ch.is_ascii_alphanumeric() || ch == '_' {
                word.push(ch);
            } else {
                flush(&mut word, &mut out);
                out.push(ch);
            }
        }
        flush(&mut word, &mut out);
        out.push_str(comment);
        out.push('\n');
    }
    out
}

/// The step's cases (`if (code == TAPE_X) { … }` lines, with the comments
/// among them) as a binary search on the code: a lane's step tests about
/// log2 of the cases' count instead of every case. The cases stay behind
/// `if`s, so a bundle whose lanes run one instruction runs one case.
fn case_tree(lines: Vec<String>) -> Vec<String> {
    let is_case = |l: &String| case_name(l).is_some();
    let (Some(first), Some(last)) = (lines.iter().position(is_case), lines.iter().rposition(is_case)) else { return lines };
    let mut cases: Vec<(u32, String)> = lines[first..=last]
        .iter()
        .filter_map(|l| case_name(l).map(|n| (Code::from_wgsl_name(n).expect("the template's cases are codes") as u32, l.trim().to_string())))
        .collect();
    cases.sort_by_key(|c| c.0);
    let mut tree = Vec::new();
    search(&cases, 1, &mut tree);
    let mut out = lines[..first].to_vec();
    out.extend(tree);
    out.extend_from_slice(&lines[last + 1..]);
    out
}

/// Writes the cases (sorted by code) as nested `if`s at indent `depth`.
fn search(cases: &[(u32, String)], depth: usize, out: &mut Vec<String>) {
    let pad = "    ".repeat(depth);
    if cases.len() <= 2 {
        out.extend(cases.iter().map(|(_, l)| format!("{pad}{l}")));
        return;
    }
    let (low, high) = cases.split_at(cases.len() / 2);
    let name = case_name(&high[0].1).expect("a case");
    out.push(format!("{pad}if (code < {name}) {{"));
    search(low, depth + 1, out);
    out.push(format!("{pad}}} else {{"));
    search(high, depth + 1, out);
    out.push(format!("{pad}}}"));
}

/// The marker of the interpreter loop's lines written once for each step K
/// after the first (`eK`, `i + Ku`).
const EACH_STEP: &str = "// each unrolled step K";

/// The template's lines with the unrolled steps of a kernel with
/// `features` written out.
fn unrolled(features: u32) -> impl Iterator<Item = String> {
    written_out(TAPE, EACH_STEP, features::unroll(features))
}

/// The lines of `template`, each line ending in `marker` written once for
/// every K from 1 to `step` - 1 (`eK` becoming `e1`, `Ku` becoming `1u`, …).
fn written_out<'a>(template: &'a str, marker: &'a str, step: u32) -> impl Iterator<Item = String> + 'a {
    template.lines().flat_map(move |line| match line.strip_suffix(marker) {
        Some(code) => (1..step).map(|k| code.trim_end().replace("eK", &format!("e{k}")).replace("Ku", &format!("{k}u"))).collect(),
        None => vec![line.to_string()],
    })
}

/// The code of a case of the interpreter's step, a template line
/// `if (code == TAPE_X) { r = op_x(a, b); }`.
fn case_name(line: &str) -> Option<&str> {
    let rest = line.trim().strip_prefix("if (code == ")?;
    let (name, body) = rest.split_once(") { r = ")?;
    body.ends_with("; }").then_some(name)
}

/// Whether the template line `line` stays in a kernel with `features`: a
/// case of `TAPE_X` only when X's group is among them, a line marked
/// `// if GROUP…` only when one of those groups is.
fn keeps_line(line: &str, features: u32) -> bool {
    if let Some((_, groups)) = line.trim_end().rsplit_once("// if ") {
        let wanted = groups.split(' ').fold(0, |acc, g| acc | features::by_name(g));
        if wanted & features == 0 {
            return false;
        }
    }
    let Some(name) = case_name(line) else { return true };
    Code::from_wgsl_name(name).is_none_or(|c| c.group() & !features == 0)
}

/// The interpreter in `domain` with its declarations, for kernels of its
/// own (the eval kernel, tests): `surf_<p>` and `evald_<p>` over the tape
/// in `@group(1) @binding(0)`. The kernel provides `iso_inf`, `iso_param`,
/// the op libraries and `g_field_work`.
pub fn interpreter(domain: Domain, features: u32) -> String {
    format!("{}{}", prelude(features, false), instantiate(domain, features))
}

/// Whether a bisection kernel for tapes with `features` shortens the tape
/// per tile: only min and max make parts of a formula dead in a region.
pub fn shortens(features: u32) -> bool {
    features & features::MINMAX != 0
}

/// Bytes of a tile's choice notes (two bits a slot), and as many for the
/// notes of the slab being enclosed.
pub const NOTE_BYTES_PER_TILE: u64 = 2 * (super::TAPE_CHOICE_SLOTS as u64 / 16 * 4);

/// Most bytes of a tape's per-tile lists in one dispatch: tiles past it run
/// the whole tape (the lists' allocator says so; the picture is the same
/// surface).
pub const TAPE_LISTS_MAX_BYTES: u64 = 32 << 20;

/// The work limit, counted per invocation: a lane cannot see what the
/// other lanes of its SIMD bundle ran, so it gets an eighth of lavapipe's
/// loop cap (`TAPE_WORK_LIMIT`).
const WORK_PER_LANE: &str = "
fn field_entry(li: u32) {}
var<private> g_work_limit: u32 = TAPE_WORK_LIMIT;
// Bisection's tile pass runs no traversal beside the interpreter: it may
// spend more (tape_tiles.wgsl).
fn tape_tile_pass_limit() { g_work_limit = TAPE_TILE_PASS_WORK_LIMIT; }
// Whether an interpreter run of `iters` loop iterations is within the limit
// (and counts it).
fn tape_admits(iters: u32) -> bool {
    if (g_field_work + iters > g_work_limit) { return false; }
    g_field_work = g_field_work + iters;
    return true;
}
";

/// The tape's work limit per SIMD bundle ([`crate::field::limits::BUNDLE_WORK_WGSL`]).
const TAPE_PER_BUNDLE: &str = "fn tape_admits(iters: u32) -> bool { return bundle_admits(iters); }\n\
    fn tape_tile_pass_limit() { g_work_limit = TAPE_TILE_PASS_BUNDLE_LIMIT; }\n";

/// Where the interpreter's instructions come from without per-tile lists:
/// the tape's programs themselves.
const WHOLE_TAPE: &str = "
fn tape_note_bits(slot: u32, c: u32) {}
fn tape_entry(i: u32) -> u32 { return i; }
fn tape_span(prog: u32) -> vec2<u32> { let h = tape_word(0u); return select(h.xy, h.zw, prog == 1u); }
";

/// With per-tile lists (`templates/fields/tape_tiles.wgsl`): the rays of a
/// tile run its list while `g_tape_list` names it.
const LISTED_TAPE: &str = "
var<private> g_tape_list: u32;
fn tape_entry(i: u32) -> u32 { return select(i, tape_lists[i], g_tape_list != 0u); }
fn tape_span(prog: u32) -> vec2<u32> {
    if (g_tape_list != 0u) {
        let b = g_tape_list - 4u + 2u * prog;
        return vec2<u32>(tape_lists[b], tape_lists[b + 1u]);
    }
    let h = tape_word(0u);
    return select(h.xy, h.zw, prog == 1u);
}
";

/// Declarations every tape kernel shares: the constants, the tape buffer
/// of the field group, the exhaustion flag and the work limit, and where
/// instructions come from (`lists`: per-tile lists).
fn prelude(features: u32, lists: bool) -> String {
    format!(
        "{}{}{}\n// The tape (src/field/tape): header, value program, derivative program,\n\
         // a texture of {w} texels a row (TapeData::texels).\n\
         {}{}{TAPE_STATE}{}",
        super::wgsl_constants(features),
        if features::bundle_work(features) { format!("{}{TAPE_PER_BUNDLE}", crate::field::limits::BUNDLE_WORK_WGSL) } else { WORK_PER_LANE.to_string() },
        if lists { tape_tiles(features) } else { String::new() },
        crate::bindings::declarations(&[&super::source::TAPE_CODE]),
        tape_word(super::source::TAPE_CODE.var, "0u"),
        if lists { LISTED_TAPE } else { WHOLE_TAPE },
        w = crate::scene::linear::TEXTURE_WIDTH,
    )
}

/// The flags and list constants every tape interpreter shares.
const TAPE_STATE: &str = "// Set when an evaluation was refused for the work limit: the pixel is reported.
var<private> g_tape_exhausted: bool;
// Set while bisection's tile pass records min/max choices (tape_tiles.wgsl).
var<private> g_tape_record: bool;
const TAPE_LIST_NOP: u32 = 0xffffffffu;
const TAPE_PC_MASK: u32 = 0x3fffffffu;
";

/// `tape_word(i)`: texel `base + i` of `texture`, TEXTURE_WIDTH texels a row.
fn tape_word(texture: &str, base: &str) -> String {
    let (mask, shift) = (crate::scene::linear::TEXTURE_WIDTH - 1, crate::scene::linear::TEXTURE_SHIFT);
    format!("fn tape_word(i: u32) -> vec4<u32> {{ let j = {base} + i; return textureLoad({texture}, vec2<u32>(j & {mask}u, j >> {shift}u), 0); }}\n")
}

/// The interpreter for another interpreter to run tapes with (a scene's
/// formula leaves): every tape in `texture` (a texture of
/// [`crate::scene::linear::TEXTURE_WIDTH`] texels a row), the one being run
/// starting at texel `g_tape_base`, its words relative to it; in each of
/// `domains`, for tapes within `features`, padded to the kernel's step.
/// The host provides `tape_admits(iters) -> bool` (its work limit) and the
/// op libraries; no per-tile lists, no choice notes.
pub fn embedded(domains: &[Domain], features: u32, texture: &str) -> String {
    let mut out = format!(
        "{}\n// The tape being run starts at texel g_tape_base of {texture}.\nvar<private> g_tape_base: u32;\n{}{TAPE_STATE}{WHOLE_TAPE}",
        super::wgsl_constants(features),
        tape_word(texture, "g_tape_base"),
    );
    for &d in domains {
        // Without the field's entry points (surf_*, evald_*): the host has its own.
        let code = instantiate(d, features);
        let cut = code.find(FIELD_ENTRIES).expect("the tape template marks its field entry points");
        out.push_str(&code[..cut]);
    }
    out
}

/// Where the template's field entry points (`surf_T`, `evald_T`) begin
/// (tests: `embedded_interpreters_leave_the_entry_points_out`).
const FIELD_ENTRIES: &str = "// The enclosure of f over the box: what `surf_*` is";

/// The scalar field and the hooks every field source provides.
const SCALAR_FIELD: &str = "
// The scalar field: the value program in f32. Past the work limit it is NaN
// (and the pixel is reported through field_exhausted).
fn field(p: vec3<f32>) -> f32 {
    tape_point_s(p.x, p.y, p.z, F.time);
    if (tape_run_s(0u) == TAPE_EXHAUSTED) { return iso_nan(); }
    return tape_reg_s(tape_word(1u).x);
}
// Loop iterations of one evaluation of the value program.
fn field_cost() -> u32 { return tape_word(2u).x + tape_word(0u).y / TAPE_UNROLL + tape_word(0u).y * TAPE_POW_PASSES; }
fn field_exhausted() -> bool { return g_tape_exhausted; }
// One field everywhere (see the scene's field_tree).
fn field_tree() -> u32 { return 0u; }
";

/// The tape field for a traversal that needs enclosures in `domain`
/// (bisection) or, with `None`, only the scalar field (sphere tracing), for
/// tapes within `features`.
pub fn field_code(domain: Option<Domain>, features: u32) -> String {
    let mut out = match domain {
        Some(d) => format!("{}{}", libraries(&[Domain::Scalar, d]), derivative::library(d)),
        None => libraries(&[Domain::Scalar]),
    };
    let lists = domain.is_some() && shortens(features);
    out.push_str(&prelude(features, lists));
    out.push_str(&instantiate(Domain::Scalar, features));
    out.push_str(SCALAR_FIELD);
    out.push_str(crate::field::UNTILED_FIELD_HOOKS);
    if !lists {
        out.push_str(crate::field::UNSHORTENED_FIELD_HOOKS);
    }
    if let Some(d) = domain {
        out.push_str(&instantiate(d, features));
        out.push_str(&compiled::enclosures(d, false));
        out.push_str(&cell_enclosure(d));
        // Bisection's cells start each ray's run with it (a compiled sum's
        // ray forms); a tape has none.
        out.push_str("fn field_begin_ray(o: vec3<f32>, dir: vec3<f32>, s_ref: f32, len: f32) {}\n");
    }
    out
}

/// The bisection's one enclosure call, `cell_enclosure(o, dir, s0, s1,
/// slope)`: one run of the interpreter, of the value or the derivative
/// program, where a value and a slope evaluator would inline two.
fn cell_enclosure(domain: Domain) -> String {
    let p = domain.prefix();
    let (forms, _) = compiled::segment_forms(domain);
    format!(
        "fn cell_enclosure(o: vec3<f32>, dir: vec3<f32>, s0: f32, s1: f32, slope: bool) -> vec4<f32> {{\n{forms}\n    \
         return tape_enclosure_{p}(X, Y, Z, {p}_const(F.time), {p}_const(dir.x), {p}_const(dir.y), {p}_const(dir.z), slope);\n}}\n"
    )
}

/// The `isotrace eval` kernel over a tape in `domain`: the same boxes and
/// results as [`crate::field::compiled::eval_shader`], with the tape in `@group(1)`, for
/// tapes within `features`.
pub fn eval_shader(domain: Domain, features: u32) -> String {
    let lib = match domain {
        Domain::Scalar => libraries(&[Domain::Scalar]),
        d => format!("{}{}", libraries(&[Domain::Scalar, d]), derivative::library(d)),
    };
    let interp = format!("var<private> g_field_work: u32;\n{}", interpreter(domain, features));
    let call = match domain {
        Domain::Scalar => "    return surf_s(x.x, y.x, z.x, t.x);",
        Domain::Interval => "    return surf_ia(x, y, z, t);",
        Domain::Affine => "    return surf_ra(ra_from_ia(x), ra_from_ia(y), ra_from_ia(z), ra_from_ia(t));",
    };
    use crate::layout::GpuBlock;
    let uniforms = crate::layout::EvalBlock::wgsl();
    template::eval(&[("uniforms", &uniforms), ("library", &lib), ("inline", ""), ("evaluator", &interp), ("call", call)])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_template_unrolls_as_the_host_pads() {
        for (f, n) in [(0, 1), (features::UNROLL_4, 4), (features::UNROLL_8, 8), (features::UNROLL_16, 16), (features::UNROLL_4 | features::UNROLL_16, 16)] {
            assert_eq!(instantiate(Domain::Scalar, f).matches("= tape_step_s(tape_entry(i").count() as u32, n);
            assert!(super::super::wgsl_constants(f).contains(&format!("const TAPE_UNROLL: u32 = {n}u;")));
        }
        assert_eq!(features::unroll(features::ALL), super::super::TAPE_UNROLL);
        // The tile pass's backward pass: one entry an iteration, four for
        // the longest tapes.
        for (f, n) in [(features::MINMAX, 1), (features::MINMAX | features::UNROLL_4, 1), (features::MINMAX | features::UNROLL_8, 4), (features::MINMAX | features::UNROLL_16, 4)] {
            assert_eq!(prelude(f, true).matches("k = tape_keep_entry(").count(), n, "{f:#x}");
            assert!(super::super::wgsl_constants(f).contains(&format!("const TAPE_KEEP_STEP: u32 = {n}u;")));
        }
    }

    /// Following the step's search with each code's value reaches that
    /// code's case and no other, for every set of groups.
    #[test]
    fn the_cases_search_finds_each_code() {
        // The case a code reaches in `lines` from line `at`, and the line after the block.
        fn walk(lines: &[&str], mut at: usize, code: u32, found: &mut Vec<String>) -> usize {
            while at < lines.len() {
                let l = lines[at].trim();
                if let Some(name) = l.strip_prefix("if (code < ").and_then(|r| r.strip_suffix(") {")) {
                    let bound = Code::from_wgsl_name(name).expect("a code") as u32;
                    // Both branches are walked; only the taken one collects.
                    let mut low = Vec::new();
                    let mut high = Vec::new();
                    let after_low = walk(lines, at + 1, code, &mut low);
                    assert_eq!(lines[after_low].trim(), "} else {");
                    let after_high = walk(lines, after_low + 1, code, &mut high);
                    assert_eq!(lines[after_high].trim(), "}");
                    found.extend(if code < bound { low } else { high });
                    at = after_high + 1;
                } else if l.starts_with('}') {
                    return at;
                } else {
                    if let Some(name) = case_name(l) {
                        if Code::from_wgsl_name(name).expect("a code") as u32 == code {
                            found.push(name.to_string());
                        }
                    }
                    at += 1;
                }
            }
            at
        }
        for f in [0, features::MINMAX, features::TRIG | features::DIV, features::ALL] {
            let code = instantiate(Domain::Interval, f);
            let step = &code[code.find("var r = ia_whole();").expect("the step")..code.find("if (g_tape_record && live)").expect("the step's end")];
            let lines: Vec<&str> = step.lines().skip(1).collect();
            let cases: Vec<&str> = lines.iter().filter_map(|l| case_name(l)).collect();
            for c in Code::ALL {
                let mut found = Vec::new();
                walk(&lines, 0, c as u32, &mut found);
                let expected: Vec<String> = cases.iter().filter(|n| **n == c.wgsl_name()).map(|n| n.to_string()).collect();
                assert_eq!(found, expected, "{f:#x}: {}", c.wgsl_name());
            }
            // About log2(cases) tests a step, not one a case.
            let depth = lines.iter().map(|l| l.len() - l.trim_start().len()).max().unwrap_or(0) / 4;
            assert!(cases.len() < 8 || depth <= 2 + cases.len().ilog2() as usize, "{f:#x}: depth {depth} for {} cases", cases.len());
        }
    }

    #[test]
    fn kernels_keep_the_cases_of_their_groups() {
        let cases = |f: u32| instantiate(Domain::Interval, f).lines().filter_map(case_name).count();
        // Every code but Nop (not written) and Whole (the initial value).
        assert_eq!(cases(features::ALL), 36);
        // Const, Neg, Add, Sub, Mul, Sqr; with input instructions, Input.
        assert_eq!(cases(0), 6);
        assert_eq!(cases(features::INPUTS), 7);
        assert_eq!(instantiate(Domain::Interval, features::PINNED).matches("g_in_ia").count(), 0);
        assert_eq!(instantiate(Domain::Interval, features::INPUTS).matches("g_regs_ia[0] = x;").count(), 0);
        assert_eq!(cases(features::POWERS | features::PARAMS), 8);
        assert_eq!(cases(features::SMALL_POWERS), 7);
        assert_eq!(cases(features::TRIG), 11);
        // The third and fourth operands are read inside the cases that have
        // them (clamp, mix, the multiply-adds; the slopes of min and max)
        // and by a list's picks (min and max only), never before the cases,
        // where every instruction would load them.
        let reads = |f: u32| {
            let k = instantiate(Domain::Interval, f);
            let step = &k[k.find("fn tape_step_ia(").expect("the step")..];
            let cases = step.lines().filter(|l| case_name(l).is_some());
            let in_cases = cases.map(|l| (l.matches("tape_c_ia(w)").count(), l.matches("tape_d_ia(w)").count())).fold((0, 0), |s, c| (s.0 + c.0, s.1 + c.1));
            let outside = step.lines().filter(|l| case_name(l).is_none() && !l.contains("(pick == ")).filter(|l| l.contains("tape_c_ia(w)") || l.contains("tape_d_ia(w)")).count();
            (in_cases, outside, step.matches("(pick == ").count())
        };
        assert_eq!(reads(features::TRIG | features::DIV), ((0, 0), 0, 0));
        assert_eq!(reads(features::MISC), ((1, 0), 0, 0));
        assert_eq!(reads(features::MINMAX), ((3, 2), 0, 2));
        assert_eq!(reads(features::MAD), ((2, 0), 0, 0));
        // Every group named by an `// if` line is one.
        for line in TAPE.lines().filter_map(|l| l.rsplit_once("// if ")) {
            assert!(line.1.split(' ').all(|g| features::by_name(g) != 0), "{}", line.1);
        }
        // Every case named in the template is a code.
        let mut named = 0;
        for name in TAPE.lines().filter_map(case_name) {
            assert!(Code::from_wgsl_name(name).is_some(), "{name}");
            named += 1;
        }
        assert_eq!(named, 36);
    }

    #[test]
    fn the_tile_pass_inlines_the_field_once() {
        // Each call site of a slab test inlines the whole field (an
        // interpreter, or the generated code): coarse and fine slabs share one.
        let calls = template::BISECT_TILES.lines().filter(|l| !l.trim_start().starts_with("//") && !l.contains("fn slab_may_hold")).map(|l| l.matches("slab_may_hold(").count()).sum::<usize>();
        assert_eq!(calls, 1);
    }

    #[test]
    fn instances_keep_no_generic_names() {
        for d in [Domain::Scalar, Domain::Interval, Domain::Affine] {
            let code: String = instantiate(d, features::ALL).lines().map(|l| l.split("//").next().unwrap_or("")).collect::<Vec<_>>().join("\n");
            assert!(!code.contains("op_") && !code.contains("_T(") && !code.contains(": T"), "{d:?}");
        }
    }

    #[test]
    fn embedded_interpreters_leave_the_entry_points_out() {
        let code = embedded(&[Domain::Scalar, Domain::Interval], features::ALL, "t");
        assert!(code.contains("fn tape_enclosure_ia(") && code.contains("fn tape_run_s("));
        assert!(!code.contains("fn surf_") && !code.contains("fn evald_"));
        assert_eq!(code.matches("fn tape_word(").count(), 1);
    }

    #[test]
    fn every_tape_kernel_validates() {
        for d in [Domain::Scalar, Domain::Interval, Domain::Affine] {
            crate::validate::validate(&eval_shader(d, features::ALL)).unwrap_or_else(|e| panic!("{d:?}: {e}"));
        }
    }
}
