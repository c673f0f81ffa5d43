//! Field sources: what a render kernel evaluates. A compiled formula
//! ([`compiled`]) is generated into the shader; a tape ([`tape`]) and a
//! blobtree scene ([`scene`]) are data in the field group (`@group(1)`)
//! run by a fixed interpreter. A traversal calls nothing of a field but
//! `field(p)` and, bisecting, the enclosures `cell_enclosure` and
//! `slab_range`; everything a source adds to a kernel is asked of it here.

pub mod compiled;
pub mod limits;
pub mod scene;
pub mod tape;

pub use scene::{SceneData, Texels};
pub use tape::{TapeData, TapeError};

use crate::inline::InlineWgsl;
use crate::ir::{Domain, Ir};

/// The field source asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FieldKind {
    /// The formula generated into WGSL.
    Compiled,
    /// The formula as a tape run by the fixed interpreter.
    Tape,
    /// The formula lowered to its blobtree (only a formula of distance
    /// forms, only sphere traced): [`crate::choice::scene`]; `Auto` takes it from
    /// [`crate::choice::SCENE_AUTO_MIN_BOUNDED`] bounded primitives on ([`crate::choice::auto_scene`]).
    Scene,
    /// Chosen per formula and traversal by [`crate::choice::choose`].
    #[default]
    Auto,
}

impl FieldKind {
    /// The name `--field`, `.iso` headers and reports use.
    pub fn name(self) -> &'static str {
        match self {
            FieldKind::Compiled => "compiled",
            FieldKind::Tape => "tape",
            FieldKind::Scene => "scene",
            FieldKind::Auto => "auto",
        }
    }

    /// The kind of a [`FieldKind::name`].
    pub fn parse(s: &str) -> Option<FieldKind> {
        [FieldKind::Compiled, FieldKind::Tape, FieldKind::Scene, FieldKind::Auto].into_iter().find(|k| k.name() == s)
    }
}


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

impl FieldSource<'_> {
    /// The field's WGSL: `field(p)`, and the enclosures in `domain` when a
    /// traversal needs them (a scene has none: it is sphere traced); `sync`:
    /// a scene's side of the synchronised tile walk; `bundle`: a compiled
    /// field's loops count their work per SIMD bundle (a tape says so in
    /// its features).
    pub(crate) fn code(&self, domain: Option<Domain>, inline: Option<&InlineWgsl>, sync: bool, bundle: bool) -> String {
        match self {
            // Bisection (a domain) runs the tile pass: rerolled min and max loops get per-tile lists.
            FieldSource::Compiled(ir) => compiled::field_code(ir, domain, inline, bundle, domain.is_some()),
            FieldSource::Scene(d) => format!("{}\n{}", scene::scene_interpreter(d.features, sync), crate::codegen::template::SCENE_TILES),
            FieldSource::Tape(t) => tape::wgsl::field_code(domain, t.features),
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
            FieldSource::Scene(_) => &scene::SCENE_PASSES,
        }
    }

    /// Whether the field can give interval enclosures (bisection needs them).
    pub fn has_enclosures(&self) -> bool {
        matches!(self, FieldSource::Compiled(_) | FieldSource::Tape(_))
    }
}

