//! The blobtree scene as a field source: its nodes, parameters, primitives
//! and bounding balls as textures and buffers of the field group, run by
//! the interpreter of `templates/fields/scene.wgsl`, with the tile pre-passes
//! of `templates/fields/scene_tiles.wgsl`. The model itself (nodes, file
//! format, linear layout) is [`crate::scene`]'s.

use crate::codegen::template;
pub use crate::layout::Texels;
pub use crate::scene::linear::SceneData;

pub mod source;


/// Most active primitives per 8×8 tile; a tile with more evaluates the
/// whole tree (counted as an overflow tile). 512 (the paper: 128, 256 for
/// its densest scene): a tile's list spans every depth here, and the
/// smooth 11,110-primitive aggregate has tiles of up to 459 at 512²; at 128
/// its 465 overflow tiles evaluated 22,219 nodes a step and ran out of the
/// loop budget. Costs 10 KiB a tile with the depths and pruned trees (160 MB at
/// 1024²; a dispatch rectangle keeps each buffer within one binding).
pub const SCENE_TILE_MAX: u32 = 512;
/// Longest pruned tree of a tile (2 × SCENE_TILE_MAX − 1 nodes).
pub const SCENE_PRUNED_MAX: u32 = 2 * SCENE_TILE_MAX;
/// Texels a row of the texture the trace reads the tile pruned trees from (a
/// power of two; 8192 rows of it hold the pruned trees of a 2048² frame).
pub const SCENE_PRUNED_TEX_WIDTH: u32 = 8192;
/// The pruned-tree length that means "the whole tree".
pub const SCENE_WHOLE_TREE: u32 = u32::MAX;
/// Depth slabs per tile (Zanni's depth ranges): each has its own pruned
/// pruned tree of the primitives whose depths meet it.
pub const SCENE_SLABS_MAX: u32 = 4;
/// A tile list up to this long keeps one slab (switching pruned trees costs a
/// copy; a short pruned tree gains little from slicing).
pub const SCENE_SLAB_MIN_LIST: u32 = 4;
/// Longest tile list whose balls a primary ray tests itself to narrow its
/// range (longer lists: the tile's depths only).
pub const SCENE_RAY_BALLS: u32 = 16;
/// Longest list of a union or comb tile (scene_tiles.wgsl): each ray
/// lists the pruned-tree entries of the members whose balls it meets (scene.wgsl,
/// `g_ray_list`), from a 64-bit mask.
pub const SCENE_UNION_MAX: u32 = 64;
/// The scene field's pre-passes, in order (`templates/fields/scene_tiles.wgsl`).
pub const SCENE_PASSES: [&str; 2] = ["scene_scatter", "scene_prune"];

/// The scene interpreter (templates/fields/scene.wgsl) with its constants,
/// the code of the node types in `features` and, with `sync`, its side of
/// the synchronised tile walk.
pub(crate) fn scene_interpreter(features: u32, sync: bool) -> String {
    format!(
        "{}const SCENE_FEATURES: u32 = {features}u;\n{}const SCENE_TILE_MAX: u32 = {SCENE_TILE_MAX}u;\nconst SCENE_PRUNED_MAX: u32 = {SCENE_PRUNED_MAX}u;\n\
         const SCENE_PRUNED_TEX_WIDTH: u32 = {SCENE_PRUNED_TEX_WIDTH}u;\n\
         const SCENE_WHOLE_TREE: u32 = {SCENE_WHOLE_TREE}u;\nconst SCENE_SLABS_MAX: u32 = {SCENE_SLABS_MAX}u;\n\
         const SCENE_SLAB_MIN_LIST: u32 = {SCENE_SLAB_MIN_LIST}u;\nconst SCENE_RAY_BALLS: u32 = {SCENE_RAY_BALLS}u;\n\
         const SCENE_UNION_MAX: u32 = {SCENE_UNION_MAX}u;\nconst SCENE_UNION_TILE: u32 = 0x80000000u;\nconst SCENE_COMB_TILE: u32 = 0x40000000u;\n{}{}\n{}\n{}",
        crate::scene::linear::wgsl_constants(),
        crate::scene::linear::wgsl_noise(),
        source::interpreter_declarations(),
        template::splice(template::SCENE, &[("primitive_cases", &crate::scene::linear::wgsl_primitive_cases()), ("unary_cases", &crate::scene::linear::wgsl_unary_cases()), ("join_cases", &crate::scene::linear::wgsl_join_cases())]).expect("the scene template has its marker"),
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
    template::eval(&[("uniforms", &crate::layout::EvalBlock::wgsl()), ("library", ""), ("inline", ""), ("evaluator", &evaluator), ("call", call)])
}

