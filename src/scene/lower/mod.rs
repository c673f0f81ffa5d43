//! Formula → scene: a formula built only from the distance forms of
//! [`crate::sdf`] (primitives, transforms, sharp and smooth CSG) with
//! constant arguments is a blobtree, and lowers to a [`Scene`] that the
//! data-driven scene field renders without generating a shader.
//!
//! The walk is over the syntax tree, not the IR: the IR has already
//! expanded every form into arithmetic of x, y and z, where a primitive is
//! no longer recognisable. Scalar arguments are evaluated in f64 here
//! (numbers, `pi`, `e`, parameters with their current values, definitions,
//! arithmetic and the numeric functions), so a parameter change re-lowers
//! to new buffers, never to a new shader.
//!
//! Transforms are pushed down to the leaves, composed as similarity
//! transforms (t₁ + R₁s₁(t₂ + R₂s₂q)), because a scene keeps one transform
//! per primitive. Definitions used twice are lowered twice (a scene is a
//! tree, not a graph); the node count is bounded while building.
//!
//! **Smooth operators.** `smooth_union(a, b, k)` (Zanni et al. eq. 8-11)
//! becomes the compact G with β = k and r_o = 2k, the scene's only smooth
//! operator. The two fields differ away from the surface but never in sign:
//! inside R_o, G is the smooth operator with its blend range k scaled by
//! 1 ∓ 6x/(6r_o − k), x being the smooth operator's own value, and the
//! blend d(a, b, k) = max(k − |a − b|, 0)³/(6k²) changes by at most 1/6 of a
//! change of k, so |G − x| ≤ k|x|/(6r_o − k) < |x|; outside R_o both
//! operands are beyond 7k/6, where blend and sharp operator agree in sign.
//! So the zero set (the picture) is the same; `src/tests/scene_lower.rs` checks
//! the signs by sampling.

use super::placement::Placement;
use super::warp::WarpKind;
use super::{Builder, Join, OpKind, Operator, Primitive, Profile, Rotation, Scene, Shape, Transform, Unary};
use crate::diag::Span;
use crate::ir::{Func1, Func2, Func3, NodeId as IrNode, Op};
use crate::sdf::operator::OperatorStyle;
use crate::sdf::{self, Form};
use crate::syntax::ast::{BinOp, Call, Expr, ExprKind, Program};
use glam::{DQuat, DVec3};
use std::collections::HashMap;
use std::rc::Rc;

mod written;

/// Why a formula is not a blobtree (or not a valid scene), at a span of
/// the formula.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{reason}")]
pub struct NotBlobtree {
    /// What is not a blobtree there.
    pub reason: String,
    /// Where.
    pub span: Span,
}

fn not(reason: impl Into<String>, span: Span) -> NotBlobtree {
    NotBlobtree { reason: reason.into(), span }
}

/// A shape under construction: transforms not yet pushed to the leaves.
#[derive(Debug)]
enum Tree {
    Leaf(Primitive, Span),
    Op(Operator, Rc<Tree>, Rc<Tree>, Span),
    Unary(Unary, Rc<Tree>, Span),
    Moved(Transform, Rc<Tree>),
    /// Reflected across the plane through the origin with this normal.
    Reflected([f64; 3], Rc<Tree>),
    /// Twisted or bent about the z axis of the frame it is in.
    Warped(WarpKind, f64, Rc<Tree>, Span),
}

#[derive(Debug, Clone)]
enum Val {
    Num(f64),
    Shape(Rc<Tree>),
    /// A 2D form, waiting for `extrude` or `revolve`.
    Profile(Profile, Span),
}

