//! Kernel templates: real `.wgsl` files with splice markers. A marker is a
//! line holding only `//!splice:NAME`; [`splice`] replaces each with its
//! part and fails (an isotrace bug) if a marker is missing or left over.
//! This is the only way shaders are put together: optional code (a
//! modality, a secondary ray) is a template file of its own that is spliced
//! in, or its `*_off.wgsl` stand-in.

use crate::bindings::Slot;

/// The render kernel's frame: uniforms, shared code, field, traversal.
pub const RENDER: &str = include_str!("../../templates/render.wgsl");
/// The `isotrace eval` kernel: one invocation per box.
const EVAL: &str = include_str!("../../templates/eval.wgsl");

/// The `eval` kernel's uniforms (`layout::EvalBlock`).
pub const EVAL_UNIFORMS: Slot = Slot::storage(0, "eval uniforms", "Ubuf", "Eval", true);
/// Its boxes: 8 floats a box, x0 x1 y0 y1 z0 z1 t0 t1 (a point has lo == hi).
pub const EVAL_BOXES: Slot = Slot::storage(1, "boxes", "boxes", "array<f32>", true);
/// Its results: lo, hi per box (empty: lo > hi; a scalar result: lo == hi).
pub const EVAL_RESULTS: Slot = Slot::storage(2, "results", "results", "array<vec2<f32>>", false);

/// The `eval` kernel (templates/eval.wgsl) with its `parts` and the
/// declarations of its bindings.
pub fn eval(parts: &[(&str, &str)]) -> String {
    let bindings = crate::bindings::declarations_in(0, &[&EVAL_UNIFORMS, &EVAL_BOXES, &EVAL_RESULTS]);
    let mut all = parts.to_vec();
    all.push(("bindings", &bindings));
    splice(EVAL, &all).expect("the eval template has its markers")
}

/// Shared by every traversal: the frame group's uniforms and helpers.
pub const FRAME: &str = include_str!("../../templates/shared/frame.wgsl");
/// The camera model and rays against the domain.
pub const CAMERA: &str = include_str!("../../templates/shared/camera.wgsl");
/// The pixel record.
pub const PIXELS: &str = include_str!("../../templates/shared/pixels.wgsl");
/// Gradient and heat map.
pub const SHADING: &str = include_str!("../../templates/shared/shading.wgsl");

/// The scene field source's interpreter.
pub const SCENE: &str = include_str!("../../templates/fields/scene.wgsl");
/// Its distance functions that need more than a line (boxes, profiles, grids).
pub const SCENE_SHAPES: &str = include_str!("../../templates/fields/scene_shapes.wgsl");
/// The scene interpreter's formula leaves (the tape interpreter's caller).
pub const SCENE_FORMULA: &str = include_str!("../../templates/fields/scene_formula.wgsl");
/// Its interval twin, for bisection.
pub const SCENE_FORMULA_IA: &str = include_str!("../../templates/fields/scene_formula_ia.wgsl");
/// Its RAA run along a cell's segment.
pub const SCENE_FORMULA_RA: &str = include_str!("../../templates/fields/scene_formula_ra.wgsl");
/// The scene interpreter on intervals, for bisection.
pub const SCENE_ENCLOSURE: &str = include_str!("../../templates/fields/scene_enclosure.wgsl");
/// The scene field source's pre-passes: per-tile active primitives and views.
pub const SCENE_TILES: &str = include_str!("../../templates/fields/scene_tiles.wgsl");

