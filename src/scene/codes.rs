//! The constants of the GPU layout (docs/scene-format.md, "The GPU
//! layout"): node word bits, type codes, primitive forms, feature bits,
//! row counts and texture widths, and the WGSL that declares them for the
//! interpreter (`wgsl_constants`). `linear` re-exports them all. The type
//! code, form and feature of a primitive type given by numbers are its
//! descriptor's ([`crate::sdf::primitive`]); those of the types before
//! descriptors existed are named here too.

use super::operator::Typed;
use super::{Node, Operator};

/// isLeaf bit of a node word.
pub const NODE_LEAF_BIT: u32 = 1 << 31;
/// isLeft bit of a node word.
pub const NODE_LEFT_BIT: u32 = 1 << 30;
/// A leaf's bit in its type field (the top one; leaf types are below
/// 64, see [`NODE_COMB_BIT`]): every operator above the leaf is a sharp union, so that the
/// sparse field of a set of such leaves is the least of their values. The
/// views pass lets each ray of a tile of such leaves evaluate only those
/// whose ball it meets (scene_tiles.wgsl, "union tiles").
pub const NODE_UNION_PATH_BIT: u32 = 1 << 29;
/// A leaf's second flag in its type field (leaf types are below 64): the
/// leaf hangs off the tree's left spine of union-style operators (sharp,
/// compact smooth or joined unions, from the root down left operands):
/// it is the spine's bottom leaf or a spine operator's right operand. The
/// pruned tree of any set of such leaves is then a chain, each leaf after
/// the first joined by its own operator (scene_tiles.wgsl, "comb tiles").
pub const NODE_COMB_BIT: u32 = 1 << 28;
/// Position of the 8-bit type field.
pub const NODE_TYPE_SHIFT: u32 = 22;
/// Mask of the type field after shifting.
pub const NODE_TYPE_MASK: u32 = 0xff;
/// Mask of the parent field.
pub const NODE_PARENT_MASK: u32 = (1 << 22) - 1;

// The type codes of the primitive types given by numbers are their
// descriptors'; the types named here are those the layout had before
// descriptors (later ones are named only by their descriptor).

/// Type code of a sphere.
pub const SPHERE: u32 = crate::sdf::primitive::SPHERE.code;
/// Type code of a box.
pub const BOX: u32 = crate::sdf::primitive::BOX.code;
/// Type code of a round box.
pub const ROUND_BOX: u32 = crate::sdf::primitive::ROUND_BOX.code;
/// Type code of a capsule.
pub const CAPSULE: u32 = crate::sdf::primitive::CAPSULE.code;
/// Type code of a torus.
pub const TORUS: u32 = crate::sdf::primitive::TORUS.code;
/// Type code of a capped cylinder.
pub const CYLINDER: u32 = crate::sdf::primitive::CYLINDER.code;
/// Type code of an octahedron.
pub const OCTAHEDRON: u32 = crate::sdf::primitive::OCTAHEDRON.code;
/// Type code of a plane.
pub const PLANE: u32 = crate::sdf::primitive::PLANE.code;
/// Type code of an extruded profile.
pub const EXTRUDE: u32 = 9;
/// Type code of a revolved profile.
pub const REVOLVE: u32 = 10;
/// Type code of a voxel grid.
pub const GRID: u32 = 11;
/// Type code of a formula leaf (`super::leaf`).
pub const FORMULA: u32 = 14;
/// Type code of a normalized density.
pub const DENSITY: u32 = crate::sdf::primitive::DENSITY.code;
/// Type code of a sharp union, the first operator code. An operator
/// style's codes (three a style from here: union, intersection,
/// difference, so (code − UNION) mod 3 tells the operation) are its
/// descriptor's (`crate::sdf::operator`), and so are a join's
/// (`crate::sdf::join`), after the styles'.
pub const UNION: u32 = crate::sdf::operator::SHARP.first_code().expect("sharp CSG has scene nodes");
/// Type code of an offset, the first unary node (codes 48-55 are unary;
/// a unary type's code, like its feature, is its descriptor's,
/// [`crate::sdf::unary`]).
pub const OFFSET: u32 = crate::sdf::unary::OFFSET.code;
/// Type code of a displacement.
pub const DISPLACE: u32 = crate::sdf::unary::DISPLACE.code;