/// Lowers `program` (a formula that compiled) to a scene; `param` gives a
/// parameter's current value by name.
pub fn lower(program: &Program, param: &dyn Fn(&str) -> Option<f64>) -> Result<Scene, NotBlobtree> {
    let body = program.body();
    if program.surfaces.len() > 1 {
        return Err(not("a scene draws one surface; the formula has several", program.surfaces[1].expr.span));
    }
    if let Some(c) = program.surfaces[0].conditions.first() {
        return Err(not("a scene has no 'where' conditions", c.span));
    }
    let defs = program.definitions.iter().enumerate().map(|(i, d)| (d.name.as_str(), i)).collect();
    let n = program.definitions.len();
    let mut w = Walker { program, param, defs, memo: vec![None; n], active: vec![false; n] };
    let tree = match w.eval(body)? {
        Val::Shape(t) => t,
        Val::Num(_) => return Err(not("the formula is a constant, not a shape", body.span)),
        Val::Profile(_, span) => return Err(not("a 2D profile is a blobtree node only inside extrude or revolve", span)),
    };
    let mut b = Builder::default();
    let mut spans = vec![];
    let root = build(&tree, &mut b, &mut spans)?;
    b.finish(root).map_err(|e| {
        // `nodes[3].radius` → node 3 (its span), field `radius`.
        let (node, field) = match e.path.strip_prefix("nodes[").and_then(|r| r.split_once(']')) {
            Some((i, rest)) => (i.parse::<usize>().ok(), rest.trim_start_matches('.').to_string()),
            None => (None, e.path.clone()),
        };
        let span = node.and_then(|i| spans.get(i).copied()).unwrap_or(body.span);
        let what = if field.is_empty() { String::new() } else { format!("{field} ") };
        not(format!("not a valid scene node: {what}{}", e.reason), span)
    })
}

struct Walker<'a> {
    program: &'a Program,
    param: &'a dyn Fn(&str) -> Option<f64>,
    /// Definition index by name (the front end refuses redefinitions).
    defs: HashMap<&'a str, usize>,
    /// Each definition's value, once walked.
    memo: Vec<Option<Val>>,
    /// Definitions being walked (the front end has already refused cycles;
    /// this guards the walk itself).
    active: Vec<bool>,
}

impl Walker<'_> {
    fn eval(&mut self, e: &Expr) -> Result<Val, NotBlobtree> {
        match &e.kind {
            ExprKind::Number(v) => Ok(Val::Num(*v)),
            ExprKind::Name(n) => self.name(n, e.span),
            ExprKind::Neg(a) => match self.eval(a)? {
                Val::Num(v) => Ok(Val::Num(-v)),
                _ => Err(not("a shape under unary minus is not a blobtree node", e.span)),
            },
            ExprKind::Binary(op, a, b) => {
                if let Some(ball) = (*op == BinOp::Sub).then(|| self.ball(a, b, e.span)).flatten() {
                    return Ok(ball);
                }
                let (x, y) = (self.num(a)?, self.num(b)?);
                Ok(Val::Num(match op {
                    BinOp::Add => x + y,
                    BinOp::Sub => x - y,
                    BinOp::Mul => x * y,
                    BinOp::Div => x / y,
                    BinOp::Pow if y.fract() == 0.0 && y.abs() < 1e9 => x.powi(y as i32),
                    BinOp::Pow => crate::reference::pow_pos(x, y),
                }))
            }
            ExprKind::Call(c) => self.call(c, e.span),
        }
    }

    /// A scalar argument; a shape here is arithmetic on a shape.
    fn num(&mut self, e: &Expr) -> Result<f64, NotBlobtree> {
        match self.eval(e)? {
            Val::Num(v) => Ok(v),
            _ => Err(not("arithmetic on a shape is not a blobtree node", e.span)),
        }
    }

    fn shape(&mut self, e: &Expr) -> Result<Rc<Tree>, NotBlobtree> {
        match self.eval(e)? {
            Val::Shape(t) => Ok(t),
            Val::Num(_) => Err(not("a number where the form takes a shape", e.span)),
            Val::Profile(_, span) => Err(not("a 2D profile is a blobtree node only inside extrude or revolve", span)),
        }
    }

    /// The 2D profile argument of `extrude` or `revolve`.
    fn profile(&mut self, e: &Expr) -> Result<Profile, NotBlobtree> {
        match self.eval(e)? {
            Val::Profile(p, _) => Ok(p),
            _ => Err(not("extrude and revolve take a 2D profile here (circle, rect, roundrect, capsule2d or polygon)", e.span)),
        }
    }

    fn name(&mut self, n: &str, span: Span) -> Result<Val, NotBlobtree> {
        if let Some(&i) = self.defs.get(n) {
            if let Some(v) = &self.memo[i] {
                return Ok(v.clone());
            }
            if self.active[i] {
                return Err(not(format!("'{n}' refers to itself"), span));
            }
            self.active[i] = true;
            let v = self.eval(&self.program.definitions[i].value);
            self.active[i] = false;
            let v = v?;
            self.memo[i] = Some(v.clone());
            return Ok(v);
        }
        match n {
            "pi" => Ok(Val::Num(std::f64::consts::PI)),
            "e" => Ok(Val::Num(std::f64::consts::E)),
            "x" | "y" | "z" | "t" => Err(not(format!("'{n}' outside a distance form: the field is not built from primitives alone"), span)),
            _ => (self.param)(n).map(Val::Num).ok_or_else(|| not(format!("'{n}' has no value"), span)),
        }
    }

    fn call(&mut self, c: &Call, span: Span) -> Result<Val, NotBlobtree> {
        if let Some(info) = sdf::lookup(&c.name) {
            if let Some(p) = self.profile_form(info.form, &c.args)? {
                return Ok(Val::Profile(p, span));
            }
            return self.form(info.form, c, span).map(Val::Shape);
        }
        if c.name == "min" || c.name == "max" {
            return self.min_max(c, span);
        }
        let a: Vec<f64> = c.args.iter().map(|e| self.num(e)).collect::<Result<_, _>>()?;
        let z: IrNode = 0;
        let op = if let Some(&f) = Func1::ALL.iter().find(|f| f.name() == c.name) {
            Op::Call1(f, z)
        } else {
            match c.name.as_str() {
                "pow" => Op::Call2(Func2::Pow, z, z),
                "atan2" => Op::Call2(Func2::Atan2, z, z),
                "min" => return Ok(Val::Num(a.iter().copied().fold(f64::INFINITY, f64::min))),
                "max" => return Ok(Val::Num(a.iter().copied().fold(f64::NEG_INFINITY, f64::max))),
                "clamp" => Op::Call3(Func3::Clamp, z, z, z),
                "mix" => Op::Call3(Func3::Mix, z, z, z),
                _ => return Err(not(format!("'{}' is not a distance form or a numeric function", c.name), c.name_span)),
            }
        };
        Ok(Val::Num(crate::reference::scalar_op(&op, &a)))
    }
}

