//! Writing a scene as `.scene.json` text (the reading is `format`'s):
//! one node a line, numbers in the shortest form that reads back the same,
//! identity transforms left out, a warped primitive's warp as its `warp`
//! object.

use super::{shape_fields, VERSION};
use crate::scene::{Node, Profile, Scene, Shape, Transform};

/// A number as JSON (shortest form that reads back the same f64).
fn num(v: f64) -> String {
    serde_json::to_string(&v).unwrap_or_else(|_| "null".into())
}

fn nums(v: &[f64]) -> String {
    let parts: Vec<String> = v.iter().map(|&x| num(x)).collect();
    format!("[{}]", parts.join(", "))
}

/// A transform's fields that differ from the identity, each after ", ".
fn transform_json(t: &Transform) -> String {
    let mut s = String::new();
    if t.translate != [0.0; 3] {
        s += &format!(", \"translate\": {}", nums(&t.translate));
    }
    if let Some(r) = &t.rotate {
        s += &format!(", \"rotate\": {}", nums(&[r.axis[0], r.axis[1], r.axis[2], r.angle]));
    }
    if t.scale != 1.0 {
        s += &format!(", \"scale\": {}", num(t.scale));
    }
    s
}

/// One node as a JSON object on one line.
pub(crate) fn node_json(n: &Node) -> String {
    let mut s = String::from("{");
    match n {
        Node::Primitive(p) => {
            s += &format!("\"type\": \"{}\"", p.shape.kind().name());
            let values: Vec<String> = match p.shape {
                Shape::Extrude { profile, half_height } => vec![profile_json(&profile), num(half_height)],
                Shape::Revolve { profile, offset } => vec![profile_json(&profile), num(offset)],
                Shape::Grid(ref g) => {
                    let file = serde_json::to_string(&g.file).unwrap_or_else(|_| "\"\"".into());
                    match g.placement {
                        Some(pl) => vec![file, num(pl.spacing), nums(&pl.origin)],
                        None => vec![file],
                    }
                }
                Shape::Formula(ref f) => {
                    let mut v = vec![serde_json::to_string(&f.source).unwrap_or_else(|_| "\"\"".into()), nums(&f.bounds())];
                    v.extend(f.lipschitz.map(num));
                    v
                }
                ref shape => {
                    let (t, v) = shape.analytic().expect("a shape given by numbers");
                    let mut at = 0;
                    let mut values = Vec::with_capacity(t.fields.len());
                    for field in t.fields {
                        values.push(if field.len == 1 { num(v[at]) } else { nums(&v[at..at + field.len]) });
                        at += field.len;
                    }
                    values
                }
            };
            for (k, v) in shape_fields(p.shape.kind()).iter().zip(values) {
                s += &format!(", \"{k}\": {v}");
            }
            s += &transform_json(&p.transform);
            if let Some(w) = &p.warp {
                s += &format!(", \"warp\": {{\"type\": \"{}\", \"rate\": {}{}}}", w.kind.name(), num(w.rate), transform_json(&w.frame));
            }
        }
        Node::Operator { op, left, right } => {
            s += &format!("\"type\": \"{}\", \"left\": {left}, \"right\": {right}", op.name());
            for (name, v) in op.fields() {
                s += &format!(", \"{name}\": {}", num(v));
            }
        }
        Node::Unary { op, child } => {
            s += &format!("\"type\": \"{}\", \"child\": {child}", op.kind().name());
            for (k, v) in op.kind().fields.iter().zip(op.values()) {
                s += &format!(", \"{k}\": {}", num(v));
            }
        }
    }
    s + "}"
}

/// A profile as a JSON object.
fn profile_json(p: &Profile) -> String {
    use crate::sdf::profile::FieldKind;
    let (t, v) = p.typed();
    let mut s = format!("{{\"type\": \"{}\"", t.scene_name);
    let mut at = 0;
    for f in t.fields {
        let value = match f.kind {
            FieldKind::Number => num(v[at]),
            FieldKind::Pair { .. } => nums(&v[at..at + 2]),
            FieldKind::Points => format!("[{}]", v[at..].chunks(2).map(nums).collect::<Vec<_>>().join(", ")),
        };
        at = match f.kind {
            FieldKind::Number => at + 1,
            FieldKind::Pair { .. } => at + 2,
            FieldKind::Points => v.len(),
        };
        s += &format!(", \"{}\": {value}", f.name);
    }
    s + "}"
}

/// The scene as version-1 JSON, one node per line, in stored order.
pub fn to_json(scene: &Scene) -> String {
    let mut s = format!("{{\"isotrace_scene\": {VERSION}, \"root\": {},\n \"nodes\": [\n", scene.root());
    let n = scene.nodes().len();
    for (i, node) in scene.nodes().iter().enumerate() {
        s += "  ";
        s += &node_json(node);
        s += if i + 1 < n { ",\n" } else { "\n" };
    }
    s + " ]}\n"
}

