//! Bind group tables: every resource a kernel binds, as data (its
//! number, names, kind and size rule). A field source describes its group
//! (`@group(1)`) with one table, from which its WGSL declarations
//! ([`declarations`]), the device's layout and resources (`gpu::field`) and
//! the browser page's program (`view::program`) are all made, so a binding
//! number is written once.

use serde::Serialize;

/// The field group's index in every render kernel.
pub const FIELD_GROUP: u32 = 1;

/// How large a resource is, for a dispatch (or the page's frame) of w × h
/// pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Size {
    /// The uniform bytes (frame block, then the traversal block).
    Uniforms,
    /// The words in the binding's `data`.
    Data,
    /// `bytes` per pixel.
    PerPixel {
        /// Bytes.
        bytes: u64,
    },
    /// `bytes` per 8×8 tile.
    PerTile {
        /// Bytes.
        bytes: u64,
    },
    /// `bytes` per 8×8 tile up to `at_most` in all, then `plus` per tile
    /// (lists that fall back to whole programs past their cap, and their
    /// per-tile headers).
    PerTileCapped {
        /// Bytes per tile below the cap.
        bytes: u64,
        /// The cap of that part.
        at_most: u64,
        /// Bytes per tile besides.
        plus: u64,
    },
    /// A fixed size.
    Fixed {
        /// Bytes.
        bytes: u64,
    },
}

impl Size {
    /// The bytes of a dispatch of `pixels` pixels in `tiles` 8×8 tiles
    /// (`data_bytes`: the binding's data), at least 16: the smallest
    /// buffer every binding gets.
    pub fn bytes(self, pixels: u64, tiles: u64, data_bytes: u64) -> u64 {
        let b = match self {
            Size::Uniforms | Size::Data => data_bytes,
            Size::PerPixel { bytes } => pixels * bytes,
            Size::PerTile { bytes } => tiles * bytes,
            Size::PerTileCapped { bytes, at_most, plus } => (tiles * bytes).min(at_most) + tiles * plus,
            Size::Fixed { bytes } => bytes,
        };
        b.max(16)
    }

    /// Bytes a pixel of the rule's growth with the frame (0 for a fixed
    /// size): what bounds a dispatch's side so each buffer fits one binding.
    pub fn bytes_per_pixel(self) -> u64 {
        match self {
            Size::PerPixel { bytes } => bytes,
            Size::PerTile { bytes } => bytes.div_ceil(64),
            Size::PerTileCapped { plus, .. } => plus.div_ceil(64),
            Size::Uniforms | Size::Data | Size::Fixed { .. } => 0,
        }
    }

    /// The rule the page runs, for a frame of `tiles` tiles: a capped rule
    /// as the fixed size it has there.
    pub fn for_page(self, tiles: u64) -> Size {
        match self {
            Size::PerTileCapped { .. } => Size::Fixed { bytes: self.bytes(0, tiles, 0) },
            other => other,
        }
    }
}

/// A texel format of a sampled texture.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TexelFormat {
    /// Four 32-bit words.
    Rgba32Uint,
    /// Four f32.
    Rgba32Float,
    /// One 32-bit word.
    R32Uint,
}

impl TexelFormat {
    /// The WebGPU name (the page's).
    pub fn name(self) -> &'static str {
        match self {
            TexelFormat::Rgba32Uint => "rgba32uint",
            TexelFormat::Rgba32Float => "rgba32float",
            TexelFormat::R32Uint => "r32uint",
        }
    }

    /// 32-bit words a texel.
    pub fn words(self) -> u32 {
        match self {
            TexelFormat::R32Uint => 1,
            TexelFormat::Rgba32Uint | TexelFormat::Rgba32Float => 4,
        }
    }
}

