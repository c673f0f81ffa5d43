//! The blobtree scene as a field source: its nodes, parameters, primitives
//! and bounding balls as textures and buffers of the field group, run by
//! the interpreter of `templates/fields/scene.wgsl`, with the tile pre-passes
//! of `templates/fields/scene_tiles.wgsl`. The model itself (nodes, file
//! format, linear layout) is [`crate::scene`]'s.

use crate::codegen::template;
pub use crate::layout::Texels;
pub use crate::scene::linear::SceneData;

pub mod leaves;
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
/// `g_ray_list`). 128: the denser tiles of the 11,110-primitive
/// aggregate hold over 64 at 512², and a tile past the limit
/// runs its whole pruned tree on every ray.
pub const SCENE_UNION_MAX: u32 = 128;
/// The scene field's pre-passes, in order (`templates/fields/scene_tiles.wgsl`).
pub const SCENE_PASSES: [&str; 2] = ["scene_scatter", "scene_prune"];

/// What the interpreter is assembled for: the traversal's side of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SceneKernel {
    /// Sphere tracing (or the `eval` kernel): the scalar field, its work
    /// bounded by the traversal's own guard; with `sync`, the synchronised
    /// tile walk.
    Sphere { sync: bool },
    /// Bisection: the scalar field and its interval enclosures
    /// (templates/fields/scene_enclosure.wgsl), one slab a tile, the work
    /// counted per SIMD bundle with `bundle` (subgroup operations), else per
    /// invocation.
    Bisect { bundle: bool },
}

/// Sphere tracing stops before lavapipe's loop cap itself (field_cost):
/// an evaluation never gives up.
const UNCOUNTED_WORK: &str = "fn scene_admit(n: u32) -> u32 { return n; }\nfn field_exhausted() -> bool { return false; }\n";

/// Bisection's budget: an evaluation past the work limit runs no node, its
/// enclosure is the whole line and its pixel is reported (field_exhausted),
/// as a tape's (`crate::field::limits`).
fn counted_work(bundle: bool, formula: bool) -> String {
    use crate::field::limits::*;
    // A kernel with formula leaves has the tape's constants, this one among them.
    let limit = if formula { String::new() } else { format!("const TAPE_BUNDLE_LIMIT: u32 = {TAPE_BUNDLE_LIMIT}u;\n") };
    let count = if bundle {
        format!(
            "{limit}{BUNDLE_WORK_WGSL}\
             fn scene_admits(n: u32) -> bool {{ return bundle_admits(n); }}\n\
             fn scene_tile_pass_limit() {{ g_work_limit = {TAPE_TILE_PASS_BUNDLE_LIMIT}u; }}\n"
        )
    } else {
        format!(
            "fn field_entry(li: u32) {{}}\nvar<private> g_work_limit: u32 = {TAPE_WORK_LIMIT}u;\n\
             fn scene_admits(n: u32) -> bool {{ return g_field_work + n <= g_work_limit; }}\n\
             fn scene_tile_pass_limit() {{ g_work_limit = {TAPE_TILE_PASS_WORK_LIMIT}u; }}\n"
        )
    };
    format!(
        "{count}// Set when an evaluation was refused for the work limit.\nvar<private> g_scene_exhausted: bool;\n\
         fn scene_admit(n: u32) -> u32 {{\n    let ok = scene_admits(n);\n    g_scene_exhausted = g_scene_exhausted || !ok;\n    return select(0u, n, ok);\n}}\n\
         fn field_exhausted() -> bool {{ return g_scene_exhausted; }}\n"
    )
}

