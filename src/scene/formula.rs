//! A scene as formula text built from the distance forms of [`crate::sdf`],
//! so the compiled path can render the same field (and the two paths can
//! be compared for depth and for time).
//!
//! One definition per node, in post-order (`n3 = union(n1, n2);`), so the
//! text nests only as deep as one primitive's transforms, whatever the
//! tree's depth (the parser allows 200 levels). Compact smooth operators
//! become `compact_union`, `compact_intersect` and `compact_subtract`.
//! Only small scenes fit: the formula language reads at most 64 KiB of text
//! (about 500 primitives) and compiles at most 50,000 operations.

use super::operator::Typed;
use super::{Node, Primitive, Profile, Scene, Shape};
use crate::syntax::parser::MAX_SOURCE_BYTES;

/// Why a scene has no formula.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NoFormula {
    /// The formula would exceed the formula language's size limit.
    #[error("the scene's formula would be {bytes} bytes or more, above the formula language's limit of {limit} bytes")]
    TooLarge {
        /// Bytes written when the limit was passed.
        bytes: usize,
        /// The limit.
        limit: usize,
    },
    /// A node type the formula language has no form for.
    #[error("nodes[{node}] is a {kind}, which the formula language has no form for")]
    NoForm {
        /// The scene node.
        node: usize,
        /// Its type.
        kind: &'static str,
    },
}

impl Scene {
    /// The scene as a formula program (`to_formula`).
    pub fn to_formula(&self) -> Result<String, NoFormula> {
        to_formula(self)
    }
}

/// A number as the formula language reads it back exactly.
fn num(v: f64) -> String {
    format!("{v:?}")
}

fn args(v: &[f64]) -> String {
    v.iter().map(|&x| num(x)).collect::<Vec<_>>().join(", ")
}

/// `translate(t, rotate(axis, angle, scale(s, form)))`, identity parts left
/// out; `None` for a shape the formula language has no form for (a grid).
pub fn primitive_formula(p: &Primitive) -> Option<String> {
    let mut s = match p.shape {
        Shape::Grid(_) => return None,
        Shape::Formula(ref f) => f.formula(&num, MAX_SOURCE_BYTES)?,
        Shape::Extrude { profile, half_height } => format!("extrude({}, {})", num(half_height), profile_formula(&profile)),
        Shape::Revolve { profile, offset } => format!("revolve({}, {})", num(offset), profile_formula(&profile)),
        ref shape => {
            let (t, v) = shape.analytic()?;
            format!("{}({})", t.info.name, args(&v))
        }
    };
    s = placed(s, &p.transform);
    // A warp turns the primitive as placed in the warp's frame, which the
    // frame's transform then places in the world.
    if let Some(w) = &p.warp {
        s = placed(format!("{}({}, {s})", w.kind.name(), num(w.rate)), &w.frame);
    }
    Some(s)
}

/// `translate(t, rotate(axis, angle, scale(s, form)))`, identity parts left out.
fn placed(mut s: String, t: &super::Transform) -> String {
    if t.scale != 1.0 {
        s = format!("scale({}, {s})", num(t.scale));
    }
    if let Some(r) = &t.rotate {
        s = format!("rotate({}, {}, {s})", args(&r.axis), num(r.angle));
    }
    if t.translate != [0.0; 3] {
        s = format!("translate({}, {s})", args(&t.translate));
    }
    s
}

/// A profile as the formula language's 2D form of the same name.
fn profile_formula(p: &Profile) -> String {
    let (t, v) = p.typed();
    format!("{}({})", t.info.name, args(&v))
}

/// The scene as a formula program; an error if it passes the formula
/// language's 64 KiB limit.
pub fn to_formula(scene: &Scene) -> Result<String, NoFormula> {
    let mut out = String::new();
    let name = |i: usize| format!("n{i}");
    for &i in scene.post_order() {
        let rhs = match &scene.nodes()[i] {
            Node::Primitive(p) => primitive_formula(p).ok_or(NoFormula::NoForm { node: i, kind: p.shape.kind().name() })?,
            Node::Operator { op, left, right } => {
                let form = match op.typed() {
                    Typed::Style(s, _) => &s.forms[op.kind as usize],
                    Typed::Join(t, _) => &t.forms[op.kind as usize],
                };
                let params: String = op.fields().iter().map(|&(_, v)| format!(", {}", num(v))).collect();
                format!("{}({}, {}{params})", form.name, name(*left), name(*right))
            }
            Node::Unary { op, child } => format!("{}({}, {})", op.kind().name(), args(&op.values()), name(*child)),
        };
        out += &format!("{} = {rhs};\n", name(i));
        if out.len() > MAX_SOURCE_BYTES {
            return Err(NoFormula::TooLarge { bytes: out.len(), limit: MAX_SOURCE_BYTES });
        }
    }
    out += &name(scene.root());
    out.push('\n');
    if out.len() > MAX_SOURCE_BYTES {
        return Err(NoFormula::TooLarge { bytes: out.len(), limit: MAX_SOURCE_BYTES });
    }
    Ok(out)
}
