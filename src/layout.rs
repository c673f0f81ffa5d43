//! The data the host and the kernels share, defined once, in Rust: the
//! uniform blocks (as `#[repr(C)]` structs whose WGSL declarations are
//! generated from the same field list) and the constants both sides use
//! (flag bits, pixel status codes, colour modes). [`wgsl_constants`] is what
//! code generation splices in front of every render kernel; the test
//! `uniform_layouts_match_naga` checks the generated WGSL against Rust's
//! layout with naga, so the two can never drift apart.
//!
//! Blocks are grouped by lifetime: [`FrameBlock`] (camera, domain, tile,
//! time, parameters: every traversal), then one traversal block
//! ([`BisectBlock`], [`SphereBlock`]). A kernel reads them as
//! `F` (frame) and `U` (traversal), copied from one read-only storage
//! buffer at entry (why a storage buffer: see `templates/shared/frame.wgsl`).

use bytemuck::{Pod, Zeroable};
use std::fmt::Write;

/// A uniform block: a Pod struct with its WGSL declaration.
pub trait GpuBlock: Pod {
    /// The WGSL struct name.
    const WGSL_NAME: &'static str;
    /// Field name, WGSL type and Rust size in bytes, in declaration order.
    const FIELDS: &'static [(&'static str, &'static str, usize)];

    /// The WGSL `struct` declaration.
    fn wgsl() -> String {
        let mut s = format!("struct {} {{\n", Self::WGSL_NAME);
        for (name, ty, _) in Self::FIELDS {
            let _ = writeln!(s, "    {name}: {ty},");
        }
        s.push_str("}\n");
        s
    }

    /// Every field with its byte offset: the block packed as declared
    /// (the test `uniform_layouts_match_naga` checks naga agrees). The
    /// viewer sends this to the page, whose host writes uniforms by name.
    fn fields() -> Vec<FieldLayout> {
        let mut offset = 0;
        Self::FIELDS
            .iter()
            .map(|&(name, ty, size)| {
                let f = FieldLayout { name, ty, offset, size };
                offset += size;
                f
            })
            .collect()
    }
}

/// One field of a [`GpuBlock`] as the host of another language needs it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct FieldLayout {
    /// Field name.
    pub name: &'static str,
    /// WGSL type (`vec4<f32>`, `u32`, `array<vec4<f32>, 16>`).
    #[serde(rename = "type")]
    pub ty: &'static str,
    /// Byte offset in the block.
    pub offset: usize,
    /// Size in bytes.
    pub size: usize,
}