/// Most nodes a lowered scene may have: definitions used several times are
/// copied, and a formula of a few kilobytes could otherwise ask for
/// billions (`a = union(s, s); b = union(a, a); …`).
pub const MAX_LOWERED_NODES: usize = 1_000_000;

impl Walker<'_> {
    fn nums<const N: usize>(&mut self, args: &[Expr]) -> Result<[f64; N], NotBlobtree> {
        let mut v = [0.0; N];
        for (k, a) in args[..N].iter().enumerate() {
            v[k] = self.num(a)?;
        }
        Ok(v)
    }

    /// A 2D form's profile; `None` for any other form.
    fn profile_form(&mut self, form: Form, a: &[Expr]) -> Result<Option<Profile>, NotBlobtree> {
        let Form::Profile(t) = form else { return Ok(None) };
        let v: Vec<f64> = a.iter().map(|e| self.num(e)).collect::<Result<_, _>>()?;
        Ok(Some(Profile::from_params(t, &v)))
    }

    /// One distance form (the front end has checked the arity).
    fn form(&mut self, form: Form, c: &Call, span: Span) -> Result<Rc<Tree>, NotBlobtree> {
        let a = &c.args[..];
        let shape = match form {
            Form::Primitive(t) => {
                let given: Vec<f64> = a.iter().map(|e| self.num(e)).collect::<Result<_, _>>()?;
                Shape::from_analytic(t, &t.with_defaults(&given))
            }
            Form::Extrude => Shape::Extrude { half_height: self.num(&a[0])?, profile: self.profile(&a[1])? },
            Form::Revolve => Shape::Revolve { offset: self.num(&a[0])?, profile: self.profile(&a[1])? },
            _ => return self.composite(form, a, span),
        };
        Ok(Rc::new(Tree::Leaf(Primitive::new(shape), span)))
    }

    /// Transforms, operators, warps, copies and unary forms.
    fn composite(&mut self, form: Form, a: &[Expr], span: Span) -> Result<Rc<Tree>, NotBlobtree> {
        match form {
            Form::Translate | Form::Rotate | Form::Scale => self.transformed(form, a),
            Form::Operator(style, kind) => self.operator(style, kind, a, span),
            Form::Join(t, kind) => {
                let (l, r, size) = (self.shape(&a[0])?, self.shape(&a[1])?, self.num(&a[2])?);
                Ok(Rc::new(Tree::Op(Operator::joined(kind, Join::from_size(t, size)), l, r, span)))
            }
            Form::Twist | Form::Bend => {
                let kind = if form == Form::Twist { WarpKind::Twist } else { WarpKind::Bend };
                Ok(Rc::new(Tree::Warped(kind, self.num(&a[0])?, self.shape(&a[1])?, span)))
            }
            Form::Repeat | Form::Mirror => self.copied(form, a, span),
            Form::Unary(t) => {
                let n = t.param_count();
                let v: Vec<f64> = a[..n].iter().map(|e| self.num(e)).collect::<Result<_, _>>()?;
                Ok(Rc::new(Tree::Unary(Unary::from_values(t, &v), self.shape(&a[n])?, span)))
            }
            _ => {
                let name = sdf::forms().find(|i| i.form == form).map_or("?", |i| i.name);
                Err(not(format!("'{name}' has no blobtree node"), span))
            }
        }
    }

    /// `translate`, `rotate` and `scale`: the shape under a transform, not
    /// yet pushed to its leaves.
    fn transformed(&mut self, form: Form, a: &[Expr]) -> Result<Rc<Tree>, NotBlobtree> {
        let (t, shape) = match form {
            Form::Translate => (Transform { translate: self.nums(a)?, ..Transform::default() }, &a[3]),
            Form::Rotate => {
                let [x, y, z, angle] = self.nums(a)?;
                (Transform { rotate: Some(Rotation { axis: [x, y, z], angle }), ..Transform::default() }, &a[4])
            }
            _ => (Transform { scale: self.num(&a[0])?, ..Transform::default() }, &a[1]),
        };
        Ok(Rc::new(Tree::Moved(t, self.shape(shape)?)))
    }

    /// An operator style's form: its operands joined left to right by the
    /// operator the scene keeps the style as, for the parameters given
    /// (defaults for those left out).
    fn operator(&mut self, style: &'static OperatorStyle, kind: OpKind, a: &[Expr], span: Span) -> Result<Rc<Tree>, NotBlobtree> {
        let n = style.operand_count(a.len());
        let mut acc = self.shape(&a[0])?;
        let mut rest = vec![];
        for e in &a[1..n] {
            rest.push(self.shape(e)?);
        }
        let given: Vec<f64> = a[n..].iter().map(|e| self.num(e)).collect::<Result<_, _>>()?;
        let op = Operator::styled(kind, style, &style.with_defaults(&given));
        for r in rest {
            acc = Rc::new(Tree::Op(op, acc, r, span));
        }
        Ok(acc)
    }

    /// `repeat` and `mirror`: copies of the shape, a union.
    fn copied(&mut self, form: Form, a: &[Expr], span: Span) -> Result<Rc<Tree>, NotBlobtree> {
        if form == Form::Mirror {
            let n: [f64; 3] = self.nums(a)?;
            if n == [0.0; 3] {
                return Err(not("the mirror plane's normal must not be zero", a[0].span));
            }
            return Ok(copies(&Copies::Mirror { normal: n }, self.shape(&a[3])?, span));
        }
        let spacing: [f64; 3] = self.nums(a)?;
        let counts: Vec<f64> = a[3..6].iter().map(|e| self.num(e)).collect::<Result<_, _>>()?;
        let n = sdf::repeat_counts(|k| Some(counts[k - 3]), |k, m| not(m, a[k].span))?;
        Ok(copies(&Copies::Repeat { spacing, count: n }, self.shape(&a[6])?, span))
    }
}