/// Feature bit: extruded or revolved profiles (their rows and formula).
pub const FEATURE_PROFILE: u32 = 1;
/// Feature bit: polygon profiles (a loop over the vertices).
pub const FEATURE_POLYGON: u32 = 2;
/// Feature bit: unary nodes (of every unary type; those with a feature of
/// their own also set it).
pub const FEATURE_UNARY: u32 = 4;
pub use crate::sdf::unary::{FEATURE_DISPLACE, FEATURE_INFILL};
/// Feature bit: voxel grids (trilinear interpolation of their samples).
pub const FEATURE_GRID: u32 = 32;
/// Feature bit: chamfer, round and sum blends.
pub const FEATURE_JOIN: u32 = 64;
/// Feature bit: twisted or bent primitives.
pub const FEATURE_WARP: u32 = 128;
/// Feature bit: formula leaves (the tape interpreter inside the scene's).
pub const FEATURE_FORMULA: u32 = 1 << 11;
/// Feature bit: formula leaves with integer powers from 8 on (the tape
/// interpreter's square-and-multiply loop, whose masked pass every
/// instruction of every leaf then pays).
pub const FEATURE_FORMULA_POWERS: u32 = 1 << 12;
/// Feature: a formula leaf enclosed in reduced affine arithmetic
/// (`FormulaLeaf::affine`): the kernel embeds the tape's RAA interpreter.
pub const FEATURE_FORMULA_AFFINE: u32 = 1 << 13;
/// Feature bit: primitives other than plain spheres (a frame and extents:
/// three rows). A scene of plain spheres (unwarped; laid out with the
/// identity frame, `rows::shape_rows`) runs a kernel that reads two rows a
/// node, not three, and evaluates |p − c| − r.
pub const FEATURE_SHAPES: u32 = 512;

/// Rows of a primitive's frame before its parameters (its quaternion,
/// then its centre and form).
pub const PRIM_FRAME_ROWS: u32 = 2;
/// The largest evaluation stack a scene may need.
pub const MAX_STACK: u32 = 32;
/// Rows of `abv` per primitive.
pub const ABV_STRIDE: u32 = 4;
/// Parameter rows of every primitive (module doc).
pub const PRIM_ROWS: u32 = 3;
pub use crate::sdf::primitive::{FORM_BOX, FORM_OCTAHEDRON, FORM_PLANE, FORM_REVOLVED};
pub use crate::sdf::primitive::density::{FEATURE_DENSITY, FORM_DENSITY};
/// Primitive form: a 2D profile in q.xy extruded along z.
pub const FORM_EXTRUDE: u32 = 4;
/// Primitive form: a 2D profile at (|q.xy| − R, q.z).
pub const FORM_REVOLVE: u32 = 5;
/// Primitive form: a voxel grid's samples, trilinearly interpolated.
pub const FORM_GRID: u32 = 6;
/// Primitive form: a formula leaf; its rows are the frame, (box centre,
/// leaf index), (box half extents, 1/L).
pub const FORM_FORMULA: u32 = 9;
/// The bit of a primitive's form where its warp kind (1 twist, 2 bend)
/// starts: the form proper is the low 4 bits.
pub const FORM_WARP_SHIFT: u32 = 4;
/// Rows of a warped primitive's warp, before its own rows (`rows::warp_rows`).
pub const WARP_ROWS: u32 = 4;
/// Rows of a grid primitive before its samples.
pub const GRID_ROWS: u32 = 4;
/// Rows of a profile primitive before its polygon vertices: the three of
/// every primitive, (R, vertex count) and the capsule's segment (a.x,
/// a.y, b.x, b.y).
pub const PROFILE_ROWS: u32 = 5;
pub use crate::layout::{TEXTURE_SHIFT, TEXTURE_WIDTH};

/// ABV kind: none, always active (planes).
pub const ABV_NONE: u32 = 0;
/// ABV kind: sphere.
pub const ABV_SPHERE: u32 = 1;
/// ABV kind: oriented box.
pub const ABV_BOX: u32 = 2;
/// ABV kind: capsule.
pub const ABV_CAPSULE: u32 = 3;

