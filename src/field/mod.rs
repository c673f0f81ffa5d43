//! Field sources: what a render kernel evaluates, behind one trait,
//! [`FieldSource`]. A compiled formula ([`compiled`]) is generated into the
//! shader; a tape (`tape`) and a blobtree scene (`scene`) are data in
//! the field group (`@group(1)`) run by a fixed interpreter. A traversal
//! calls nothing of a field but `field(p)` and, bisecting, the enclosures
//! `cell_enclosure` and `slab_range`; everything a source adds to a kernel,
//! the device or the browser page is asked of it through the trait.

pub mod compiled;
pub(crate) mod limits;
pub(crate) mod scene;
pub(crate) mod tape;

pub use scene::{SceneData, Texels};
pub use crate::inline::InlineWgsl;
pub use tape::{TapeData, TapeError};

use crate::ir::Domain;

/// The field source asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FieldKind {
    /// The formula generated into WGSL.
    Compiled,
    /// The formula as a tape run by the fixed interpreter.
    Tape,
    /// The formula lowered to its blobtree (only a formula of distance
    /// forms; sphere traced, or bisected in IA): [`crate::choice::scene`]; `Auto` takes it from
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
pub const UNTILED_FIELD_HOOKS: &str = "fn field_enter_pixel(px: vec2<u32>) {}\n\
    fn field_ray_range(o: vec3<f32>, d: vec3<f32>) -> vec2<f32> { return vec2<f32>(-F.inf, F.inf); }\n";
/// The hooks of bisection's tile pass for a field that runs the same code in
/// every tile (a tape with min or max shortens itself per tile instead:
/// `templates/fields/tape_tiles.wgsl`).
pub const UNSHORTENED_FIELD_HOOKS: &str = "fn field_leave_frustum() {}\n\
    fn field_tile_begin(t: u32, tile: vec2<u32>, block: bool) -> vec3<u32> { return vec3<u32>(0xffffffffu, 0xffffffffu, 0u); }\n\
    fn field_slab_begin(record: bool) {}\nfn field_slab_end(hold: bool) {}\n\
    fn field_tile_done(mask: vec2<u32>, n: u32, block: bool) -> u32 { return 0u; }\n\
    fn field_enter_tile(list: u32) {}\nfn field_in_tile(inside: bool) {}\n";

/// What a kernel asks of a field source's code.
#[derive(Debug, Clone, Copy, Default)]
pub struct CodeRequest<'a> {
    /// Bisection's number domain for the enclosures (`None`: sphere
    /// tracing, the scalar field alone).
    pub domain: Option<Domain>,
    /// The user's `--inline` WGSL (a compiled field splices it in).
    pub inline: Option<&'a InlineWgsl>,
    /// The field's side of sphere tracing's synchronised tile walk.
    pub sync: bool,
    /// The device has subgroup operations: a field whose loops count
    /// their work may count it per SIMD bundle, what lavapipe's loop cap
    /// counts.
    pub bundle: bool,
}

/// What the field group's table is made for.
#[derive(Debug, Clone, Copy, Default)]
pub struct BindingRequest {
    /// The traversal bisects (its tile pass reads per-tile lists).
    pub bisect: bool,
    /// The features of the kernel the table binds to (a field replacing
    /// another runs the first one's kernel: its lists are sized for it).
    pub kernel_features: u32,
    /// The kernel has the user's `--inline` WGSL.
    pub inline: bool,
}

/// Why a field cannot replace the one a kernel was built for: the value
/// named and the reason, for a settings error.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Refusal {
    /// What is refused.
    pub value: &'static str,
    /// Why.
    pub reason: String,
}

impl Refusal {
    /// A refusal of `value` for `reason`.
    pub fn new(value: &'static str, reason: impl Into<String>) -> Refusal {
        Refusal { value, reason: reason.into() }
    }
}

/// Where a render kernel's field comes from: everything the kernel
/// assembly, the device and the browser page ask of a source. A formula
/// compiled into the shader ([`crate::ir::Ir`]), a tape ([`TapeData`]) and a scene
/// ([`SceneData`]) implement it; a new source implements it in a folder of
/// its own, and nothing outside it changes.
pub trait FieldSource: Sync {
    /// Its name in reports and messages (`compiled`, `tape`, `scene`).
    fn name(&self) -> &'static str;