impl Serialize for TexelFormat {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// A sampled 2D texture of 32-bit texels: data given row by row, or a
/// scratch texture filled by a stage's copy (its rows: as many as its size
/// rule's bytes need).
#[derive(Debug, Clone, Serialize)]
pub struct TextureShape {
    /// Texels per row.
    pub width: u32,
    /// Rows (0 for a scratch texture: from its size rule).
    pub height: u32,
    /// Its texel format.
    pub format: TexelFormat,
}

/// What a field reports from a binding it writes and the host reads back
/// after each dispatch, for the frame statistics.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Statistics {
    /// Per tile: its pruned node list's length and its active primitives
    /// (`render::record::TileStats`).
    TileLists,
    /// A tape's per-tile list counts (`render::TapeListStats`).
    TapeLists,
    /// A compiled formula's per-tile term list counts (`render::LoopListStats`).
    TermLists,
}

/// One resource of a bind group: a storage buffer (the smallest is 16
/// bytes) or, with `texture`, a sampled texture.
#[derive(Debug, Clone, Serialize)]
pub struct Binding {
    /// Binding index.
    pub binding: u32,
    /// What it holds (for messages and the tests).
    pub name: &'static str,
    /// Read-only or read-write storage.
    pub read_only: bool,
    /// Its size rule.
    pub size: Size,
    /// Its contents as 32-bit words (f32 as bits), for `Size::Data`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub data: Option<Vec<u32>>,
    /// A tile pass's queue: reset to (0, 1, 1) before the dispatch and
    /// copied into the indirect arguments of the stage that reads it.
    pub indirect: bool,
    /// Zeroed before every dispatch (the rest is written before it is read).
    pub clear: bool,
    /// A sampled texture holding `data` (or a stage's copy) instead of a buffer.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub texture: Option<TextureShape>,
    /// Read back after each dispatch for the frame statistics.
    #[serde(skip)]
    pub statistics: Option<Statistics>,
}

/// A binding's fixed half: its number, names and kind. A field source
/// keeps its table as constants of this type; its WGSL declarations and
/// the resources of every frame are made from them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Slot {
    /// Binding index.
    pub binding: u32,
    /// What it holds (for messages and the tests).
    pub name: &'static str,
    /// Its WGSL variable.
    pub var: &'static str,
    /// Its WGSL type.
    pub wgsl: &'static str,
    /// Read-only or read-write storage (a texture is read-only).
    pub read_only: bool,
    /// A sampled texture of this format instead of a buffer.
    pub texture: Option<TexelFormat>,
    /// A uniform buffer instead of storage: the viewer's present pass
    /// reads its block so (kernels read theirs from storage, whose size
    /// rule is [`Size::Uniforms`]).
    pub uniform: bool,
}

impl Slot {
    /// A storage buffer.
    pub const fn storage(binding: u32, name: &'static str, var: &'static str, wgsl: &'static str, read_only: bool) -> Slot {
        Slot { binding, name, var, wgsl, read_only, texture: None, uniform: false }
    }

    /// A uniform buffer holding the block `wgsl` (its WGSL struct).
    pub const fn uniform(binding: u32, name: &'static str, var: &'static str, wgsl: &'static str) -> Slot {
        Slot { binding, name, var, wgsl, read_only: true, texture: None, uniform: true }
    }

    /// A sampled 2D texture.
    pub const fn texture(binding: u32, name: &'static str, var: &'static str, format: TexelFormat) -> Slot {
        let wgsl = match format {
            TexelFormat::Rgba32Float => "texture_2d<f32>",
            TexelFormat::Rgba32Uint | TexelFormat::R32Uint => "texture_2d<u32>",
        };
        Slot { binding, name, var, wgsl, read_only: true, texture: Some(format), uniform: false }
    }

    /// Its WGSL declaration in `group`.
    pub fn declaration(&self, group: u32) -> String {
        let access = match (self.texture, self.uniform, self.read_only) {
            (Some(_), _, _) => "",
            (None, true, _) => "<uniform>",
            (None, false, true) => "<storage, read>",
            (None, false, false) => "<storage, read_write>",
        };
        format!("@group({group}) @binding({}) var{access} {}: {};\n", self.binding, self.var, self.wgsl)
    }

    fn binding(&self, size: Size, data: Option<Vec<u32>>, clear: bool) -> Binding {
        let texture = self.texture.map(|format| TextureShape { width: 0, height: 0, format });
        Binding { binding: self.binding, name: self.name, read_only: self.read_only, size, data, indirect: false, clear, texture, statistics: None }
    }