/// `outer` after `inner`: p ↦ t₁ + R₁s₁(t₂ + R₂s₂q).
fn compose(outer: &Transform, inner: &Transform) -> Transform {
    let quat = |r: &Option<Rotation>| match r {
        Some(r) => DQuat::from_axis_angle(DVec3::from(r.axis).normalize(), r.angle),
        None => DQuat::IDENTITY,
    };
    let (qo, qi) = (quat(&outer.rotate), quat(&inner.rotate));
    let t = DVec3::from(outer.translate) + qo * (DVec3::from(inner.translate) * outer.scale);
    let rotate = match (&outer.rotate, &inner.rotate) {
        (None, None) => None,
        (Some(r), None) | (None, Some(r)) => Some(*r),
        _ => {
            let (axis, angle) = (qo * qi).normalize().to_axis_angle();
            Some(Rotation { axis: axis.into(), angle })
        }
    };
    Transform { translate: t.into(), rotate, scale: outer.scale * inner.scale }
}

/// A unary node under transform `tf` (whose scale multiplies values), as
/// its type moves (`UnaryType::moved`). A scene's unary node has no frame
/// of its own, so a transform over a pattern fixed in the world (the
/// gyroid, the noise) is not a blobtree node.
fn moved_unary(op: &Unary, tf: &Placement, span: Span) -> Result<Unary, NotBlobtree> {
    let (t, v) = op.typed();
    match t.moved {
        Some(moved) => Ok(Unary::from_values(t, &moved(&v, tf.scale()))),
        None if tf.is_identity() => Ok(*op),
        None => Err(not(format!("a transform over '{}' is not a blobtree node (its pattern is fixed in the world): transform its operand instead", op.kind().name()), span)),
    }
}