    /// The field's WGSL: `field(p)`, the hooks of `UNTILED_FIELD_HOOKS`
    /// and, bisecting, the enclosures `cell_enclosure` and `slab_range` in
    /// the request's domain, with the declarations of its bindings
    /// ([`crate::bindings::declarations`] of its table).
    fn code(&self, request: &CodeRequest<'_>) -> String;

    /// The field group's table: every binding with its size rule and data.
    fn bindings(&self, request: &BindingRequest) -> Vec<crate::bindings::Binding>;

    /// The compute passes the field runs before a traversal, every dispatch.
    fn passes(&self) -> Vec<crate::bindings::Stage> {
        vec![]
    }

    /// How many surfaces the field draws (several with level-set CSG).
    fn surfaces(&self) -> usize {
        1
    }

    /// Whether the field gives interval enclosures (bisection needs them).
    fn has_enclosures(&self) -> bool;

    /// Whether the field's code takes the user's `--inline` WGSL (its
    /// functions called from the formula, its hooks).
    fn takes_inline(&self) -> bool {
        false
    }

    /// The interpreter features compiled into its kernel (node types,
    /// operation groups; 0 for code generated whole).
    fn features(&self) -> u32 {
        0
    }

    /// Whether bisection's `cell_enclosure` also sets `g_cell_f_mid` to f
    /// at `g_cell_s_mid`, the point of the cell the traversal sets before
    /// the call (the mean-value form's midpoint), so that the traversal
    /// does not evaluate f there: a source whose evaluation is mostly a
    /// loop's overhead computes the point in the same pass for little.
    fn cell_midpoint(&self) -> bool {
        false
    }

    /// Whether bisection runs a cell's scalar work from one call site of f
    /// (`cells_resumable.wgsl`), in rounds that resume the pixels the
    /// field's work limit stopped.
    fn cells_resume(&self) -> bool {
        false
    }

    /// Rounds of the per-pixel pass after the first that resume stopped
    /// pixels, where [`FieldSource::cells_resume`].
    fn resume_rounds(&self) -> u32 {
        0
    }

    /// Whether bisection's cells may close in on roots two points a step
    /// (`root_search_two_points.wgsl`), and whether they do by default:
    /// `None` where they cannot (an interpreter runs from one call site).
    fn pairs_root_search(&self) -> Option<bool> {
        None
    }

    /// Whether the field lists each tile's work in its passes, so sphere
    /// tracing runs a tile pass that leaves the empty tiles out.
    fn lists_tiles(&self) -> bool {
        false
    }

    /// Whether bisection runs a block pass before its tile pass (a field
    /// whose tile pass reads its blocks' entries), for a kernel of
    /// `kernel_features`.
    fn block_pass(&self, _kernel_features: u32) -> bool {
        false
    }

    /// What of the field shares lavapipe's loop cap with bisection's
    /// iterations (it then limits `--max-iter`), said as the subject of a
    /// message: "a tape field (its interpreter shares".
    fn shares_loop_cap(&self) -> Option<&'static str> {
        None
    }

    /// The field's bits of the frame flags; `dense`: the whole field in
    /// every tile, the baseline of a field that lists tiles.
    fn frame_flags(&self, _dense: bool) -> u32 {
        0
    }

    /// Whether this field's data can replace that of a field named
    /// `kernel_name` in a kernel built with `kernel_features`, without a
    /// new shader.
    fn replaces(&self, kernel_name: &'static str, kernel_features: u32) -> Result<(), Refusal>;

    /// A short description for messages ("a tape of 120 instructions in
    /// the interpreter").
    fn describe(&self) -> String {
        format!("the {} field", self.name())
    }
}

/// An edit in place of a bound field: what it writes into its resources.
pub trait FieldEdit {
    /// The writes, by the field's bindings.
    fn writes(&self) -> Vec<FieldWrite>;
}

impl FieldEdit for [FieldWrite] {
    fn writes(&self) -> Vec<FieldWrite> {
        self.to_vec()
    }
}

/// Writes into a bound field's resources in place: texels of a texture
/// binding (from texel `first`, wrapping onto the next rows) or bytes of a
/// buffer binding.
#[derive(Debug, Clone, PartialEq)]
pub enum FieldWrite {
    /// Vec4 texels of texture binding `binding`, from texel `first`.
    Texels {
        /// The binding.
        binding: u32,
        /// The first texel (row-major).
        first: u64,
        /// The texels.
        texels: Vec<[f32; 4]>,
    },
    /// Bytes of buffer binding `binding` at `offset`.
    Bytes {
        /// The binding.
        binding: u32,
        /// Byte offset.
        offset: u64,
        /// The bytes.
        bytes: Vec<u8>,
    },
}
