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

use super::{compiled, tape_field, template, Domain, TapeData};
use crate::inline::InlineWgsl;
use crate::ir::Ir;
use crate::layout::{self, BisectBlock, SphereBlock};
use crate::render::{BisectOptions, Modalities, RootSearch, SphereFeatures, Traversal};
use std::fmt::Write;
use std::ops::Range;

/// Where a render kernel's field comes from.
#[derive(Debug, Clone, Copy)]
pub enum FieldSource<'a> {
    /// A formula generated into WGSL evaluators.
    Compiled(&'a Ir),
    /// A blobtree kept as data (nodes and parameters in the field group),
    /// run by a fixed interpreter: edits change buffers, not the shader.
    Scene(&'a SceneData),
    /// A formula flattened into a tape (instructions in the field group),
    /// run by a fixed interpreter in the traversal's domain: a new formula
    /// changes buffers, not the shader.
    Tape(&'a TapeData),
}

/// A scene's buffers in the layout of `templates/fields/scene.wgsl`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SceneData {
    /// One word quadruple per post-order node (root last).
    pub nodes: Vec<[u32; 4]>,
    /// Transforms and parameters, a vec4 at a time.
    pub params: Vec<[f32; 4]>,
    /// The node index of every primitive.
    pub prims: Vec<u32>,
    /// Two balls a primitive (centre, radius; +inf bounds nothing): its
    /// augmented bounding ball, then its limit ball, outside which an
    /// intersection above it is inactive (`scene::reach`).
    pub balls: Vec<[f32; 4]>,
    /// The interpreter features the scene needs (`scene::linear::FEATURE_*`
    /// bits): part of the kernel, so a renderer built for one set draws
    /// any scene whose set is within it.
    pub features: u32,
}

/// A table of vec4s laid out as a scene texture: rows of
/// [`TEXTURE_WIDTH`](crate::scene::linear::TEXTURE_WIDTH) texels, the last
/// padded with zeros.
#[derive(Debug, Clone, PartialEq)]
pub struct Texels<T> {
    /// Texels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// `width × height` texels, row by row.
    pub texels: Vec<T>,
}

impl<T: Copy + Default> Texels<T> {
    /// `rows` after an optional header texel, padded to full rows.
    pub fn from_rows(header: Option<T>, rows: &[T]) -> Texels<T> {
        let width = crate::scene::linear::TEXTURE_WIDTH;
        let mut texels: Vec<T> = header.into_iter().chain(rows.iter().copied()).collect();
        let height = (texels.len().div_ceil(width as usize)).max(1) as u32;
        texels.resize((width * height) as usize, T::default());
        Texels { width, height, texels }
    }
}

impl SceneData {
    /// The node texture: texel 0 holds the node count, node i is texel
    /// i + 1 (`scene_node` in templates/fields/scene.wgsl).
    pub fn node_texels(&self) -> Texels<[u32; 4]> {
        Texels::from_rows(Some([self.nodes.len() as u32, 0, 0, 0]), &self.nodes)
    }

    /// The parameter texture: row i of `params` is texel i.
    pub fn param_texels(&self) -> Texels<[f32; 4]> {
        Texels::from_rows(None, &self.params)
    }
}

/// Largest render kernel handed to naga and the driver: 500 KB of WGSL
/// code ([`Kernel::code_bytes`]: comment lines, which cost the driver
/// nothing, aside), about 3 times the largest catalog kernel (`@city` with
/// RAA, 156 KB).
/// lavapipe's compile time grows faster than the shader (`@creature` at
/// 126 KB takes minutes, a 757 KB kernel did not finish in 13 minutes), so
/// past this a render would sit silent for a very long time; a formula
/// that gets here is one to simplify.
pub const MAX_SHADER_BYTES: usize = 500_000;

/// Most active primitives per 8×8 tile; a tile with more evaluates the
/// whole tree (counted as an overflow tile). 512 (the paper: 128, 256 for
/// its densest scene): a tile's list spans every depth here, and the
/// smooth 11,110-primitive aggregate has tiles of up to 459 at 512²; at 128
/// its 465 overflow tiles evaluated 22,219 nodes a step and ran out of the
/// loop budget. Costs 10 KiB a tile with the depths and views (160 MB at
/// 1024²; a dispatch rectangle keeps each buffer within one binding).
pub const SCENE_TILE_MAX: u32 = 512;
/// Longest pruned view of a tile (2 × SCENE_TILE_MAX − 1 nodes).
pub const SCENE_VIEW_MAX: u32 = 2 * SCENE_TILE_MAX;
/// Texels a row of the texture the trace reads the tile views from (a
/// power of two; 8192 rows of it hold the views of a 2048² frame).
pub const SCENE_VIEW_TEX_WIDTH: u32 = 8192;
/// The view length that means "the whole tree".
pub const SCENE_VIEW_FULL: u32 = u32::MAX;
/// Depth slabs per tile (Zanni's depth ranges): each has its own pruned
/// view of the primitives whose depths meet it.
pub const SCENE_SLABS_MAX: u32 = 4;
/// A tile list up to this long keeps one slab (switching views costs a
/// copy; a short view gains little from slicing).
pub const SCENE_SLAB_MIN_LIST: u32 = 4;
/// Longest tile list whose balls a primary ray tests itself to narrow its
/// range (longer lists: the tile's depths only).
pub const SCENE_RAY_BALLS: u32 = 16;
/// Longest list of a union or comb tile (scene_tiles.wgsl): each ray
/// lists the view entries of the members whose balls it meets (scene.wgsl,
/// `g_ray_list`), from a 64-bit mask.
pub const SCENE_UNION_MAX: u32 = 64;
/// The scene field's pre-passes, in order (`templates/fields/scene_tiles.wgsl`).
pub const SCENE_PASSES: [&str; 2] = ["scene_scatter", "scene_views"];

impl FieldSource<'_> {
    /// The field's WGSL: `field(p)`, and the enclosures in `domain` when a
    /// traversal needs them (a scene has none: it is sphere traced); `sync`:
    /// a scene's side of the synchronised tile walk; `bundle`: a compiled
    /// field's loops count their work per SIMD bundle (a tape says so in
    /// its features).
    fn code(&self, domain: Option<Domain>, inline: Option<&InlineWgsl>, sync: bool, bundle: bool) -> String {
        match self {
            // Bisection (a domain) runs the tile pass: rerolled min and max loops get per-tile lists.
            FieldSource::Compiled(ir) => compiled::field_code(ir, domain, inline, bundle, domain.is_some()),
            FieldSource::Scene(d) => format!("{}\n{}", scene_interpreter(d.features, sync), template::SCENE_TILES),
            FieldSource::Tape(t) => tape_field::field_code(domain, t.features),
        }
    }

    /// How many surfaces the field draws (several with level-set CSG).
    pub fn surfaces(&self) -> usize {
        match self {
            FieldSource::Compiled(ir) => ir.surfaces.len().max(1),
            FieldSource::Scene(_) | FieldSource::Tape(_) => 1,
        }
    }

    /// The compute entry points the field runs before a traversal, every
    /// dispatch.
    pub fn passes(&self) -> &'static [&'static str] {
        match self {
            FieldSource::Compiled(_) | FieldSource::Tape(_) => &[],
            FieldSource::Scene(_) => &SCENE_PASSES,
        }
    }

    /// Whether the field can give interval enclosures (bisection needs them).
    pub fn has_enclosures(&self) -> bool {
        matches!(self, FieldSource::Compiled(_) | FieldSource::Tape(_))
    }
}

