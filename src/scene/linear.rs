//! The linearised post-order blobtree the GPU reads (Zanni et al. 2024 §5
//! and §7, after Grasberger et al. 2016). **The layout is fixed**: the WGSL
//! interpreter and traversal are written against it, and
//! `wgsl_constants` generates their constants from the ones here.
//!
//! `nodes: Vec<[u32; 4]>`, one per node in post-order (root last, index n − 1):
//! - x: isLeaf (bit 31) | isLeft (bit 30) | type (bits 22..29) | parent
//!   (bits 0..21; the root's parent is n, "invalid");
//! - y: index of the node's first vec4 in `params`;
//! - z: the fast ancestor (the brief §1.4; the root's is n);
//! - w: a primitive's index in `primitives` (its ball's), 0 for other nodes.
//!
//! `params: Vec<[f32; 4]>`: a primitive has `PRIM_ROWS` = 3 rows. Its
//! local point is q = A(p − c)/s (A the rotation to its frame, c its
//! centre, s its scale): row 0 is Q, the unit quaternion of A divided by
//! √s, so that q = (w² − |u|²)v + 2(u·v)u + 2w(u × v) for Q = (u, w) and
//! v = p − c, and s = 1/|Q|²; row 1 is (c, form); row 2 is (hx, hy, hz, r).
//! Three texel fetches where a 3×4 matrix and two parameter rows took five.
//! The field is s · d(q) with one branch-free formula for every type (the
//! interpreter runs on SIMD lanes that evaluate every branch, so a switch
//! over eight types cost eight):
//! - `FORM_BOX`: d = box(q, h) − r. A sphere is h = 0, r = radius; a
//!   round box h = half − r; a capsule h = (0, 0, |b − a|/2) in a frame
//!   centred on the segment with z along it (composed into A and c).
//! - `FORM_REVOLVED`: the same in (|q.xy| − R, 0, q.z) with R = hy and
//!   no bound along y: a torus is h = (0, R, 0), r = minor; a cylinder
//!   h = (radius, 0, half height), r = 0.
//! - `FORM_OCTAHEDRON`: (|q.x| + |q.y| + |q.z| − hx)/√3.
//! - `FORM_PLANE`: n·q with n = (hx, hy, hz) of unit length (the offset
//!   moves c).
//! - `FORM_DENSITY`: row 2 is (R, h, T, c) (`sdf::blend`'s density).
//! - Other types with a case of their own: row 2 as their descriptor's
//!   `rows` writes it (`crate::sdf::primitive`).
//! - Profiles and voxel grids have rows of their own after these
//!   (`rows::profile_rows`, `rows::grid_rows`).
//!
//! An operator has one row (β, r_o, 0, 0), zeros when sharp.
//!
//! `abv: Vec<[f32; 4]>`: `ABV_STRIDE` = 4 rows per primitive, primitives
//! in post-order (the k-th is node `primitives[k]`):
//! - row 0: (x0, y0, z0, kind) with kind `ABV_NONE` 0 (always active),
//!   `ABV_SPHERE` 1, `ABV_BOX` 2, `ABV_CAPSULE` 3, as a float;
//! - sphere: row 0 xyz the centre, row 1 (0, 0, 0, radius);
//! - box: row 0 xyz the centre, rows 1-3 (unit axis, half extent along it);
//! - capsule: row 0 xyz the end a, row 1 (b, radius);
//! - unused rows are zero. Radii and half extents are rounded up to f32 and
//!   padded by 2⁻²⁰ of the volume's size, so f32 rounding never shrinks one.
//!
//! Operands of commutative operators (every one but difference) are put in
//! the order that needs the smaller evaluation stack (the larger subtree
//! first, as Sethi-Ullman numbering), which changes no value: min, max and
//! |a − b| are symmetric. A left comb then needs 2 values, a balanced tree
//! log₂ n + 1; only differences nested on their right can exceed
//! `MAX_STACK`, and such scenes are refused.

use super::roi::{self, Aabb, Abv, Roi};
use super::{Node, NodeId, OpKind, Scene, SceneError, Shape, Unary};
use super::operator::Typed;
pub use super::patch::ScenePatch;
pub(crate) use super::rows::{abv_rows, primitive_rows, warp_rows};
pub use super::rows::LEAF_INDEX_ROW;
use super::rows::unary_row;
pub(crate) use super::codes::*;