/// Builds the scene in post-order with an explicit stack (an n-ary union
/// of thousands of shapes is a comb that deep); `spans[i]` is where node i
/// was written.
fn build(tree: &Rc<Tree>, b: &mut Builder, spans: &mut Vec<Span>) -> Result<usize, NotBlobtree> {
    // Below a warp: the warp, its frame being the frame it was met in.
    type Warping = Option<(WarpKind, f64, Transform)>;
    enum Task<'t> {
        Visit(&'t Tree, Placement, Warping),
        Combine(Operator, Span),
        Wrap(Unary, Span),
    }
    let mut stack = vec![Task::Visit(tree, Placement::identity(), None)];
    let mut out: Vec<usize> = vec![];
    while let Some(task) = stack.pop() {
        let (id, span) = match task {
            Task::Visit(Tree::Leaf(p, span), tf, w) => {
                let mut p = tf.place(p, compose).ok_or_else(|| not("a voxel grid or a twisted or bent shape cannot be mirrored", *span))?;
                if let Some((kind, rate, frame)) = w {
                    if p.warp.is_some() {
                        return Err(not("a twist or bend inside another is not a blobtree node (a primitive carries one warp)", *span));
                    }
                    p.warp = Some(super::warp::Warp { kind, rate, frame, clamp: None });
                }
                (b.primitive(p), *span)
            }
            Task::Visit(Tree::Moved(t, sub), tf, w) => {
                stack.push(Task::Visit(sub, tf.then(t, compose), w));
                continue;
            }
            Task::Visit(Tree::Reflected(n, sub), tf, w) => {
                stack.push(Task::Visit(sub, tf.reflected(DVec3::from(*n)), w));
                continue;
            }
            Task::Visit(Tree::Warped(kind, rate, sub, span), tf, w) => {
                let Placement::Plain(frame) = tf else {
                    return Err(not(format!("a mirrored '{}' is not a blobtree node (reflect its operand instead)", kind.name()), *span));
                };
                if w.is_some() {
                    return Err(not("a twist or bend inside another is not a blobtree node (a primitive carries one warp)", *span));
                }
                stack.push(Task::Visit(sub, Placement::identity(), Some((*kind, *rate, frame))));
                continue;
            }
            Task::Visit(Tree::Op(op, l, r, span), tf, w) => {
                stack.push(Task::Combine(*op, *span));
                stack.push(Task::Visit(r, tf.clone(), w));
                stack.push(Task::Visit(l, tf, w));
                continue;
            }
            Task::Combine(op, span) => {
                let r = out.pop().expect("two operands");
                let l = out.pop().expect("two operands");
                (b.operator(op, l, r), span)
            }
            Task::Visit(Tree::Unary(op, sub, span), tf, w) => {
                if w.is_some() && op.kind().moved.is_none() {
                    return Err(not(format!("'{}' under a twist or bend is not a blobtree node (its pattern is fixed in the world)", op.kind().name()), *span));
                }
                stack.push(Task::Wrap(moved_unary(op, &tf, *span)?, *span));
                stack.push(Task::Visit(sub, tf, w));
                continue;
            }
            Task::Wrap(op, span) => {
                let c = out.pop().expect("an operand");
                (b.unary(op, c), span)
            }
        };
        if b.len() > MAX_LOWERED_NODES {
            return Err(not(format!("the blobtree would have more than {MAX_LOWERED_NODES} nodes (definitions used several times are copied)"), span));
        }
        spans.push(span);
        out.push(id);
    }
    Ok(out.pop().expect("a root"))
}