/// The scene interpreter (templates/fields/scene.wgsl) with its constants,
/// the code of the node types in `features` and the traversal's side of it
/// (`kernel`).
pub(crate) fn scene_interpreter(features: u32, kernel: SceneKernel) -> String {
    let (sync, slabs, work) = match kernel {
        SceneKernel::Sphere { sync } => (sync, SCENE_SLABS_MAX, UNCOUNTED_WORK.to_string()),
        // A cell may span the depths of several slabs: one pruned tree a tile.
        SceneKernel::Bisect { bundle } => (false, 1, counted_work(bundle, features & crate::scene::linear::FEATURE_FORMULA != 0)),
    };
    let mut out = format!(
        "{}const SCENE_FEATURES: u32 = {features}u;\n{}const SCENE_TILE_MAX: u32 = {SCENE_TILE_MAX}u;\nconst SCENE_PRUNED_MAX: u32 = {SCENE_PRUNED_MAX}u;\n\
         const SCENE_PRUNED_TEX_WIDTH: u32 = {SCENE_PRUNED_TEX_WIDTH}u;\n\
         const SCENE_WHOLE_TREE: u32 = {SCENE_WHOLE_TREE}u;\nconst SCENE_SLABS_MAX: u32 = {slabs}u;\n\
         const SCENE_SLAB_MIN_LIST: u32 = {SCENE_SLAB_MIN_LIST}u;\nconst SCENE_RAY_BALLS: u32 = {SCENE_RAY_BALLS}u;\n\
         const SCENE_UNION_MAX: u32 = {SCENE_UNION_MAX}u;\nconst SCENE_UNION_TILE: u32 = 0x80000000u;\nconst SCENE_COMB_TILE: u32 = 0x40000000u;\n{}{}{work}\n{}\n{}",
        crate::scene::linear::wgsl_constants(),
        crate::scene::linear::wgsl_noise(),
        source::interpreter_declarations(),
        template::splice(template::SCENE, &[("primitive_cases", &crate::scene::linear::wgsl_primitive_cases()), ("unary_cases", &crate::scene::linear::wgsl_unary_cases()), ("join_cases", &crate::scene::linear::wgsl_join_cases())]).expect("the scene template has its marker"),
        template::SCENE_SHAPES,
        template::optional(template::SCENE_SYNC, sync),
    );
    let bisect = matches!(kernel, SceneKernel::Bisect { .. });
    let formula = features & crate::scene::linear::FEATURE_FORMULA != 0;
    // One copy of each op library the kernel's interpreters use.
    use crate::ir::Domain;
    let affine = formula && features & crate::scene::linear::FEATURE_FORMULA_AFFINE != 0;
    let domains: &[Domain] = match (bisect, affine) {
        (true, true) => &[Domain::Scalar, Domain::Interval, Domain::Affine],
        (true, false) => &[Domain::Scalar, Domain::Interval],
        (false, _) if formula => &[Domain::Scalar],
        _ => &[],
    };
    if !domains.is_empty() {
        out.push_str(&crate::codegen::libraries(domains));
    }
    if formula {
        if bisect {
            out.push_str(&crate::field::compiled::derivative::library(if affine { Domain::Affine } else { Domain::Interval }));
        }
        out.push_str(&leaves::code(features, bisect));
    } else {
        // The leaf cases are compiled out (SCENE_FEATURES), but named.
        out.push_str("fn scene_leaves_cost() -> u32 { return 0u; }\nfn scene_formula(q: vec3<f32>, r2: vec4<f32>, o: u32) -> f32 { return 0.0; }\n");
        if bisect {
            out.push_str("fn scene_formula_ia(r0: vec4<f32>, r1: vec4<f32>, b: SceneBox, r2: vec4<f32>, o: u32, along: bool) -> vec2<f32> { return vec2<f32>(0.0); }\n\
                fn scene_leaf_cell(o: vec3<f32>, dir: vec3<f32>, s0: f32, s1: f32) -> vec4<f32> { return vec4<f32>(1.0, 0.0, 0.0, 0.0); }\n");
        }
    }
    if bisect {
        out.push_str(&scene_enclosures());
    }
    out
}