/// The scene interpreter (templates/fields/scene.wgsl) with its constants,
/// the code of the node types in `features` and, with `sync`, its side of
/// the synchronised tile walk.
fn scene_interpreter(features: u32, sync: bool) -> String {
    format!(
        "{}const SCENE_FEATURES: u32 = {features}u;\n{}const SCENE_TILE_MAX: u32 = {SCENE_TILE_MAX}u;\nconst SCENE_VIEW_MAX: u32 = {SCENE_VIEW_MAX}u;\n\
         const SCENE_VIEW_TEX_WIDTH: u32 = {SCENE_VIEW_TEX_WIDTH}u;\n\
         const SCENE_VIEW_FULL: u32 = {SCENE_VIEW_FULL}u;\nconst SCENE_SLABS_MAX: u32 = {SCENE_SLABS_MAX}u;\n\
         const SCENE_SLAB_MIN_LIST: u32 = {SCENE_SLAB_MIN_LIST}u;\nconst SCENE_RAY_BALLS: u32 = {SCENE_RAY_BALLS}u;\n\
         const SCENE_UNION_MAX: u32 = {SCENE_UNION_MAX}u;\nconst SCENE_UNION_TILE: u32 = 0x80000000u;\nconst SCENE_COMB_TILE: u32 = 0x40000000u;\n{}\n{}\n{}",
        crate::scene::linear::wgsl_constants(),
        crate::scene::linear::wgsl_noise(),
        template::SCENE,
        template::SCENE_SHAPES,
        template::optional(template::SCENE_SYNC, sync),
    )
}