/// The Lipschitz bound sphere tracing assumes for a scene with compact
/// smooth operators: Zanni et al.'s empirical 1.45 (each operator scales
/// the bound by 6 r_o / (6 r_o - beta) at most; the product along a path
/// is far looser than what random scenes show, max |grad f| <= 1.23).
/// Scenes of sharp operators on exact distances are 1-Lipschitz.
pub const SMOOTH_LIPSCHITZ: f64 = 1.45;

/// The type code of a node.
pub fn type_code(node: &Node) -> u32 {
    match node {
        Node::Primitive(p) => p.shape.kind().code(),
        Node::Operator { op, .. } => op_code(op),
        Node::Unary { op, .. } => op.kind().code,
    }
}

/// The type code of node word `x` (its first word), without the leaf,
/// left, union-path and comb bits.
pub fn word_type(x: u32) -> u32 {
    (x & !(NODE_LEAF_BIT | NODE_LEFT_BIT | NODE_UNION_PATH_BIT | NODE_COMB_BIT)) >> NODE_TYPE_SHIFT & NODE_TYPE_MASK
}

/// Whether type code `t` is a unary node's.
pub fn is_unary_code(t: u32) -> bool {
    (OFFSET..OFFSET + 8).contains(&t)
}

fn op_code(op: &Operator) -> u32 {
    let first = match op.typed() {
        Typed::Style(s, _) => s.first_code().expect("a style of the model has nodes"),
        Typed::Join(t, _) => t.code,
    };
    first + op.kind as u32
}

/// The constants of this layout as WGSL (`const NODE_SPHERE: u32 = 1u;` …,
/// the operator styles' `NODE_<NAME>` among them), then the `FORM_<NAME>`
/// and `FEATURE_<NAME>` of the primitive types with a case of their own
/// that the list does not name, the `NODE_<NAME>` of
/// the joins' operations and the range of their codes (`NODE_JOIN_FIRST`,
/// `NODE_JOIN_LAST`), then the `NODE_<NAME>` and (where they have one)
/// `FEATURE_<NAME>` of the unary types.
pub fn wgsl_constants() -> String {
    let head: [(&str, u32); 15] = [
        ("NODE_LEAF_BIT", NODE_LEAF_BIT),
        ("NODE_COMB_BIT", NODE_COMB_BIT),
        ("NODE_UNION_PATH_BIT", NODE_UNION_PATH_BIT),
        ("NODE_LEFT_BIT", NODE_LEFT_BIT),
        ("NODE_TYPE_SHIFT", NODE_TYPE_SHIFT),
        ("NODE_TYPE_MASK", NODE_TYPE_MASK),
        ("NODE_PARENT_MASK", NODE_PARENT_MASK),
        ("NODE_SPHERE", SPHERE),
        ("NODE_BOX", BOX),
        ("NODE_ROUND_BOX", ROUND_BOX),
        ("NODE_CAPSULE", CAPSULE),
        ("NODE_TORUS", TORUS),
        ("NODE_CYLINDER", CYLINDER),
        ("NODE_OCTAHEDRON", OCTAHEDRON),
        ("NODE_PLANE", PLANE),
    ];
    let tail: [(&str, u32); 41] = [
        ("PRIM_FRAME_ROWS", PRIM_FRAME_ROWS),
        ("SCENE_MAX_STACK", MAX_STACK),
        ("ABV_STRIDE", ABV_STRIDE),
        ("ABV_NONE", ABV_NONE),
        ("ABV_SPHERE", ABV_SPHERE),
        ("ABV_BOX", ABV_BOX),
        ("ABV_CAPSULE", ABV_CAPSULE),
        ("SCENE_MAX_NODES", super::MAX_NODES as u32),
        ("SCENE_TEX_SHIFT", TEXTURE_SHIFT),
        ("FORM_BOX", FORM_BOX),
        ("FORM_REVOLVED", FORM_REVOLVED),
        ("FORM_OCTAHEDRON", FORM_OCTAHEDRON),
        ("FORM_PLANE", FORM_PLANE),
        ("SCENE_TEX_WIDTH", TEXTURE_WIDTH),
        ("SCENE_ENTRY_ROW_BITS", ENTRY_ROW_BITS),
        ("NODE_EXTRUDE", EXTRUDE),
        ("NODE_REVOLVE", REVOLVE),
        ("FORM_EXTRUDE", FORM_EXTRUDE),
        ("FORM_REVOLVE", FORM_REVOLVE),
        ("PROFILE_ROWS", PROFILE_ROWS),
        ("MAX_POLYGON", super::profile::MAX_POLYGON as u32),
        ("FEATURE_PROFILE", FEATURE_PROFILE),
        ("FEATURE_POLYGON", FEATURE_POLYGON),
        ("FEATURE_UNARY", FEATURE_UNARY),
        ("FEATURE_GRID", FEATURE_GRID),
        ("FEATURE_JOIN", FEATURE_JOIN),
        ("FEATURE_WARP", FEATURE_WARP),
        ("FEATURE_DENSITY", FEATURE_DENSITY),
        ("FEATURE_SHAPES", FEATURE_SHAPES),
        ("FORM_WARP_SHIFT", FORM_WARP_SHIFT),
        ("WARP_ROWS", WARP_ROWS),
        ("NODE_GRID", GRID),
        ("FORM_GRID", FORM_GRID),
        ("FORM_DENSITY", FORM_DENSITY),
        ("NODE_DENSITY", DENSITY),
        ("GRID_ROWS", GRID_ROWS),
        ("NODE_FORMULA", FORMULA),
        ("FORM_FORMULA", FORM_FORMULA),
        ("FEATURE_FORMULA", FEATURE_FORMULA),
        ("FEATURE_FORMULA_POWERS", FEATURE_FORMULA_POWERS),
        ("FEATURE_FORMULA_AFFINE", FEATURE_FORMULA_AFFINE),
    ];
    let named = |list: &[(&str, u32)]| list.iter().map(|&(n, v)| (n.to_string(), v)).collect::<Vec<_>>();
    let consts: Vec<(String, u32)> = named(&head).into_iter().chain(style_constants()).chain(named(&tail)).collect();
    let mut s = String::new();
    for (name, v) in &consts {
        s.push_str(&format!("const {name}: u32 = {v}u;\n"));
    }
    s + &descriptor_constants(&consts)
}