/// A scene in post-order: the GPU buffers and the topology the CPU
/// traversal uses. Vectors indexed "by node" use post-order indices.
#[derive(Debug, Clone)]
pub struct Linear {
    /// The node words (module doc).
    pub nodes: Vec<[u32; 4]>,
    /// Parameter rows (module doc).
    pub params: Vec<[f32; 4]>,
    /// ABV rows, `ABV_STRIDE` per primitive (module doc).
    pub abv: Vec<[f32; 4]>,
    /// The post-order index of each primitive, ascending.
    pub primitives: Vec<u32>,
    /// The most values a post-order stack interpreter holds at once.
    pub stack_depth: u32,
    /// A box holding the solid {f ≤ 0} (`roi::bounds`); infinite sides
    /// if a plane is not cut off.
    pub bounds: Aabb,
    /// The scene node at each post-order index.
    pub order: Vec<NodeId>,
    /// Parent of each node (the root's: n).
    pub parent: Vec<u32>,
    /// Fast ancestor of each node (the root's: n).
    pub fast: Vec<u32>,
    /// Whether each node is a left operand.
    pub is_left: Vec<bool>,
    /// An operator's operands (left, right) as the GPU sees them; leaves: (n, n).
    pub children: Vec<[u32; 2]>,
    /// Each node's range of interest.
    pub roi: Vec<Roi>,
    /// Each primitive's ABV in f64, in `primitives` order.
    pub abvs: Vec<Abv>,
    /// The interpreter features the scene needs (`FEATURE_*` bits): the
    /// kernel compiles only those, so scenes of the basic types pay
    /// nothing for the others.
    pub features: u32,
    /// The Lipschitz bound the field is traced with ([`Linear::lipschitz`]).
    lipschitz: f64,
    /// The distinct formula leaves, by leaf index (a leaf's rows name it).
    pub leaves: Vec<std::sync::Arc<super::leaf::FormulaLeaf>>,
    /// The unary nodes that stand for a merged chain, by post-order index
    /// (ascending), with the operation of the whole chain.
    folded: Vec<(u32, Unary)>,
}

impl Linear {
    /// Linearises `scene`, its chains of unary nodes folded
    /// (`fold`); refuses a scene whose evaluation would need
    /// more than `MAX_STACK` values (the error names the lowest node that
    /// does), one with more than `MAX_UNPRUNED_DEPTH`
    /// unprunable nodes above a primitive, and one whose bounds reach
    /// beyond `MAX_EXTENT`. Errors name the
    /// scene's own nodes; [`Linear::order`] holds them too (a merged
    /// chain: its top node).
    pub fn new(scene: &Scene) -> Result<Linear, SceneError> {
        let scene_roi = roi::ranges(scene);
        super::extent::check(scene, &scene_roi)?;
        let Some(folded) = super::fold::fold(scene) else {
            return Linear::build(scene, scene_roi, &|i| i);
        };
        let (tree, origin) = (&folded.scene, &folded.origin);
        let mut lin = Linear::build(tree, roi::ranges(tree), &|i| origin[i])?;
        for (k, &i) in lin.order.iter().enumerate() {
            if let Node::Unary { op, .. } = tree.nodes()[i] {
                if !matches!(scene.nodes()[origin[i]], Node::Unary { op: own, .. } if own == op) {
                    lin.folded.push((k as u32, op));
                }
            }
        }
        for i in &mut lin.order {
            *i = origin[*i];
        }
        Ok(lin)
    }

    /// [`Linear::new`] of a tree that folds no further, with its ranges of
    /// interest; `name` gives the scene node of a node of `scene`.
    fn build(scene: &Scene, scene_roi: Vec<Roi>, name: &dyn Fn(NodeId) -> NodeId) -> Result<Linear, SceneError> {
        super::fold::check_depth(scene, &scene_roi, name)?;
        let (swap, stack_depth) = operand_order(scene).map_err(|(i, e)| SceneError::at(name(i), "", e))?;
        let order = ordered_post(scene, &swap);
        let n = order.len();
        let mut index = vec![0u32; n];
        for (k, &i) in order.iter().enumerate() {
            index[i] = k as u32;
        }
        let bounds = roi::bounds(scene, &scene_roi);
        let mut lin = Linear {
            nodes: Vec::with_capacity(n),
            params: Vec::new(),
            abv: Vec::new(),
            primitives: Vec::new(),
            stack_depth,
            bounds,
            parent: vec![n as u32; n],
            fast: vec![n as u32; n],
            is_left: vec![false; n],
            children: vec![[n as u32; 2]; n],
            roi: order.iter().map(|&i| scene_roi[i]).collect(),
            abvs: Vec::new(),
            features: features(scene),
            lipschitz: lipschitz_bound(scene),
            leaves: Vec::new(),
            order,
            folded: Vec::new(),
        };
        if !lin.lipschitz.is_finite() {
            return Err(unbounded_slope(scene, name));
        }
        lin.link(scene, &index, &swap);
        lin.fast = fast_ancestors(&lin.parent, &lin.is_left, &lin.order, scene);
        lin.fill(scene);
        lin.mark_union_paths();
        if lin.params.len() >= 1 << ENTRY_ROW_BITS {
            return Err(SceneError::new(
                "nodes",
                format!("the scene's parameters take {} rows, above the limit of {} (a pruned view's entry holds the row in {ENTRY_ROW_BITS} bits)", lin.params.len(), (1u32 << ENTRY_ROW_BITS) - 1),
            ));
        }
        Ok(lin)
    }