/// The `eval` kernel over a scene: the interpreter runs the whole tree at
/// each point (the box's low corner), as secondary rays do. The hook the
/// scene tests use to check the device's interpreter against the f64
/// reference at random points. The render kernel's frame block is replaced
/// by the few fields the interpreter's unused tile functions name.
pub fn scene_eval_shader(features: u32) -> String {
    use crate::layout::GpuBlock;
    let frame = "struct SceneEvalFrame { eye: vec4<f32>, forward: vec4<f32>, inf: f32, tile_origin: vec2<u32>, tile_size: vec2<u32> }\n\
                 var<private> F: SceneEvalFrame;\nvar<private> g_field_work: u32;\n";
    let eval = "fn scene_eval_point(p: vec3<f32>) -> f32 {\n    var sp = 0u;\n    var top = iso_inf();\n    \
                for (var j = 0u; j < scene_node_count(); j = j + 1u) { scene_step(scene_entry(j), p, &sp, &top); }\n    return top;\n}\n";
    let evaluator = format!("{frame}{}\n{eval}", scene_interpreter(features, false));
    let call = "    let v = scene_eval_point(vec3<f32>(x.x, y.x, z.x));\n    return vec2<f32>(v, v);";
    template::splice(template::EVAL, &[("uniforms", &crate::layout::EvalBlock::wgsl()), ("library", ""), ("inline", ""), ("evaluator", &evaluator), ("call", call)])
        .expect("the eval template has its markers")
}

/// The `eval` kernel over bisection's interval cells on rays (the hook the
/// tests use to check the cell enclosure, with the nodes it takes from the
/// ray, against f64 samples on the device). Three boxes a query, 24
/// floats: o, dir, s_ref, len (the ray and what `field_begin_ray` gets),
/// then the cell's s0, s1. Results: box 3k the value's range over the
/// cell, 3k + 1 the slope's along dir, 3k + 2 the scalar field on the ray
/// at s0 and at s1. The render kernel's frame block is replaced by the two
/// fields the field code reads.
pub fn ray_cell_eval_shader(ir: &Ir) -> String {
    use crate::layout::GpuBlock;
    let frame = "struct CellEvalFrame { time: f32, inf: f32 }\nvar<private> F: CellEvalFrame;\nvar<private> g_field_work: u32;\n";
    let evaluator = format!("{frame}{}", compiled::field_code(ir, Some(Domain::Interval), None, false, false));
    let call = "    F = CellEvalFrame(0.0, iso_inf());\n    let k = (i / 3u) * 24u;\n    \
                let o = vec3<f32>(boxes[k], boxes[k + 1u], boxes[k + 2u]);\n    \
                let dir = vec3<f32>(boxes[k + 3u], boxes[k + 4u], boxes[k + 5u]);\n    \
                field_begin_ray(o, dir, boxes[k + 6u], boxes[k + 7u]);\n    let s0 = boxes[k + 8u];\n    let s1 = boxes[k + 9u];\n    \
                let c = cell_enclosure(o, dir, s0, s1, true);\n    \
                return select(select(vec2<f32>(field_ray(o, dir, s0), field_ray(o, dir, s1)), c.zw, i % 3u == 1u), c.xy, i % 3u == 0u);";
    template::splice(template::EVAL, &[("uniforms", &crate::layout::EvalBlock::wgsl()), ("library", ""), ("inline", ""), ("evaluator", &evaluator), ("call", call)])
        .expect("the eval template has its markers")
}

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
pub fn assemble(field: FieldSource<'_>, traversal: &Traversal) -> Kernel {
    assemble_for(field, traversal, false)
}