/// `NODE_<NAME>` of every operation of the operator styles with nodes of
/// their own, NAME the scene type in capitals (`NODE_SMOOTH_UNION`).
fn style_constants() -> Vec<(String, u32)> {
    let mut out = vec![];
    for s in crate::sdf::operator::STYLES {
        let (Some(names), Some(first)) = (s.scene_names(), s.first_code()) else { continue };
        out.extend(names.iter().zip(first..).map(|(name, code)| (format!("NODE_{}", name.to_uppercase()), code)));
    }
    out
}

/// The constants the descriptors name (`wgsl_constants`' doc) that the
/// list `consts` does not.
fn descriptor_constants(consts: &[(String, u32)]) -> String {
    let mut s = String::new();
    for t in crate::sdf::primitive::TYPES {
        let Some(case) = t.wgsl else { continue };
        let name = t.scene_name.to_uppercase();
        for (prefix, v) in [("FORM", case.form), ("FEATURE", case.feature)] {
            let name = format!("{prefix}_{name}");
            if !consts.iter().any(|(n, _)| *n == name) {
                s.push_str(&format!("const {name}: u32 = {v}u;\n"));
            }
        }
    }
    for t in crate::sdf::join::TYPES {
        for (k, name) in t.scene_names.iter().enumerate() {
            s.push_str(&format!("const NODE_{}: u32 = {}u;\n", name.to_uppercase(), t.code + k as u32));
        }
    }
    let (first, last) = join_codes();
    s.push_str(&format!("const NODE_JOIN_FIRST: u32 = {first}u;\nconst NODE_JOIN_LAST: u32 = {last}u;\n"));
    for t in crate::sdf::unary::TYPES {
        let name = t.name().to_uppercase();
        s.push_str(&format!("const NODE_{name}: u32 = {}u;\n", t.code));
        if t.wgsl.feature != 0 {
            s.push_str(&format!("const FEATURE_{name}: u32 = {}u;\n", t.wgsl.feature));
        }
    }
    s
}