/// Bisection: stackless interval bisection per pixel.
pub const BISECT: &str = include_str!("../../templates/traverse/bisect/kernel.wgsl");
/// Bisection's cells with their scalar work inline (compiled fields), and
/// with it run from one call site of f (interpreted fields).
pub const BISECT_CELLS: [&str; 2] = [
    include_str!("../../templates/traverse/bisect/cells.wgsl"),
    include_str!("../../templates/traverse/bisect/cells_resumable.wgsl"),
];
/// Bisection's root search in a compiled field's cells: one point of f a
/// step, and two (`narrow` in cells.wgsl).
pub const BISECT_ROOT_SEARCH: [&str; 2] = [
    include_str!("../../templates/traverse/bisect/root_search_one_point.wgsl"),
    include_str!("../../templates/traverse/bisect/root_search_two_points.wgsl"),
];
/// Bisection's tile pass (entry point `tiles`).
pub const BISECT_TILES: &str = include_str!("../../templates/traverse/bisect/tiles.wgsl");
/// Bisection's shading, colour modes and environment.
pub const BISECT_SHADE: &str = include_str!("../../templates/traverse/bisect/shade.wgsl");
/// Bisection's shadow rays, and their stand-in.
pub const BISECT_SHADOWS: [&str; 2] = [
    include_str!("../../templates/traverse/bisect/shadows_off.wgsl"),
    include_str!("../../templates/traverse/bisect/shadows.wgsl"),
];
/// Bisection's reflections, and their stand-in.
pub const BISECT_REFLECTIONS: [&str; 2] = [
    include_str!("../../templates/traverse/bisect/reflections_off.wgsl"),
    include_str!("../../templates/traverse/bisect/reflections.wgsl"),
];

/// Sphere tracing for distance bounds (Keinert et al.'s five techniques).
pub const SPHERE: &str = include_str!("../../templates/traverse/sphere/kernel.wgsl");
/// Sphere tracing's shadow rays, and their stand-in.
pub const SPHERE_SHADOWS: [&str; 2] = [
    include_str!("../../templates/traverse/sphere/shadows_off.wgsl"),
    include_str!("../../templates/traverse/sphere/shadows.wgsl"),
];
/// Sphere tracing's tile pass over a scene, and its stand-in.
pub const SPHERE_TILES: [&str; 2] = [
    include_str!("../../templates/traverse/sphere/tiles_off.wgsl"),
    include_str!("../../templates/traverse/sphere/tiles.wgsl"),
];
/// Sphere tracing's per-pixel pass: each ray on its own, or (a scene) the
/// rays of a tile walking its depth slabs together.
pub const SPHERE_PRIMARY: [&str; 2] = [
    include_str!("../../templates/traverse/sphere/primary.wgsl"),
    include_str!("../../templates/traverse/sphere/primary_sync.wgsl"),
];
/// The scene's side of that walk, and its stand-in.
pub const SCENE_SYNC: [&str; 2] = [
    include_str!("../../templates/fields/scene_sync_off.wgsl"),
    include_str!("../../templates/fields/scene_sync.wgsl"),
];
/// Sphere tracing's glass, and its stand-in.
pub const SPHERE_GLASS: [&str; 2] = [
    include_str!("../../templates/traverse/sphere/glass_off.wgsl"),
    include_str!("../../templates/traverse/sphere/glass.wgsl"),
];

/// How the affine library reads a form's range: without the NaN test
/// where no form can overflow (`analysis::magnitude`), or with it.
pub const AFFINE_RANGE: [&str; 2] = [
    include_str!("../../templates/domains/affine_range_bounded.wgsl"),
    include_str!("../../templates/domains/affine_range.wgsl"),
];

/// The part `[off, on]` of an optional feature.
pub fn optional(parts: [&'static str; 2], on: bool) -> &'static str {
    parts[usize::from(on)]
}

/// Replaces every `//!splice:NAME` line of `template` by its value.
pub fn splice(template: &str, parts: &[(&str, &str)]) -> Result<String, String> {
    let mut out = String::with_capacity(template.len() + parts.iter().map(|p| p.1.len()).sum::<usize>());
    let mut used = vec![false; parts.len()];
    for line in template.lines() {
        match line.trim().strip_prefix("//!splice:") {
            Some(name) => {
                let Some(i) = parts.iter().position(|(n, _)| *n == name) else {
                    return Err(format!("template marker '{name}' has no content"));
                };
                used[i] = true;
                out.push_str(&format!("// ---- begin {name} ----\n"));
                out.push_str(parts[i].1);
                if !parts[i].1.ends_with('\n') {
                    out.push('\n');
                }
                out.push_str(&format!("// ---- end {name} ----\n"));
            }
            None => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    if let Some(i) = used.iter().position(|u| !u) {
        return Err(format!("no marker '//!splice:{}' in the template", parts[i].0));
    }
    Ok(out)
}