    /// Parent, isLeft and operands from the scene's operators.
    fn link(&mut self, scene: &Scene, index: &[u32], swap: &[bool]) {
        for (k, &i) in self.order.iter().enumerate() {
            match scene.nodes()[i] {
                Node::Operator { left, right, .. } => {
                    let (l, r) = if swap[i] { (right, left) } else { (left, right) };
                    let (l, r) = (index[l], index[r]);
                    self.children[k] = [l, r];
                    self.parent[l as usize] = k as u32;
                    self.parent[r as usize] = k as u32;
                    self.is_left[l as usize] = true;
                }
                // A unary node's operand counts as a left one: no traversal
                // ever waits for a second operand there.
                Node::Unary { child, .. } => {
                    let c = index[child];
                    self.children[k][0] = c;
                    self.parent[c as usize] = k as u32;
                    self.is_left[c as usize] = true;
                }
                Node::Primitive(_) => {}
            }
        }
    }

    /// Node words, parameters and ABVs.
    fn fill(&mut self, scene: &Scene) {
        for k in 0..self.order.len() {
            let node = &scene.nodes()[self.order[k]];
            let mut x = (type_code(node) << NODE_TYPE_SHIFT) | self.parent[k];
            if self.is_left[k] {
                x |= NODE_LEFT_BIT;
            }
            let mut y = self.params.len() as u32;
            let mut w = 0;
            match node {
                Node::Primitive(p) => {
                    x |= NODE_LEAF_BIT;
                    self.params.extend(warp_rows(p));
                    y = self.params.len() as u32;
                    self.params.extend(primitive_rows(p));
                    if let Shape::Formula(f) = &p.shape {
                        self.params[y as usize + super::rows::LEAF_INDEX_ROW][3] = self.leaf_index(f) as f32;
                    }
                    let a = roi::abv(p, self.roi[k].hi);
                    self.abv.extend(abv_rows(&a));
                    self.abvs.push(a);
                    w = self.primitives.len() as u32;
                    self.primitives.push(k as u32);
                }
                Node::Operator { op, .. } => {
                    self.params.push(op.row().map(|v| v as f32));
                }
                Node::Unary { op, .. } => self.params.push(unary_row(op)),
            }
            self.nodes.push([x, y, self.fast[k], w]);
        }
    }

    /// Sets [`NODE_UNION_PATH_BIT`] on every leaf whose ancestors are all
    /// sharp unions, and [`NODE_COMB_BIT`] on every leaf hanging off the
    /// left spine of union-style operators: top-down, a parent after its
    /// children in post-order.
    fn mark_union_paths(&mut self) {
        let n = self.nodes.len();
        let ty = |w: [u32; 4]| (w[0] >> NODE_TYPE_SHIFT) & NODE_TYPE_MASK;
        let union_style = |w: [u32; 4]| w[0] & NODE_LEAF_BIT == 0 && (UNION..OFFSET).contains(&ty(w)) && (ty(w) - UNION) % 3 == 0;
        let mut path = vec![false; n];
        let mut spine = vec![false; n];
        for k in (0..n).rev() {
            let p = self.parent[k] as usize;
            let w = self.nodes[k];
            path[k] = p >= n || (path[p] && ty(self.nodes[p]) == UNION);
            spine[k] = union_style(w) && (p >= n || (spine[p] && self.is_left[k]));
            if self.is_leaf(k as u32) {
                debug_assert!(ty(w) < 64, "a leaf type code must leave the type field's bits 28-29 to the flags");
                if path[k] {
                    self.nodes[k][0] |= NODE_UNION_PATH_BIT;
                }
                if p >= n || spine[p] {
                    self.nodes[k][0] |= NODE_COMB_BIT;
                }
            }
        }
    }