/// The interval interpreter (templates/fields/scene_enclosure.wgsl) with
/// the IA library, the node types' enclosures, the noise on intervals and
/// the ray segment and slab enclosures bisection calls.
fn scene_enclosures() -> String {
    use crate::ir::Domain;
    let enclosure = template::splice(
        template::SCENE_ENCLOSURE,
        &[("primitive_enclosures", &crate::scene::linear::wgsl_primitive_enclosures()), ("unary_enclosures", &crate::scene::linear::wgsl_unary_enclosures())],
    )
    .expect("the enclosure template has its markers");
    format!("{}{enclosure}\n{}", crate::scene::linear::wgsl_noise_ia(), crate::field::compiled::enclosures(Domain::Interval, false))
}

/// The render kernel's frame block in the `eval` kernels over a scene: the
/// few fields the interpreter's unused tile functions name.
const SCENE_EVAL_FRAME: &str = "struct SceneEvalFrame { eye: vec4<f32>, forward: vec4<f32>, inf: f32, time: f32, tile_origin: vec2<u32>, tile_size: vec2<u32> }\n\
    var<private> F: SceneEvalFrame;\nvar<private> g_field_work: u32;\n";

/// The `eval` kernel over a scene: the interpreter runs the whole tree at
/// each point (the box's low corner), as secondary rays do. The hook the
/// scene tests use to check the device's interpreter against the f64
/// reference at random points.
pub fn scene_eval_shader(features: u32) -> String {
    use crate::layout::GpuBlock;
    let eval = "fn scene_eval_point(p: vec3<f32>) -> f32 {\n    var sp = 0u;\n    var top = iso_inf();\n    \
                for (var j = 0u; j < scene_node_count(); j = j + 1u) { scene_step(scene_entry(j), p, &sp, &top); }\n    return top;\n}\n";
    let evaluator = format!("{SCENE_EVAL_FRAME}{}\n{eval}", scene_interpreter(features, SceneKernel::Sphere { sync: false }));
    let call = "    let v = scene_eval_point(vec3<f32>(x.x, y.x, z.x));\n    return vec2<f32>(v, v);";
    template::eval(&[("uniforms", &crate::layout::EvalBlock::wgsl()), ("library", ""), ("inline", ""), ("evaluator", &evaluator), ("call", call)])
}


/// The `eval` kernel of a scene's interval enclosures over boxes: bisection's
/// `surf_ia` over the whole tree, with its work limit per invocation (an
/// evaluation refused for it gives the whole line). The hook the scene
/// tests use to check enclosures against f64 sampling of the reference.
#[cfg(test)]
pub fn scene_enclosure_shader(features: u32) -> String {
    use crate::layout::GpuBlock;
    let evaluator = format!("{SCENE_EVAL_FRAME}{}", scene_interpreter(features, SceneKernel::Bisect { bundle: false }));
    let call = "    F.inf = iso_inf();\n    return surf_ia(x, y, z, t);";
    template::eval(&[("uniforms", &crate::layout::EvalBlock::wgsl()), ("library", ""), ("inline", ""), ("evaluator", &evaluator), ("call", call)])
}

/// The `eval` kernel of bisection's cell enclosure over a scene's whole
/// tree, for ray cells given as boxes: (x0, y0, z0) the ray's origin, (x1,
/// y1, z1) its direction, [t0, t1] the cell. It returns the value's range,
/// or with `slope` the slope's (the tests of a formula leaf's slopes
/// against f64 differences).
#[cfg(test)]
pub fn scene_cell_shader(features: u32, slope: bool) -> String {
    use crate::layout::GpuBlock;
    let evaluator = format!("{SCENE_EVAL_FRAME}{}", scene_interpreter(features, SceneKernel::Bisect { bundle: false }));
    let call = format!(
        "    F.inf = iso_inf();\n    let r = cell_enclosure(vec3<f32>(x.x, y.x, z.x), vec3<f32>(x.y, y.y, z.y), t.x, t.y, true);\n    return {};",
        if slope { "r.zw" } else { "r.xy" }
    );
    template::eval(&[("uniforms", &crate::layout::EvalBlock::wgsl()), ("library", ""), ("inline", ""), ("evaluator", &evaluator), ("call", &call)])
}