    /// The buffer holding `words`.
    pub fn data(&self, words: Vec<u32>) -> Binding {
        self.binding(Size::Data, Some(words), false)
    }

    /// The texture holding `texels` (vec4 texels, row by row).
    pub fn texels<T: bytemuck::Pod>(&self, texels: crate::layout::Texels<T>) -> Binding {
        let words = bytemuck::cast_slice::<T, u8>(&texels.texels).chunks(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
        let mut b = self.data(words);
        if let Some(t) = &mut b.texture {
            (t.width, t.height) = (texels.width, texels.height);
        }
        b
    }

    /// A buffer of `size` zeroed before every dispatch.
    pub fn scratch(&self, size: Size) -> Binding {
        self.binding(size, None, true)
    }

    /// A buffer of `size` its stages write before they read it: not zeroed.
    pub fn kept(&self, size: Size) -> Binding {
        self.binding(size, None, false)
    }

    /// A texture of `size` bytes in rows of `width` texels, filled by a
    /// stage's copy.
    pub fn copied(&self, width: u32, size: Size) -> Binding {
        let mut b = self.binding(size, None, false);
        if let Some(t) = &mut b.texture {
            t.width = width;
        }
        b
    }
}

impl Binding {
    /// This binding, read back for `statistics`.
    pub fn reported(self, statistics: Statistics) -> Binding {
        Binding { statistics: Some(statistics), ..self }
    }

    /// Whether the binding holds data of its own (made once, not per dispatch).
    pub fn is_static(&self) -> bool {
        self.data.is_some()
    }
}

/// The WGSL declarations of `slots` in the field group.
pub fn declarations(slots: &[&Slot]) -> String {
    declarations_in(FIELD_GROUP, slots)
}

/// The WGSL declarations of `slots` in `group`.
pub fn declarations_in(group: u32, slots: &[&Slot]) -> String {
    slots.iter().map(|s| s.declaration(group)).collect()
}

/// A copy after a stage: a buffer it wrote into a scratch texture of the
/// same group, whole rows (the source buffer is made at least that large).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Copy {
    /// The bind group of both.
    pub group: u32,
    /// The buffer's binding.
    pub from: u32,
    /// The texture's binding.
    pub to: u32,
}

/// How many workgroups a stage runs for a w × h frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Groups {
    /// One per `per_group` words of field binding `binding` (a scene's
    /// primitives), x first, then y past 65,535.
    Items {
        /// The field binding counted.
        binding: u32,
        /// Items per workgroup.
        per_group: u32,
    },
    /// One per `per_group` 8×8 tiles, in x.
    Tiles {
        /// Tiles per workgroup.
        per_group: u32,
    },
    /// One per `side` × `side` pixels (bisection's tile pass: 64; a
    /// tape's block pass: 128), `layers` deep (the block pass: 2).
    Blocks {
        /// Side in pixels.
        side: u32,
        /// Workgroups in z.
        layers: u32,
    },
    /// One per 8×8 tile in x and per `tiles_per_group` tile rows in y.
    PixelTiles {
        /// Tile rows per workgroup.
        tiles_per_group: u32,
    },
    /// The counts a tile pass left in pass binding `binding`.
    Indirect {
        /// The pass-group binding of the queue.
        binding: u32,
    },
}

/// One compute pass of a dispatch.
#[derive(Debug, Clone, Serialize)]
pub struct Stage {
    /// The WGSL entry point.
    pub entry: &'static str,
    /// Its workgroups.
    pub groups: Groups,
    /// The (group, binding) pairs the entry point uses, from naga's
    /// analysis: the page binds only these per stage, because WebGPU
    /// counts every binding of a layout against the per-stage limit.
    pub uses: Vec<[u32; 2]>,
    /// A copy to run after the stage.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub copy: Option<Copy>,
}

impl Stage {
    /// A stage of `groups` with no copy after it.
    pub fn new(entry: &'static str, groups: Groups) -> Stage {
        Stage { entry, groups, uses: vec![], copy: None }
    }
}