    /// Whether leaf `k` has only sharp unions above it
    /// (`NODE_UNION_PATH_BIT`).
    pub fn on_union_path(&self, k: u32) -> bool {
        self.nodes[k as usize][0] & NODE_UNION_PATH_BIT != 0
    }

    /// Whether leaf `k` hangs off the left spine of union-style operators
    /// (`NODE_COMB_BIT`).
    pub fn on_comb(&self, k: u32) -> bool {
        self.nodes[k as usize][0] & NODE_COMB_BIT != 0
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.order.len()
    }

    /// Never true.
    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// The root's post-order index, n − 1.
    pub fn root(&self) -> u32 {
        self.order.len() as u32 - 1
    }

    /// Whether node `k` is a primitive.
    pub fn is_leaf(&self, k: u32) -> bool {
        self.nodes[k as usize][0] & NODE_LEAF_BIT != 0
    }

    /// The Lipschitz bound to trace the scene with: 1, or
    /// `SMOOTH_LIPSCHITZ` when it has a compact smooth operator, times
    /// the bound its displacements and voxel grids give
    /// (`roi::field_lipschitz`; 1 without any).
    pub fn lipschitz(&self) -> f64 {
        self.lipschitz
    }

    /// The leaf index of formula leaf `f`: a leaf with the same formula and
    /// bound shares its index and tape.
    fn leaf_index(&mut self, f: &std::sync::Arc<super::leaf::FormulaLeaf>) -> usize {
        if let Some(k) = self.leaves.iter().position(|l| std::sync::Arc::ptr_eq(l, f) || (l.source == f.source && l.lipschitz == f.lipschitz)) {
            return k;
        }
        self.leaves.push(f.clone());
        self.leaves.len() - 1
    }

    /// The first formula leaf that declares no Lipschitz bound, as the
    /// error sphere tracing gives for it (bisection needs none).
    pub fn untraceable_leaf(&self) -> Option<SceneError> {
        self.order.iter().zip(&self.nodes).find_map(|(&i, w)| {
            let leaf = w[0] & NODE_LEAF_BIT != 0 && word_type(w[0]) == FORMULA;
            let y = w[1] as usize + super::rows::LEAF_INDEX_ROW;
            let k = self.params.get(y).map_or(0, |r| r[3] as usize);
            (leaf && self.leaves.get(k).is_some_and(|l| l.lipschitz.is_none())).then(|| {
                SceneError::at(i, "lipschitz", "a formula leaf without a Lipschitz bound cannot be sphere traced: declare one, or render with --method bisect")
            })
        })
    }

    /// The operation of unary node `k` when it stands for a merged chain
    /// of the scene's ([`Linear::new`]); None: the scene node's own.
    pub fn folded_unary(&self, k: u32) -> Option<Unary> {
        self.folded.binary_search_by_key(&k, |e| e.0).ok().map(|j| self.folded[j].1)
    }

    /// Whether node `k` is a unary node.
    pub fn is_unary(&self, k: u32) -> bool {
        is_unary_code((self.nodes[k as usize][0] >> NODE_TYPE_SHIFT) & NODE_TYPE_MASK)
    }
}

/// For every operator, whether to swap its operands, and the root's stack need.
fn operand_order(scene: &Scene) -> Result<(Vec<bool>, u32), (NodeId, String)> {
    let nodes = scene.nodes();
    let mut need = vec![1u32; nodes.len()];
    let mut swap = vec![false; nodes.len()];
    for &i in scene.post_order() {
        if let Node::Unary { child, .. } = nodes[i] {
            need[i] = need[child];
        }
        if let Node::Operator { op, left, right } = nodes[i] {
            let (mut l, mut r) = (need[left], need[right]);
            if op.commutative() && r > l {
                swap[i] = true;
                std::mem::swap(&mut l, &mut r);
            }
            need[i] = l.max(r + 1);
            if need[i] > MAX_STACK {
                return Err((
                    i,
                    format!(
                        "evaluating it needs a stack of {} values, above the limit of {MAX_STACK}: differences nested in their right operand cannot be reordered; nest them on the left",
                        need[i]
                    ),
                ));
            }
        }
    }
    Ok((swap, need[scene.root()]))
}