macro_rules! gpu_block {
    ($(#[$doc:meta])* $name:ident as $wgsl:literal { $($(#[$fdoc:meta])* $field:ident : $rty:ty = $wty:literal),* $(,)? }) => {
        $(#[$doc])*
        #[repr(C)]
        #[derive(Debug, Clone, Copy, Pod, Zeroable)]
        pub struct $name {
            $($(#[$fdoc])* pub $field: $rty),*
        }
        impl GpuBlock for $name {
            const WGSL_NAME: &'static str = $wgsl;
            const FIELDS: &'static [(&'static str, &'static str, usize)] =
                &[$((stringify!($field), $wty, std::mem::size_of::<$rty>())),*];
        }
    };
}

/// Parameter values per frame (`array<vec4<f32>, 16>`).
pub const MAX_PARAMS: usize = 64;

gpu_block! {
    /// What every traversal needs of a frame and of the tile being rendered.
    FrameBlock as "Frame" {
        /// Eye position.
        eye: [f32; 4] = "vec4<f32>",
        /// Camera frame (unit vectors).
        forward: [f32; 4] = "vec4<f32>",
        /// Right axis.
        right: [f32; 4] = "vec4<f32>",
        /// Up axis.
        up: [f32; 4] = "vec4<f32>",
        /// Domain box, low corner.
        box_min: [f32; 4] = "vec4<f32>",
        /// Domain box, high corner; w: radius of the clip ball around the box centre (0: none).
        box_max: [f32; 4] = "vec4<f32>",
        /// Whole image, pixels.
        size: [u32; 2] = "vec2<u32>",
        /// This dispatch's first pixel.
        tile_origin: [u32; 2] = "vec2<u32>",
        /// This dispatch's size.
        tile_size: [u32; 2] = "vec2<u32>",
        /// `FLAG_*` bits.
        flags: u32 = "u32",
        /// tan(fov / 2).
        tan_half_fov: f32 = "f32",
        /// Termination width along the ray.
        eps: f32 = "f32",
        /// +inf (WGSL constants cannot hold it).
        inf: f32 = "f32",
        /// Time value t.
        time: f32 = "f32",
        /// Padding to the 16-byte alignment of `params`.
        pad0: u32 = "u32",
        /// Formula parameters in the formula's order.
        params: [f32; MAX_PARAMS] = "array<vec4<f32>, 16>",
    }
}

gpu_block! {
    /// The bisection traversal's frame values (modalities, budget).
    BisectBlock as "Bisect" {
        /// xyz: point light; w: shadow-ray eps.
        light: [f32; 4] = "vec4<f32>",
        /// Isovalues (`iso_count` of them).
        iso: [f32; 8] = "array<vec4<f32>, 2>",
        /// Environment image size (0 when procedural).
        env_size: [u32; 2] = "vec2<u32>",
        /// Iteration budget per pixel.
        max_iter: u32 = "u32",
        /// First depth with derivative enclosures (u32::MAX: off).
        mono_depth: u32 = "u32",
        /// Number of isovalues (1: just f = 0).
        iso_count: u32 = "u32",
        /// Per-layer opacity with transparency.
        opacity: f32 = "f32",
        /// Weight of each reflection bounce.
        reflectivity: f32 = "f32",
        /// Padding to 16 bytes.
        pad0: u32 = "u32",
    }
}

gpu_block! {
    /// The sphere tracing traversal's frame values (Keinert's techniques).
    SphereBlock as "Sphere" {
        /// Bound sphere: centre, radius; bound box: min corner.
        bound_a: [f32; 4] = "vec4<f32>",
        /// Bound box: max corner.
        bound_b: [f32; 4] = "vec4<f32>",
        /// Unit direction towards the key light.
        light: [f32; 4] = "vec4<f32>",
        /// Step budget per ray.
        max_steps: u32 = "u32",
        /// Technique 4 iterations (0: off).
        fixpoint: u32 = "u32",
        /// `BOUND_*`.
        bound_kind: u32 = "u32",
        /// `SPHERE_COLOR_*`.
        color_mode: u32 = "u32",
        /// Technique 1 (1: off).
        omega: f32 = "f32",
        /// 1 / Lipschitz bound.
        inv_lipschitz: f32 = "f32",
        /// Half a pixel at unit distance: tan(fov / 2) / height.
        pixel_radius: f32 = "f32",
        /// Smallest forward step (0: none).
        min_step: f32 = "f32",
        /// Technique 3's minimum offset; threshold of secondary rays.
        eps_min: f32 = "f32",
        /// Padding to 16 bytes.
        pad0: u32 = "u32",
        /// Padding.
        pad1: u32 = "u32",
        /// Padding.
        pad2: u32 = "u32",
    }
}

gpu_block! {
    /// The `isotrace eval` kernel's uniforms.
    EvalBlock as "Eval" {
        /// +inf.
        inf: f32 = "f32",
        /// Number of boxes.
        count: u32 = "u32",
        /// Invocations per row of the 2D dispatch grid.
        row: u32 = "u32",
        /// Padding.
        pad: u32 = "u32",
        /// Formula parameters.
        params: [f32; MAX_PARAMS] = "array<vec4<f32>, 16>",
    }
}

gpu_block! {
    /// The viewer's present pass (`templates/view/present.wgsl`): how the
    /// page turns a frame's pixel records into canvas pixels.
    PresentBlock as "Present" {
        /// Size of the frame the records hold (coarse while the view moves).
        size: [u32; 2] = "vec2<u32>",
        /// Size of the canvas, pixels.
        canvas: [u32; 2] = "vec2<u32>",
        /// `PRESENT_*`: the kernel's colour, normals, or work as a heat map.
        mode: u32 = "u32",
        /// Full scale of the work heat map (`--color steps:MAX`).
        steps_max: u32 = "u32",
        /// 1: tint the pixels whose visible surface is the selected
        /// primitive's (the selection's records); 0: none.
        highlight: u32 = "u32",
        /// Padding to 16 bytes.
        pad0: u32 = "u32",
    }
}

/// Present the colour the kernel drew (`--color shade`, `gradient`, `depth`, `field`).
pub const PRESENT_COLOR: u32 = 0;
/// Present the normal as a colour (`--color normal`).
pub const PRESENT_NORMAL: u32 = 1;
/// Present the work as a heat map (`--color steps:MAX`).
pub const PRESENT_STEPS: u32 = 2;

/// Frame flag: draw unresolved / unconverged pixels solid magenta.
pub const FLAG_UNRESOLVED_SOLID: u32 = 1;
/// Bisection flag: skip the tile pass (every ray traverses the whole segment).
pub const FLAG_NO_TILE_CULLING: u32 = 2;
/// Sphere flag: technique 2 (screen-space criterion, best candidate).
pub const FLAG_SCREEN: u32 = 4;
/// Sphere flag: technique 3 (dynamic eps of secondary rays).
pub const FLAG_DYNAMIC_EPS: u32 = 8;
/// Sphere flag: cast shadow rays.
pub const FLAG_SHADOWS: u32 = 16;
/// Sphere flag: render the object as glass.
pub const FLAG_GLASS: u32 = 32;
/// Frame flag: draw unresolved / unconverged pixels like hits (neither this
/// nor `FLAG_UNRESOLVED_SOLID`: hatched).
pub const FLAG_UNRESOLVED_GUESS: u32 = 64;
/// Scene field flag: every tile evaluates the whole tree (the dense
/// baseline the sparse traversal is measured against; `bench --suite scenes`).
pub const FLAG_SCENE_FULL: u32 = 128;
/// Bisection flag: a tape field runs its whole tape in every tile, not the
/// tile's shortened list (the comparison the shortening is tested against).
pub const FLAG_NO_TAPE_SHORTENING: u32 = 256;

/// Pixel status in the record (bits 30-31 of the colour word).
pub const STATUS_MISS: u32 = 0;
/// The ray found a root.
pub const STATUS_HIT: u32 = 1;
/// The budget ran out (bisection: unresolved; sphere tracing: unconverged).
pub const STATUS_UNRESOLVED: u32 = 2;

/// Sphere tracing: a ray "sees" a Lipschitz violation when f / L changes
/// faster than this many units per unit of distance between two samples
/// (f32 evaluation noise stays far below 1 %).
pub const LIPSCHITZ_SLACK: f32 = 1.01;

/// Loop iterations an invocation may spend before a traversal gives up on
/// the pixel and reports it: lavapipe silently stops any invocation after
/// 65,535 loop iterations in total (counted across all loops), so the
/// kernels stop well before and say so instead of drawing garbage.
pub const LOOP_LIMIT: u32 = 60_000;

/// Every shared constant, as WGSL `const` declarations.
pub fn wgsl_constants() -> String {
    let mut s = String::new();
    let u = [
        ("FLAG_UNRESOLVED_SOLID", FLAG_UNRESOLVED_SOLID),
        ("FLAG_UNRESOLVED_GUESS", FLAG_UNRESOLVED_GUESS),
        ("FLAG_SCENE_FULL", FLAG_SCENE_FULL),
        ("FLAG_NO_TILE_CULLING", FLAG_NO_TILE_CULLING),
        ("FLAG_NO_TAPE_SHORTENING", FLAG_NO_TAPE_SHORTENING),
        ("FLAG_SCREEN", FLAG_SCREEN),
        ("FLAG_DYNAMIC_EPS", FLAG_DYNAMIC_EPS),
        ("FLAG_SHADOWS", FLAG_SHADOWS),
        ("FLAG_GLASS", FLAG_GLASS),
        ("STATUS_MISS", STATUS_MISS),
        ("STATUS_HIT", STATUS_HIT),
        ("STATUS_UNRESOLVED", STATUS_UNRESOLVED),
        ("BOUND_NONE", BoundKind::None as u32),
        ("BOUND_SPHERE", BoundKind::Sphere as u32),
        ("BOUND_BOX", BoundKind::Box as u32),
        ("COLOR_PHONG", KernelColor::Phong as u32),
        ("COLOR_GRADIENT", KernelColor::Gradient as u32),
        ("COLOR_DEPTH", KernelColor::Depth as u32),
        ("COLOR_FIELD", KernelColor::Field as u32),
        ("LOOP_LIMIT", LOOP_LIMIT),
        ("PRESENT_COLOR", PRESENT_COLOR),
        ("PRESENT_NORMAL", PRESENT_NORMAL),
        ("PRESENT_STEPS", PRESENT_STEPS),
    ];
    for (name, v) in u {
        let _ = writeln!(s, "const {name}: u32 = {v}u;");
    }
    let _ = writeln!(s, "const LIPSCHITZ_SLACK: f32 = {LIPSCHITZ_SLACK:?};");
    s
}

/// The uniform declarations of a kernel whose traversal block is `T`: the
/// frame block, the traversal block and the buffer holding both.
pub fn wgsl_uniforms<T: GpuBlock>() -> String {
    format!(
        "{}\n{}\nstruct Uniforms {{\n    frame: Frame,\n    trav: {},\n}}\n",
        FrameBlock::wgsl(),
        T::wgsl(),
        T::WGSL_NAME
    )
}

/// The convex bound kinds of sphere tracing's technique 5.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum BoundKind {
    /// No bound.
    None = 0,
    /// A sphere.
    Sphere = 1,
    /// A box.
    Box = 2,
}

/// What the kernel draws into a hit pixel's colour (`COLOR_*` in WGSL).
/// Colourings made on the host from the record (normals, work heat maps)
/// are not kernel colour modes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[repr(u32)]
pub enum KernelColor {
    /// Two-sided Phong.
    #[default]
    Phong = 0,
    /// |grad f| on a log scale (bisection).
    Gradient = 1,
    /// Depth (bisection).
    Depth = 2,
    /// f(p) / err(t) at the hit (sphere tracing's technique 4 picture).
    Field = 3,
}


/// log2 of the width in texels of the data textures.
pub const TEXTURE_SHIFT: u32 = 12;
/// Width in texels of the data textures (a vec4 a texel): a scene's nodes
/// and parameters, a tape, a compiled formula's term table. The GPU reads
/// them through `textureLoad`, not from storage buffers: lavapipe turns
/// every storage-buffer load of a non-uniform address into a loop over its
/// SIMD lanes with a branch per lane and component, while a texel fetch is
/// a vector gather.
pub const TEXTURE_WIDTH: u32 = 1 << TEXTURE_SHIFT;

/// A table of vec4s laid out as a data texture: rows of `TEXTURE_WIDTH`
/// texels, the last padded with zeros.
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
        let width = TEXTURE_WIDTH;
        let mut texels: Vec<T> = header.into_iter().chain(rows.iter().copied()).collect();
        let height = (texels.len().div_ceil(width as usize)).max(1) as u32;
        texels.resize((width * height) as usize, T::default());
        Texels { width, height, texels }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// naga's layout of the generated declarations equals Rust's: every
    /// member at the offset the Rust struct puts it, the same total size.
    fn check<T: GpuBlock>() {
        let src = format!("{}\n@group(0) @binding(0) var<storage, read> u: Uniforms;\n", wgsl_uniforms::<T>());
        let module = naga::front::wgsl::parse_str(&src).expect("parses");
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).expect("layout");
        for (handle, ty) in module.types.iter() {
            let naga::TypeInner::Struct { members, span } = &ty.inner else { continue };
            let name = ty.name.as_deref().unwrap_or("");
            let fields: &[(&str, &str, usize)] = match name {
                "Frame" => FrameBlock::FIELDS,
                n if n == T::WGSL_NAME => T::FIELDS,
                "Uniforms" => {
                    assert_eq!(*span as usize, std::mem::size_of::<FrameBlock>() + std::mem::size_of::<T>());
                    assert_eq!(members[1].offset as usize, std::mem::size_of::<FrameBlock>());
                    continue;
                }
                other => panic!("unexpected struct {other}"),
            };
            let mut offset = 0;
            for (m, (fname, _, size)) in members.iter().zip(fields) {
                assert_eq!(m.name.as_deref(), Some(*fname));
                assert_eq!(m.offset as usize, offset, "{name}.{fname}");
                offset += size;
            }
            assert_eq!(*span as usize, offset, "size of {name}");
            let listed = if name == "Frame" { FrameBlock::fields() } else { T::fields() };
            for (m, f) in members.iter().zip(&listed) {
                assert_eq!(m.offset as usize, f.offset, "{name}.{} in fields()", f.name);
            }
            assert_eq!(layouter[handle].size as usize, offset);
        }
    }

    #[test]
    fn uniform_layouts_match_naga() {
        check::<BisectBlock>();
        check::<SphereBlock>();
        assert_eq!(std::mem::size_of::<FrameBlock>() % 16, 0);
    }
}