/// [`assemble`] for a device with subgroup operations or without
/// (`subgroups`): with them, bisecting a compiled field whose runs of terms
/// are loops counts the loops' work per SIMD bundle, what lavapipe's loop
/// cap counts, as a tape's interpreter does (`tape::features::BUNDLE_WORK`).
pub fn assemble_for(field: FieldSource<'_>, traversal: &Traversal, subgroups: bool) -> Kernel {
    let shared = [template::FRAME, template::CAMERA, template::PIXELS, template::SHADING].join("\n");
    let (uniforms, field_code, traversal_code, entries, inline) = match traversal {
        Traversal::Bisect(b) => {
            let user = b.modalities.inline.as_ref();
            (
                format!("{}\nalias Traversal = Bisect;\n{}", layout::wgsl_uniforms::<BisectBlock>(), layout::wgsl_constants()),
                field.code(Some(b.algebra), user, false, subgroups),
                bisect(b, field.surfaces(), one_call_site(field), paired_root_search(field, b.root_search)),
                &["main", "tiles"][..],
                user.cloned(),
            )
        }
        Traversal::Sphere(s) => {
            let tiles = sphere_tile_pass(field);
            let sync = tiles && s.synchronized;
            (
                format!("{}\nalias Traversal = Sphere;\n{}", layout::wgsl_uniforms::<SphereBlock>(), layout::wgsl_constants()),
                field.code(None, None, sync, false),
                sphere(s.features(), tiles, sync),
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
    entries.extend(field.passes());
    Kernel { wgsl, entries, inline }
}

/// The largest compiled formula (live IR nodes, `isotrace check`'s
/// operations) whose bisection kernel gets the two-point root search by
/// default. A big f keeps the core busy on its own, so the second point
/// costs nearly what the first does: at 1024² `@creature` (454 nodes) is
/// faster with two points (137-142 against 147-149 ms), `@city` (678)
/// slower (412-426 against 406-409 ms). Its second copy of f in the kernel
/// adds little to the compile (`@city`'s `main` 282 → 292-305 ms).
pub const PAIR_MAX_NODES: usize = 500;

/// Whether bisecting `field` closes in on roots two points a step
/// (narrow_pair.wgsl) for the user's `choice`: only a compiled field's
/// cells can (an interpreted field's cell work runs from one call site).
fn paired_root_search(field: FieldSource<'_>, choice: RootSearch) -> bool {
    let FieldSource::Compiled(ir) = field else { return false };
    match choice {
        RootSearch::Auto => ir.live().len() <= PAIR_MAX_NODES,
        RootSearch::OnePoint => false,
        RootSearch::TwoPoints => true,
    }
}

/// Whether bisection runs a cell's scalar work from one call site of f
/// (`cells_probe.wgsl`), whose rounds of `main` resume the pixels the
/// field's work limit stopped (`gpu::renderer` runs them): an interpreted
/// field, and a compiled formula with rerolled loops and no per-tile term
/// lists (sums), whose loops count against the same limit. Each call site
/// of f is a copy of its loops for lavapipe to compile: one site took the
/// 12,503-operation sum's cold 512² frame 2.32 → 1.97-2.00 s and the
/// 1,000-term `sin·cos·sin` sum's 13.1 → 11.9-12.1 s. A listed union keeps the inline
/// cells: their scalar points are on the ray, where its squares come from
/// their polynomials along it (`ray_forms`), and from one call site they
/// are not (1,212 ball distances: 2.22 → 3.09-3.11 s, alternating).
pub fn one_call_site(field: FieldSource<'_>) -> bool {
    match field {
        FieldSource::Tape(_) => true,
        FieldSource::Compiled(ir) => super::reroll::table_texels(ir).is_some() && super::reroll::lists::for_formula(ir).is_none(),
        _ => false,
    }
}

/// The bisection traversal with its modalities' code and configuration;
/// `one_call` runs a cell's scalar work from one call site of f (an
/// interpreted field, whose every call site is a whole interpreter), else
/// `pair` picks the compiled cells' root search.
fn bisect(b: &BisectOptions, surfaces: usize, one_call: bool, pair: bool) -> String {
    let m = &b.modalities;
    let config = format!("{}{}", bisect_config(m, surfaces), hooks(m.inline.as_ref()));
    let modalities = format!("{}{}", template::optional(template::BISECT_SHADOWS, m.shadows), template::optional(template::BISECT_REFLECTIONS, m.reflect > 0));
    let cells = if one_call {
        template::BISECT_CELLS[1].to_string()
    } else {
        template::splice(template::BISECT_CELLS[0], &[("narrow", template::optional(template::BISECT_NARROW, pair))]).expect("the cells template has its marker")
    };
    template::splice(
        template::BISECT,
        &[("config", &config), ("cells", &cells), ("shading", template::BISECT_SHADE), ("modalities", &modalities), ("tiles", template::BISECT_TILES)],
    )
    .expect("the bisection template has its markers")
}

/// Compile-time constants of the modalities: code for one exists only when
/// it is asked for.
fn bisect_config(m: &Modalities, surfaces: usize) -> String {
    let mut s = String::new();
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

/// Whether sphere tracing `field` runs a tile pass that leaves the empty
/// tiles out of the per-pixel pass: a scene knows them (its views pass).
pub fn sphere_tile_pass(field: FieldSource<'_>) -> bool {
    matches!(field, FieldSource::Scene(_))
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
pub fn render_shader(ir: &Ir, domain: Domain) -> String {
    assemble(FieldSource::Compiled(ir), &Traversal::Bisect(BisectOptions::new(domain))).wgsl
}

/// The sphere tracing kernel of a formula with the secondary rays of `features`.
pub fn sphere_shader(ir: &Ir, features: SphereFeatures) -> String {
    let o = crate::render::SphereOptions { shadows: features.shadows, glass: features.glass, synchronized: features.synchronized, ..Default::default() };
    assemble(FieldSource::Compiled(ir), &Traversal::Sphere(o)).wgsl
}