/// The post-order with operands swapped where `swap` says.
fn ordered_post(scene: &Scene, swap: &[bool]) -> Vec<NodeId> {
    let nodes = scene.nodes();
    let mut out = Vec::with_capacity(nodes.len());
    let mut stack = vec![(scene.root(), false)];
    while let Some((i, expanded)) = stack.pop() {
        match nodes[i] {
            Node::Operator { left, right, .. } if !expanded => {
                let (l, r) = if swap[i] { (right, left) } else { (left, right) };
                stack.push((i, true));
                stack.push((r, false));
                stack.push((l, false));
            }
            Node::Unary { child, .. } if !expanded => {
                stack.push((i, true));
                stack.push((child, false));
            }
            _ => out.push(i),
        }
    }
    out
}

/// Whether a chain on side `left` may jump over `node`: union-like
/// operators on both sides, difference-like on the left only, intersections
/// and unary nodes (which change the value) never.
fn passes(node: &Node, left: bool) -> bool {
    match node {
        Node::Operator { op, .. } => match op.kind {
            OpKind::Union => true,
            OpKind::Difference => left,
            OpKind::Intersection => false,
        },
        _ => false,
    }
}

/// fast(i) of the brief §1.4: from the parent, climb while the node is on
/// the same side as i and passes; the root's is n. Memoised top-down in
/// O(n): jump(m) is where a climb that reaches m (on m's own side) stops.
fn fast_ancestors(parent: &[u32], is_left: &[bool], order: &[NodeId], scene: &Scene) -> Vec<u32> {
    let n = parent.len();
    let root = n - 1;
    let mut jump = vec![root; n];
    for m in (0..root).rev() {
        if !is_operator(scene, order[m]) {
            continue;
        }
        jump[m] = if !passes(&scene.nodes()[order[m]], is_left[m]) {
            m
        } else {
            let p = parent[m] as usize;
            if p == root || is_left[p] != is_left[m] { p } else { jump[p] }
        };
    }
    let mut fast = vec![n as u32; n];
    for i in 0..root {
        let m = parent[i] as usize;
        fast[i] = if m == root || is_left[m] != is_left[i] { m as u32 } else { jump[m] as u32 };
    }
    fast
}

fn is_operator(scene: &Scene, i: NodeId) -> bool {
    !matches!(scene.nodes()[i], Node::Primitive(_))
}

/// The `FEATURE_*` bits of the node types `scene` uses.
fn features(scene: &Scene) -> u32 {
    scene.nodes().iter().fold(0, |acc, n| {
        acc | match n {
            Node::Primitive(p) => (match p.shape {
                Shape::Extrude { profile, .. } | Shape::Revolve { profile, .. } if profile.kind().has_points() => FEATURE_PROFILE | FEATURE_POLYGON,
                Shape::Extrude { .. } | Shape::Revolve { .. } => FEATURE_PROFILE,
                Shape::Grid(_) => FEATURE_GRID,
                Shape::Formula(ref f) => {
                    FEATURE_FORMULA | if f.has_power_loops() { FEATURE_FORMULA_POWERS } else { 0 } | if f.affine() { FEATURE_FORMULA_AFFINE } else { 0 }
                }
                ref shape => shape.analytic().and_then(|(t, _)| t.wgsl).map_or(0, |c| c.feature),
            }) | if p.warp.is_some() { FEATURE_WARP } else { 0 }
                | if matches!(p.shape, Shape::Sphere { .. }) && p.warp.is_none() { 0 } else { FEATURE_SHAPES },
            Node::Operator { op, .. } => if op.join.is_some() { FEATURE_JOIN } else { 0 },
            Node::Unary { op, .. } => FEATURE_UNARY | op.kind().wgsl.feature,
        }
    })
}

/// The error for a scene whose traced bound overflowed: it names the first
/// primitive whose own bound did (at the field its type blames, as a
/// density's range against its radius; a warp's rate against its radius),
/// or the scene.
fn unbounded_slope(scene: &Scene, name: &dyn Fn(NodeId) -> NodeId) -> SceneError {
    let reason = "its Lipschitz bound is not finite, so sphere tracing could not take a step";
    for &i in scene.post_order() {
        if let Node::Primitive(p) = &scene.nodes()[i] {
            if let Some((t, v)) = p.shape.analytic() {
                if let crate::sdf::primitive::Lipschitz::Of { bound, field } = t.lipschitz {
                    if !bound(&v).is_finite() {
                        return SceneError::at(name(i), field, reason);
                    }
                }
            }
            if !p.warp.map_or(1.0, |w| w.lipschitz()).is_finite() {
                return SceneError::at(name(i), "warp.rate", reason);
            }
        }
    }
    SceneError::new("nodes", format!("the scene: {reason}"))
}

