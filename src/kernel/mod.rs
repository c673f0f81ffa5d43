//! Render kernel assembly: one traversal × one field source, spliced into
//! `templates/render.wgsl` around the shared frame, camera, pixel and
//! shading code. This is the only place a render shader is put together;
//! the GPU side only runs what it gets here.
//!
//! The two axes are independent. A traversal template calls nothing of the
//! field but `field(p)` (and, bisecting, the enclosures `cell_enclosure`
//! and `slab_range`); a field source provides exactly those,
//! generated (a compiled formula) or as an interpreter over buffers bound in
//! the field group (`@group(1)`), without touching traversal code.

pub mod bindings;

use crate::codegen::template;
use crate::field::{CodeRequest, FieldSource};
use crate::inline::InlineWgsl;
use crate::ir::Ir;
use crate::layout::{self, BisectBlock, SphereBlock};
use crate::render::{BisectOptions, Modalities, RootSearch, SphereFeatures, Traversal};
use std::fmt::Write;
use std::ops::Range;

/// Largest render kernel handed to naga and the driver: 500 KB of WGSL
/// code ([`Kernel::code_bytes`]: comment lines, which cost the driver
/// nothing, aside), about 3 times the largest catalog kernel (`@city` with
/// RAA, 156 KB).
/// lavapipe's compile time grows faster than the shader (the largest
/// catalog kernels already take long, and a kernel half again past this
/// limit did not finish at all in a long wait), so past this a render
/// would sit silent for a very long time; a formula that gets here is one
/// to simplify.
pub const MAX_SHADER_BYTES: usize = 500_000;

/// An assembled render kernel.
#[derive(Debug, Clone)]
pub struct Kernel {
    /// The complete WGSL module (not yet validated).
    pub wgsl: String,
    /// Its compute entry points: the per-pixel `main` first, then the
    /// traversal's pre-pass (`tiles`) if any, then the field's pre-passes.
    pub entries: Vec<&'static str>,
    /// Where the user's `--inline` WGSL sits in `wgsl`, to map naga's
    /// diagnostics back into the user's file.
    pub inline: Option<(Range<usize>, InlineWgsl)>,
}

impl Kernel {
    /// The bytes of `wgsl` that are code: every line but those holding only
    /// a comment (the templates' documentation grows with the traversal's
    /// features; the driver's compile time grows with the code).
    pub fn code_bytes(&self) -> usize {
        code_bytes(&self.wgsl)
    }
}

/// [`Kernel::code_bytes`] of WGSL text.
pub fn code_bytes(wgsl: &str) -> usize {
    wgsl.lines().filter(|l| !l.trim_start().starts_with("//")).map(|l| l.len() + 1).sum()
}

/// The render kernel of `field` traced by `traversal` (its structural
/// choices: algebra and modalities, or secondary rays), counting loop work
/// per invocation: for any device (`isotrace wgsl`, the browser page).
pub fn assemble(field: &dyn FieldSource, traversal: &Traversal) -> Kernel {
    assemble_for(field, traversal, false)
}

/// [`assemble`] for a device with subgroup operations or without
/// (`subgroups`): with them, bisecting a compiled field whose runs of terms
/// are loops counts the loops' work per SIMD bundle, what lavapipe's loop
/// cap counts, as a tape's interpreter does (`tape::features::BUNDLE_WORK`).
pub fn assemble_for(field: &dyn FieldSource, traversal: &Traversal, subgroups: bool) -> Kernel {
    let shared = [&bindings::shared(), template::FRAME, template::CAMERA, template::PIXELS, template::SHADING].join("\n");
    let (uniforms, field_code, traversal_code, entries, inline) = match traversal {
        Traversal::Bisect(b) => {
            let user = b.modalities.inline.as_ref();
            (
                format!("{}\nalias Traversal = Bisect;\n{}", layout::wgsl_uniforms::<BisectBlock>(), layout::wgsl_constants()),
                field.code(&CodeRequest { domain: Some(b.algebra), inline: user, sync: false, bundle: subgroups }),
                format!("{}{}", bindings::bisect(), bisect(b, field, paired_root_search(field, b.root_search))),
                &["main", "tiles"][..],
                user.cloned(),
            )
        }
        Traversal::Sphere(s) => {
            let tiles = field.lists_tiles();
            let sync = tiles && s.synchronized;
            (
                format!("{}\nalias Traversal = Sphere;\n{}", layout::wgsl_uniforms::<SphereBlock>(), layout::wgsl_constants()),
                field.code(&CodeRequest { sync, ..Default::default() }),
                format!("{}{}", bindings::sphere(tiles), sphere(s.features(), tiles, sync)),
                if tiles { &["main", "tiles"][..] } else { &["main"][..] },
                None,
            )
        }
    };
    let wgsl = template::splice(template::RENDER, &[("uniforms", &uniforms), ("shared", &shared), ("field", &field_code), ("traversal", &traversal_code)])
        .expect("the render template has its markers");
    let inline = inline.map(|user| {
        let start = wgsl.find(&user.text).unwrap_or(0);
        (start..start + user.text.len(), user)
    });
    let mut entries = entries.to_vec();
    entries.extend(field.passes().iter().map(|p| p.entry));
    Kernel { wgsl, entries, inline }
}