/// A scene file's `repeat` or `mirror` node: expanded into plain nodes
/// when the file is read ([`expand`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Copies {
    /// A centred grid of copies, `count` a side, `spacing` apart.
    Repeat {
        /// Distance between copies along x, y, z.
        spacing: [f64; 3],
        /// Copies along x, y, z.
        count: [u64; 3],
    },
    /// The operand and its reflection across the plane through the origin
    /// with this normal.
    Mirror {
        /// Not zero.
        normal: [f64; 3],
    },
    /// Not copies: the operand twisted or bent about the z axis of `frame`
    /// (a file's `twist` and `bend` nodes, expanded the same way).
    Warp {
        /// Twist or bend.
        kind: WarpKind,
        /// Radians per unit of the frame's length.
        rate: f64,
        /// World from the warp's frame.
        frame: Transform,
    },
}

/// The union of the copies of `shape` that `c` makes.
fn copies(c: &Copies, shape: Rc<Tree>, span: Span) -> Rc<Tree> {
    match *c {
        Copies::Mirror { normal } => {
            let image = Rc::new(Tree::Reflected(normal, shape.clone()));
            Rc::new(Tree::Op(Operator::UNION, shape, image, span))
        }
        // The operand is in world coordinates: A · warp · A⁻¹.
        Copies::Warp { kind, rate, frame } => {
            let inside = Rc::new(Tree::Moved(super::warp::inverse(&frame), shape));
            Rc::new(Tree::Moved(frame, Rc::new(Tree::Warped(kind, rate, inside, span))))
        }
        Copies::Repeat { spacing, count: n } => {
            let mut acc: Option<Rc<Tree>> = None;
            for i in 0..n[0] {
                for j in 0..n[1] {
                    for k in 0..n[2] {
                        let translate = [0, 1, 2].map(|q| spacing[q] * sdf::repeat_offset([i, j, k][q], n[q]));
                        let copy = Rc::new(Tree::Moved(Transform { translate, ..Transform::default() }, shape.clone()));
                        acc = Some(match acc {
                            Some(l) => Rc::new(Tree::Op(Operator::UNION, l, copy, span)),
                            None => copy,
                        });
                    }
                }
            }
            acc.expect("at least one copy")
        }
    }
}

/// `scene` with its `repeat` and `mirror` nodes (`copies[i]` for node i,
/// which `scene` holds as a placeholder with one operand) expanded into
/// plain nodes, as a formula's `repeat` and `mirror` are: copies, and
/// reflected twins. The error says why a subtree cannot be copied (a
/// mirrored voxel grid, a moved infill).
pub fn expand(scene: &Scene, copies_of: &HashMap<usize, Copies>) -> Result<Scene, NotBlobtree> {
    let nodes = scene.nodes();
    let mut trees: Vec<Option<Rc<Tree>>> = vec![None; nodes.len()];
    let span = Span::default();
    for &i in scene.post_order() {
        let sub = |c: usize, trees: &mut Vec<Option<Rc<Tree>>>| trees[c].take().expect("operands first");
        let t = match (&nodes[i], copies_of.get(&i)) {
            (super::Node::Unary { child, .. }, Some(c)) => copies(c, sub(*child, &mut trees), span),
            (super::Node::Primitive(p), _) => Rc::new(Tree::Leaf(p.clone(), span)),
            (super::Node::Operator { op, left, right }, _) => {
                let (l, r) = (sub(*left, &mut trees), sub(*right, &mut trees));
                Rc::new(Tree::Op(*op, l, r, span))
            }
            (super::Node::Unary { op, child }, None) => Rc::new(Tree::Unary(*op, sub(*child, &mut trees), span)),
        };
        trees[i] = Some(t);
    }
    let root = trees[scene.root()].take().expect("the root is in the post-order");
    let mut b = Builder::default();
    let id = build(&root, &mut b, &mut vec![])?;
    b.finish(id).map_err(|e| not(format!("after expanding repeat and mirror: {e}"), span))
}

/// Lowers a compiled formula with its parameter values (in the formula's
/// parameter order, as in `Settings::params`).
pub fn from_formula(f: &crate::Formula, params: &[f32]) -> Result<Scene, NotBlobtree> {
    // The formula compiled, so its text parses.
    let program = crate::syntax::parse(&f.source).map_err(|e| not(e.to_diagnostic().message, Span::default()))?;
    let value = |n: &str| f.ir.params.iter().position(|(p, _)| p == n).and_then(|i| params.get(i)).map(|&v| v as f64);
    lower(&program, &value)
}
