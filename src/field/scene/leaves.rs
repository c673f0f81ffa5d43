//! A scene's formula leaves as tapes (`crate::scene::FormulaLeaf`): every
//! leaf's formula flattened by the tape source's encoder, in one texture the
//! scene interpreter's tape interpreter reads (`templates/fields/
//! scene_formula.wgsl`). The kernel runs every operation group the tapes
//! can hold, so a scene with other formulas is a new texture, not a new
//! shader.

use crate::field::tape::{features, TapeData};
use crate::ir::Domain;
use crate::scene::linear::SceneData;
use crate::scene::SceneError;

/// The tape interpreter's features in a scene kernel: every operation
/// group and the largest register file, 4 instructions an iteration
/// (leaves' programs are padded for it); no parameters (a scene has none);
/// the power loop only for scenes with `FEATURE_FORMULA_POWERS`.
pub fn leaf_tape_features(scene_features: u32) -> u32 {
    let powers = if scene_features & crate::scene::linear::FEATURE_FORMULA_POWERS != 0 { features::POWERS } else { 0 };
    (features::ALL & !features::PARAMS & !features::POWERS) | powers
}

/// Instructions the scene's tape interpreter runs an iteration.
const LEAF_TAPE_STEP: u32 = 4;

/// The tapes texture's words: (leaf count, loop iterations of one value run
/// of every leaf node of the tree, summed: what the whole tree's
/// evaluation may add to its node count), then each leaf's (first texel,
/// 1 where its cells are enclosed in RAA), then the tapes. A leaf whose
/// tape cannot be made gets a header whose run the work limit refuses, so
/// its pixels are reported, never drawn; the CLI refuses such a scene
/// first ([`check`]).
pub fn texels(data: &SceneData) -> Vec<[u32; 4]> {
    let n = data.leaves.len();
    let mut words = vec![[0u32; 4]; 1 + n.max(1)];
    words[0][0] = n as u32;
    let mut runs = Vec::with_capacity(n);
    let pow_passes = u32::from(leaf_tape_features(data.features) & features::POWERS != 0);
    for (k, leaf) in data.leaves.iter().enumerate() {
        let base = words.len() as u32;
        words[1 + k] = [base, u32::from(leaf.affine()), 0, 0];
        match TapeData::padded(&leaf.ir, LEAF_TAPE_STEP) {
            Ok(t) => {
                // As tape_run counts it, with the power loop's masked pass
                // per instruction where the kernel has it (TAPE_POW_PASSES).
                runs.push(t.value_iterations(LEAF_TAPE_STEP) + t.words[0][1] * pow_passes);
                words.extend(t.words);
            }
            Err(_) => {
                runs.push(0);
                // An empty value program whose power-chain iterations no
                // work limit admits.
                let h = crate::field::tape::TAPE_HEADER;
                words.extend([[h, 0, h, 0], [0; 4], [u32::MAX / 2, u32::MAX / 2, 0, 0]]);
            }
        }
    }
    words[0][1] = leaf_nodes(data).map(|k| runs.get(k).copied().unwrap_or(0)).fold(0u32, |a, r| a.saturating_add(r));
    words
}

/// The tapes texture of a scene whose kernel runs formula leaves; `None`
/// for another (its kernel reads no tapes).
pub fn texture(data: &SceneData) -> Option<crate::layout::Texels<[u32; 4]>> {
    (data.features & crate::scene::linear::FEATURE_FORMULA != 0).then(|| crate::layout::Texels::from_rows(None, &texels(data)))
}

/// The leaf index of every formula leaf node of the tree.
fn leaf_nodes(data: &SceneData) -> impl Iterator<Item = usize> + '_ {
    use crate::scene::linear::{word_type, FORMULA, NODE_LEAF_BIT};
    data.nodes.iter().filter(|w| w[0] & NODE_LEAF_BIT != 0 && word_type(w[0]) == FORMULA).map(|w| {
        let row = w[1] as usize + crate::scene::linear::LEAF_INDEX_ROW;
        data.params.get(row).map_or(0, |r| r[3] as usize)
    })
}

/// Refuses a scene one of whose formula leaves has no tape (too many live
/// values for the interpreter's registers), naming the leaf's formula.
pub fn check(leaves: &[std::sync::Arc<crate::scene::FormulaLeaf>]) -> Result<(), SceneError> {
    for leaf in leaves {
        if let Err(e) = TapeData::padded(&leaf.ir, LEAF_TAPE_STEP) {
            return Err(SceneError::new("nodes", format!("the formula leaf '{}' cannot run in a scene: {e}", short(&leaf.source))));
        }
    }
    Ok(())
}

/// A formula's text cut for a message.
fn short(s: &str) -> String {
    let t: String = s.chars().take(60).collect();
    if t.len() < s.len() { format!("{t}...") } else { t }
}

/// The WGSL of formula leaves in a scene kernel: the tape interpreter in
/// the scalar domain (and, `bisect`, on intervals, and in RAA for a scene
/// with `FEATURE_FORMULA_AFFINE`), the leaf functions, and
/// the interpreter's work limit (bisecting, the scene's budget).
pub fn code(scene_features: u32, bisect: bool) -> String {
    let affine = scene_features & crate::scene::linear::FEATURE_FORMULA_AFFINE != 0;
    let domains: &[Domain] = match (bisect, affine) {
        (true, true) => &[Domain::Scalar, Domain::Interval, Domain::Affine],
        (true, false) => &[Domain::Scalar, Domain::Interval],
        _ => &[Domain::Scalar],
    };
    let admits = if bisect {
        // A refused run marks the evaluation exhausted (scene_admit), as a
        // refused tree does.
        "fn tape_admits(iters: u32) -> bool {\n    let ok = scene_admit(iters) == iters;\n    g_field_work = g_field_work + select(0u, iters, ok);\n    return ok;\n}\n"
    } else {
        // Sphere tracing bounds its steps by field_cost, which counts the
        // leaves' runs (scene_leaves_cost).
        "fn tape_admits(iters: u32) -> bool { return true; }\n"
    };
    format!(
        "{}{admits}{}fn scene_leaves_cost() -> u32 {{ g_tape_base = 0u; return tape_word(0u).y; }}\n{}{}{}",
        crate::bindings::declarations(&[&super::source::TAPES]),
        crate::field::tape::wgsl::embedded(domains, leaf_tape_features(scene_features), super::source::TAPES.var),
        crate::codegen::template::SCENE_FORMULA,
        if bisect { crate::codegen::template::SCENE_FORMULA_IA } else { "" },
        match (bisect, affine) {
            (true, true) => crate::codegen::template::SCENE_FORMULA_RA,
            // Named by the interval leaf, compiled out (SCENE_FEATURES).
            (true, false) => "fn scene_leaf_tape_ra(q: SceneBox, v: vec3<f32>, err: f32, dl: vec3<f32>, slope: bool) -> vec4<f32> { return vec4<f32>(0.0); }\n",
            _ => "",
        },
    )
}
