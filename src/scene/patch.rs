//! Edits of a laid-out scene in place, and the buffers the scene field
//! source binds: what changes between frames without a new layout, shader
//! or pipeline (`gpu::Renderer::edit_field` uploads a [`ScenePatch`]).

use super::linear::{Linear, ABV_STRIDE, FORM_WARP_SHIFT, WARP_ROWS};
use super::roi;
use super::rows::{abv_rows, ball, primitive_rows, warp_rows};
use super::{Node, SceneError};

impl Linear {
    /// The buffers of the scene field source: nodes, parameters, every
    /// primitive's node index and its two balls, a bounding ball of its ABV
    /// and its limit ball (`reach`; the tile pre-pass tests both against
    /// tile frusta; an infinite radius bounds nothing).
    pub fn field_data(&self) -> super::linear::SceneData {
        super::linear::SceneData { nodes: self.nodes.clone(), params: self.params.clone(), prims: self.primitives.clone(), balls: self.balls(), features: self.features, leaves: self.leaves.clone() }
    }

    /// The balls of [`Linear::field_data`]: two a primitive.
    fn balls(&self) -> Vec<[f32; 4]> {
        self.abvs.iter().zip(self.limit_balls()).flat_map(|(a, l)| [ball(a), l]).collect()
    }

    /// Replaces primitive number `j` (in `primitives` order) by `p` of the
    /// same type, in place: its parameter rows, ABV and ball change, and
    /// nothing else can (ranges of interest come from the operators above
    /// it, the topology is untouched). Returns the rows to upload, so an
    /// edit costs a few hundred bytes of buffer writes instead of a new
    /// linearisation. `bounds` grows to hold the moved primitive (it only
    /// frames the default view). Another type, or a parameter count that
    /// differs, is an error: build a new `Linear`.
    pub fn set_primitive(&mut self, j: usize, p: &crate::scene::Primitive) -> Result<ScenePatch, SceneError> {
        let Some(&k) = self.primitives.get(j) else {
            return Err(SceneError::new("primitive", format!("{j} is not a primitive index (the scene has {})", self.primitives.len())));
        };
        let k = k as usize;
        if let Err((field, reason)) = p.check() {
            return Err(SceneError::at(self.order[k], &field, reason));
        }
        let old_type = super::codes::word_type(self.nodes[k][0]);
        let row = self.first_row(k);
        // Other primitives' limits change only if this one bounds an
        // intersection's or a difference's other operand (a walk to the
        // root, not the whole tree, for the common edit).
        let old_limits = self.bounds_a_limit(k).then(|| self.limit_balls());
        // A warp is clamped for the primitive's range of interest, which
        // the edit does not change; a stronger warp would need a smaller
        // step everywhere (the bound the scene is traced with).
        let p = &crate::scene::Primitive { warp: super::warp::fit(p, self.roi[k].hi), ..p.clone() };
        if p.warp.map_or(1.0, |w| w.lipschitz()) > self.lipschitz() {
            return Err(SceneError::at(self.order[k], "warp", "the edit raises the scene's Lipschitz bound: build a new scene"));
        }
        let mut rows = warp_rows(p);
        let own = rows.len();
        rows.extend(primitive_rows(p));
        if let super::Shape::Formula(f) = &p.shape {
            // The leaf keeps its tape: the same formula, the same leaf index.
            let at = self.nodes[k][1] as usize + super::rows::LEAF_INDEX_ROW;
            let index = self.params.get(at).map_or(0.0, |r| r[3]);
            if self.leaves.get(index as usize).is_none_or(|l| l.source != f.source) {
                return Err(SceneError::at(self.order[k], "formula", "an edit in place keeps a formula leaf's formula (its tape): build a new scene to change it"));
            }
            if self.leaves[index as usize].lipschitz != f.lipschitz {
                return Err(SceneError::at(self.order[k], "lipschitz", "an edit in place keeps a formula leaf's Lipschitz bound: build a new scene to change it"));
            }
            rows[own + super::rows::LEAF_INDEX_ROW][3] = index;
        }
        let new_type = super::linear::type_code(&Node::Primitive(p.clone()));
        let old_rows = self.row_count(k);
        if new_type != old_type || rows.len() != old_rows {
            return Err(SceneError::at(self.order[k], "type", "an edit in place keeps the primitive's type: build a new scene to change it"));
        }
        self.params[row..row + rows.len()].copy_from_slice(&rows);
        let a = roi::abv(p, self.roi[k].hi);
        self.abv[j * ABV_STRIDE as usize..(j + 1) * ABV_STRIDE as usize].copy_from_slice(&abv_rows(&a));
        self.abvs[j] = a;
        self.bounds = self.bounds.hull(&a.aabb());
        // The primitive's own ball, and the limits of the primitives under
        // the other operand of an intersection above it.
        let mut balls = vec![(2 * j as u32, ball(&a))];
        if let Some(old) = old_limits {
            let new = self.limit_balls();
            balls.extend((0..new.len()).filter(|&i| new[i] != old[i]).map(|i| (2 * i as u32 + 1, new[i])));
        }
        Ok(ScenePatch { param_row: row as u32, params: rows, balls })
    }

    /// Parameter rows of node `k`: up to the next node's first row.
    fn row_count(&self, k: usize) -> usize {
        let next = if k + 1 < self.nodes.len() { self.first_row(k + 1) } else { self.params.len() };
        next - self.first_row(k)
    }

    /// The first parameter row of node `k`: its warp's, for a warped
    /// primitive (whose node word points at its own rows, after them).
    fn first_row(&self, k: usize) -> usize {
        let y = self.nodes[k][1] as usize;
        let warped = self.is_leaf(k as u32) && (self.params[y + 1][3] as u32) >> FORM_WARP_SHIFT != 0;
        if warped { y - WARP_ROWS as usize } else { y }
    }
}

/// What an edit in place changes in the scene field's buffers
/// ([`Linear::set_primitive`]; uploaded by `gpu::Renderer::edit_field`).
#[derive(Debug, Clone, PartialEq)]
pub struct ScenePatch {
    /// First changed row of the parameter buffer.
    pub param_row: u32,
    /// The new rows.
    pub params: Vec<[f32; 4]>,
    /// The balls that changed (the primitive's own, limits of others), by
    /// their index in [`SceneData::balls`](super::linear::SceneData).
    pub balls: Vec<(u32, [f32; 4])>,
}