/// Whether bisecting `field` closes in on roots two points a step
/// (root_search_two_points.wgsl) for the user's `choice`, where its cells
/// can (an interpreted field's cell work runs from one call site).
fn paired_root_search(field: &dyn FieldSource, choice: RootSearch) -> bool {
    let Some(default) = field.pairs_root_search() else { return false };
    match choice {
        RootSearch::Auto => default,
        RootSearch::OnePoint => false,
        RootSearch::TwoPoints => true,
    }
}

/// The bisection traversal of `field` with its modalities' code and
/// configuration; a field whose cells resume runs a cell's scalar work from
/// one call site of f (an interpreted field, whose every call site is a
/// whole interpreter), else `pair` picks the compiled cells' root search.
fn bisect(b: &BisectOptions, field: &dyn FieldSource, pair: bool) -> String {
    let m = &b.modalities;
    let one_call = field.cells_resume();
    let config = format!("{}{}", bisect_config(m, field), hooks(m.inline.as_ref()));
    let modalities = format!("{}{}", template::optional(template::BISECT_SHADOWS, m.shadows), template::optional(template::BISECT_REFLECTIONS, m.reflect > 0));
    let cells = if one_call {
        template::BISECT_CELLS[1].to_string()
    } else {
        template::splice(template::BISECT_CELLS[0], &[("root_search", template::optional(template::BISECT_ROOT_SEARCH, pair))]).expect("the cells template has its marker")
    };
    template::splice(
        template::BISECT,
        &[("config", &config), ("cells", &cells), ("shading", template::BISECT_SHADE), ("modalities", &modalities), ("tiles", template::BISECT_TILES)],
    )
    .expect("the bisection template has its markers")
}

/// Compile-time constants of the modalities: code for one exists only when
/// it is asked for.
fn bisect_config(m: &Modalities, field: &dyn FieldSource) -> String {
    let surfaces = field.surfaces();
    let mut s = String::new();
    let _ = writeln!(s, "const CELL_F_MID: bool = {};", field.cell_midpoint());
    let _ = writeln!(s, "const SHADOWS: bool = {};", m.shadows);
    let _ = writeln!(s, "const LAYERS: u32 = {}u;", m.layers.max(1));
    let _ = writeln!(s, "const REFLECT: u32 = {}u;", m.reflect);
    let _ = writeln!(s, "const ISO_COUNT: u32 = {}u;", m.isovalues.len().clamp(1, 8));
    let _ = writeln!(s, "const COLOR_MODE: u32 = {}u;", m.color as u32);
    let _ = writeln!(s, "const ENV_MODE: u32 = {}u;", m.env.mode());
    let _ = writeln!(s, "const CSG_COLORS: bool = {};", surfaces > 1);
    s
}

/// The three hook functions the bisection traversal calls: the user's
/// hooks where their `--inline` file defines them, else the defaults.
fn hooks(inline: Option<&InlineWgsl>) -> String {
    let (reject, hit, shade) = inline.map_or((false, false, false), |i| (i.reject, i.hit, i.shade));
    let mut s = String::new();
    s.push_str(if reject {
        "fn keep_cell(r: vec2<f32>) -> bool { return hook_reject(r); }\n"
    } else {
        "fn keep_cell(r: vec2<f32>) -> bool { return may_contain_iso(r); }\n"
    });
    s.push_str(if hit { "fn accept_hit(p: vec3<f32>) -> bool { return hook_hit(p); }\n" } else { "fn accept_hit(p: vec3<f32>) -> bool { return true; }\n" });
    s.push_str(if shade {
        "fn final_color(p: vec3<f32>, dir: vec3<f32>, n: vec3<f32>, c: vec3<f32>) -> vec3<f32> { return hook_shade(p, dir, n, c); }\n"
    } else {
        "fn final_color(p: vec3<f32>, dir: vec3<f32>, n: vec3<f32>, c: vec3<f32>) -> vec3<f32> { return c; }\n"
    });
    s
}

/// The sphere tracing traversal with the secondary rays of `features`, with
/// `tiles`, its tile pass (tiles.wgsl), and with `sync`, the synchronised
/// walk of a scene's tiles (primary_sync.wgsl).
fn sphere(features: SphereFeatures, tiles: bool, sync: bool) -> String {
    template::splice(
        template::SPHERE,
        &[
            ("shadows", template::optional(template::SPHERE_SHADOWS, features.shadows)),
            ("glass", template::optional(template::SPHERE_GLASS, features.glass)),
            ("tiles", template::optional(template::SPHERE_TILES, tiles)),
            ("primary", template::optional(template::SPHERE_PRIMARY, sync)),
        ],
    )
    .expect("the sphere template has its markers")
}

/// The render kernel of a formula with bisection in `domain` and no
/// modalities (what `isotrace wgsl` prints by default).
#[cfg(any(test, feature = "internals"))]
pub fn render_shader(ir: &Ir, domain: crate::ir::Domain) -> String {
    assemble(ir, &Traversal::Bisect(BisectOptions::new(domain))).wgsl
}

/// The sphere tracing kernel of a formula with the secondary rays of `features`.
pub fn sphere_shader(ir: &Ir, features: SphereFeatures) -> String {
    let o = crate::render::SphereOptions { shadows: features.shadows, glass: features.glass, synchronized: features.synchronized, ..Default::default() };
    assemble(ir, &Traversal::Sphere(o)).wgsl
}