/// The cases of the primitive types that have one (`primitive_cases` in
/// `scene_shape`, templates/fields/scene.wgsl), in type-code order, each
/// compiled where the scene has its feature.
pub fn wgsl_primitive_cases() -> String {
    crate::sdf::primitive::TYPES.iter().filter_map(|t| t.wgsl.map(|c| feature_gated(t.scene_name, c.code))).collect()
}

/// `code` compiled where the scene has the feature of type `name`
/// (`FEATURE_<NAME>`).
fn feature_gated(name: &str, code: &str) -> String {
    format!("    if ((SCENE_FEATURES & FEATURE_{}) != 0u) {{\n{code}    }}\n", name.to_uppercase())
}

/// The enclosures of the primitive types whose field is not a distance
/// (`primitive_enclosures` in `scene_shape_ia`,
/// templates/fields/scene_enclosure.wgsl), each compiled where the scene
/// has its feature; the others are enclosed by their centred form.
pub fn wgsl_primitive_enclosures() -> String {
    crate::sdf::primitive::TYPES.iter().filter_map(|t| t.wgsl.and_then(|c| c.enclosure).map(|code| feature_gated(t.scene_name, code))).collect()
}

/// The first and last type codes of the joins.
fn join_codes() -> (u32, u32) {
    let codes = crate::sdf::join::TYPES.iter().flat_map(|t| (0..t.scene_names.len() as u32).map(|k| t.code + k));
    (codes.clone().min().expect("joins"), codes.max().expect("joins"))
}

/// The cases of the joins (`join_cases` in `scene_join`,
/// templates/fields/scene.wgsl), in type-code order.
pub fn wgsl_join_cases() -> String {
    crate::sdf::join::TYPES.iter().map(|t| t.wgsl).collect()
}

/// The cases of the unary types (`unary_cases` in `scene_unary`,
/// templates/fields/scene.wgsl), in type-code order, those with a feature
/// of their own compiled where the scene has it.
pub fn wgsl_unary_cases() -> String {
    unary_snippets(|c| c.code)
}

/// A snippet of every unary type (`pick`s of its case), gated by its
/// feature where it has one of its own.
fn unary_snippets(pick: fn(&crate::sdf::unary::UnaryCase) -> &'static str) -> String {
    let snippet = |t: &crate::sdf::unary::UnaryType| match t.wgsl.feature {
        0 => pick(&t.wgsl).to_string(),
        _ => feature_gated(t.name(), pick(&t.wgsl)),
    };
    crate::sdf::unary::TYPES.iter().map(|t| snippet(t)).collect()
}

/// The enclosures of the unary types (`unary_enclosures` in
/// `scene_unary_ia`, templates/fields/scene_enclosure.wgsl), as
/// [`wgsl_unary_cases`] places their cases.
pub fn wgsl_unary_enclosures() -> String {
    unary_snippets(|c| c.enclosure)
}

/// `scene_noise_ia(b, f)`: [`wgsl_noise`] over a box, each wave's phase
/// by `scene_dot_ia` and its sine by the IA library's.
pub fn wgsl_noise_ia() -> String {
    let terms: Vec<String> = crate::sdf::NOISE_WAVES
        .iter()
        .map(|&(a, m, w, phase)| format!("ia_scale(ia_sin(ia_scale(scene_dot_ia(vec3<f32>({:?}, {:?}, {:?}), b), f * {m:?}) + {phase:?}), {w:?})", a[0], a[1], a[2]))
        .collect();
    format!("fn scene_noise_ia(b: SceneBox, f: f32) -> vec2<f32> {{\n    return {};\n}}\n", terms.join("\n        + "))
}

/// `scene_noise(p, f)`, the displacement's pseudo-noise
/// ([`crate::sdf::noise`]), as WGSL written from the same table.
pub fn wgsl_noise() -> String {
    let terms: Vec<String> = crate::sdf::NOISE_WAVES
        .iter()
        .map(|&(a, m, w, phase)| format!("{w:?} * sin(f * {m:?} * dot(vec3<f32>({:?}, {:?}, {:?}), p) + {phase:?})", a[0], a[1], a[2]))
        .collect();
    format!("fn scene_noise(p: vec3<f32>, f: f32) -> f32 {{\n    return {};\n}}\n", terms.join("\n        + "))
}