/// The bound [`Linear::lipschitz`] returns for `scene`.
fn lipschitz_bound(scene: &Scene) -> f64 {
    // A style that blends (β > 0: Zanni's G), not a join, whose bound is exact.
    let smooth = scene.nodes().iter().any(|n| matches!(n, Node::Operator { op, .. } if matches!(op.typed(), Typed::Style(s, v) if (s.blend)(&v) > 0.0)));
    let base = if smooth { SMOOTH_LIPSCHITZ } else { 1.0 };
    base * roi::field_lipschitz(scene)
}

/// A scene's buffers in the layout of `templates/fields/scene.wgsl`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SceneData {
    /// One word quadruple per post-order node (root last).
    pub nodes: Vec<[u32; 4]>,
    /// Transforms and parameters, a vec4 at a time.
    pub params: Vec<[f32; 4]>,
    /// The node index of every primitive.
    pub prims: Vec<u32>,
    /// Two balls a primitive (centre, radius; +inf bounds nothing): its
    /// augmented bounding ball, then its limit ball, outside which an
    /// intersection above it is inactive (`scene::reach`).
    pub balls: Vec<[f32; 4]>,
    /// The interpreter features the scene needs (`FEATURE_*`
    /// bits): part of the kernel, so a renderer built for one set draws
    /// any scene whose set is within it.
    pub features: u32,
    /// The formulas of its formula leaves, by leaf index (the field source
    /// makes their tapes).
    pub leaves: Vec<std::sync::Arc<super::FormulaLeaf>>,
}

impl SceneData {
    /// The node texture: texel 0 holds the node and primitive counts, node
    /// i is texel i + 1 (`scene_node` in templates/fields/scene.wgsl). The
    /// primitive count is the scatter pass's, not its buffer's length: a
    /// buffer is at least 16 bytes, and the padding of a scene of fewer than
    /// four primitives read as more copies of its first.
    pub fn node_texels(&self) -> crate::layout::Texels<[u32; 4]> {
        crate::layout::Texels::from_rows(Some([self.nodes.len() as u32, self.prims.len() as u32, 0, 0]), &self.nodes)
    }

    /// The parameter texture: row i of `params` is texel i.
    pub fn param_texels(&self) -> crate::layout::Texels<[f32; 4]> {
        crate::layout::Texels::from_rows(None, &self.params)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Builder, Operator, Primitive, Shape};

    fn sphere(b: &mut Builder) -> NodeId {
        b.primitive(Primitive::new(Shape::Sphere { radius: 1.0 }))
    }

    #[test]
    fn right_combs_of_unions_are_turned_into_left_combs() {
        let mut b = Builder::default();
        let leaves: Vec<NodeId> = (0..5).map(|_| sphere(&mut b)).collect();
        let mut acc = leaves[4];
        for &l in leaves[..4].iter().rev() {
            acc = b.operator(Operator::UNION, l, acc);
        }
        let scene = b.finish(acc).unwrap();
        let lin = Linear::new(&scene).unwrap();
        assert_eq!(lin.stack_depth, 2);
        assert_eq!(lin.parent[lin.root() as usize], 9);
        assert_eq!(lin.nodes[8][0] & NODE_PARENT_MASK, 9);
        assert!(lin.is_leaf(0) && !lin.is_leaf(8));
    }

    #[test]
    fn right_nested_differences_beyond_the_limit_are_refused() {
        let mut b = Builder::default();
        let mut acc = sphere(&mut b);
        for _ in 0..MAX_STACK {
            let l = sphere(&mut b);
            acc = b.operator(Operator::DIFFERENCE, l, acc);
        }
        let e = Linear::new(&b.finish(acc).unwrap()).unwrap_err();
        assert!(e.to_string().starts_with("nodes[64]: evaluating it needs a stack of 33 values, above the limit of 32"), "{e}");
    }

    #[test]
    fn constants_are_generated() {
        let w = wgsl_constants();
        assert!(w.contains("const NODE_SPHERE: u32 = 1u;\n"));
        assert!(w.contains("const NODE_SMOOTH_DIFFERENCE: u32 = 37u;\n"));
        assert!(w.contains("const NODE_LEAF_BIT: u32 = 2147483648u;\n"));
        naga::front::wgsl::parse_str(&w).expect("the constants are valid WGSL");
    }
}