/// Bits of a pruned view's entry that hold the node's first parameter row
/// (`scene_entry` in templates/fields/scene.wgsl: isLeaf, type, row): every
/// scene within [`super::MAX_NODES`] fits.
pub const ENTRY_ROW_BITS: u32 = 25;
const _: () = assert!((super::MAX_NODES as u64) * (PRIM_ROWS as u64) < 1 << ENTRY_ROW_BITS);
const _: () = assert!(DISPLACE < 1 << (31 - ENTRY_ROW_BITS));


#[cfg(test)]
mod tests {
    use super::*;
    use crate::sdf::primitive as types;

    #[test]
    fn primitive_type_codes_leave_the_other_types_theirs() {
        for t in types::TYPES {
            assert!(![EXTRUDE, REVOLVE, GRID].contains(&t.code) && t.code < UNION, "{t:?}");
        }
    }

    #[test]
    fn forms_and_features_of_cases_are_their_own() {
        let features = [FEATURE_PROFILE, FEATURE_POLYGON, FEATURE_UNARY, FEATURE_INFILL, FEATURE_DISPLACE, FEATURE_GRID, FEATURE_JOIN, FEATURE_WARP, FEATURE_SHAPES];
        for t in types::TYPES {
            let Some(c) = t.wgsl else { continue };
            assert!(![FORM_EXTRUDE, FORM_REVOLVE, FORM_GRID].contains(&c.form), "{t:?}");
            assert!(features.iter().all(|f| f & c.feature == 0), "{t:?}");
        }
        let w = wgsl_constants();
        naga::front::wgsl::parse_str(&w).expect("declared once each");
        let cases = wgsl_primitive_cases();
        for t in types::TYPES {
            let Some(c) = t.wgsl else { continue };
            let name = t.scene_name.to_uppercase();
            assert!(w.contains(&format!("const FORM_{name}: u32 = {}u;\n", c.form)) && w.contains(&format!("const FEATURE_{name}: u32 = {}u;\n", c.feature)), "{t:?}");
            assert!(cases.contains(&format!("    if ((SCENE_FEATURES & FEATURE_{name}) != 0u) {{\n{}    }}\n", c.code)), "{t:?}");
        }
    }

    #[test]
    fn join_codes_are_operator_codes_before_the_unary_ones() {
        let w = wgsl_constants();
        let cases = wgsl_join_cases();
        for t in crate::sdf::join::TYPES {
            let styles_end = style_constants().iter().map(|(_, c)| c + 1).max().expect("styles");
            assert!(t.code >= styles_end && t.code + t.scene_names.len() as u32 <= OFFSET && (t.code - UNION) % 3 == 0, "{t:?}");
            for (k, name) in t.scene_names.iter().enumerate() {
                let name = name.to_uppercase();
                assert!(w.contains(&format!("const NODE_{name}: u32 = {}u;\n", t.code + k as u32)), "{t:?}");
            }
            let last = t.scene_names.last().expect("a name").to_uppercase();
            assert!(cases.contains(t.wgsl) && t.wgsl.contains(&format!("ty <= NODE_{last}")) || t.wgsl.contains(&format!("ty == NODE_{last}")), "{t:?}");
        }
    }

    #[test]
    fn unary_codes_and_features_are_their_own() {
        let w = wgsl_constants();
        let cases = wgsl_unary_cases();
        for t in crate::sdf::unary::TYPES {
            assert!(is_unary_code(t.code) && t.code < 1 << (31 - ENTRY_ROW_BITS), "{t:?}");
            let name = t.name().to_uppercase();
            assert!(w.contains(&format!("const NODE_{name}: u32 = {}u;\n", t.code)), "{t:?}");
            assert!(cases.contains(t.wgsl.code) && t.wgsl.code.contains(&format!("ty == NODE_{name}")), "{t:?}");
            let f = t.wgsl.feature;
            assert!(f == 0 || (f & FEATURE_UNARY == 0 && w.contains(&format!("const FEATURE_{name}: u32 = {f}u;\n"))), "{t:?}");
        }
    }
}
