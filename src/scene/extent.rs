//! How far from the origin a scene may reach: the GPU traces it in f32,
//! and its default view (box, eye) is derived from its bounds, so a value
//! that throws the bounds far out (a translate of 1e308, a blend range of
//! 1e300) is refused at load, naming the node and field that did it,
//! rather than surfacing later as a flag the user never gave (`invalid
//! --box …`, `invalid --eye inf,inf,inf`).

use super::roi::{self, Abv, Aabb, Roi};
use super::{Node, NodeId, Scene, SceneError};
use crate::diag::show_number;
use serde_json::Value;

/// The largest coordinate a scene's bounds may reach, in absolute value.
/// The GPU evaluates distances in f32, where the square of a coordinate
/// beyond about 1.8e19 overflows (a length, a dot product); the default
/// eye, a few box sizes away, then stays well below the camera's own
/// limit of 1e30.
pub const MAX_EXTENT: f64 = 1e18;

/// Refuses a scene one of whose primitives reaches beyond [`MAX_EXTENT`]
/// with its augmented bounding volume (or a plane whose position does):
/// the error names the field that made it, the primitive's own or that of
/// a node above it whose range of interest grew the volume.
pub fn check(scene: &Scene, roi: &[Roi]) -> Result<(), SceneError> {
    let nodes = scene.nodes();
    for &i in scene.post_order() {
        let Node::Primitive(p) = &nodes[i] else { continue };
        let reach = match roi::abv(p, roi[i].hi) {
            // A plane bounds nothing: its own numbers place it.
            Abv::Always => largest_field(&nodes[i]).map_or(0.0, |(_, v)| v.abs()),
            a => farthest(&a.aabb()),
        };
        if reach <= MAX_EXTENT {
            continue;
        }
        let own = farthest(&roi::abv(p, 0.0).aabb()) > MAX_EXTENT || matches!(roi::abv(p, 0.0), Abv::Always);
        let culprit = if own { i } else { widest_ancestor(scene, i) };
        let (field, value) = blamed_field(&nodes[culprit]);
        return Err(SceneError::at(
            culprit,
            &field,
            format!(
                "{} puts the scene's bounds at {}, beyond the limit of {} (the GPU computes in f32, where squared distances that far out overflow)",
                show_number(value),
                show_number(reach),
                show_number(MAX_EXTENT)
            ),
        ));
    }
    check_resolution(scene, roi)
}

/// How many times its own size a scene may be from the origin: beyond it
/// f32's resolution there (2⁻²⁴ of the distance) is over 1/16 of the
/// scene, and the picture would be rounding noise.
pub const MAX_DISTANCE_PER_SIZE: f64 = (1u64 << 20) as f64;

/// Refuses a bounded scene farther from the origin than
/// [`MAX_DISTANCE_PER_SIZE`] times its size, naming the largest field of
/// the primitive that reaches farthest.
fn check_resolution(scene: &Scene, roi: &[Roi]) -> Result<(), SceneError> {
    let b = roi::bounds(scene, roi);
    if !b.is_bounded() || b.is_empty() {
        return Ok(());
    }
    let size = (0..3).map(|k| b.max[k] - b.min[k]).fold(0.0, f64::max);
    let far = farthest(&b);
    if far <= size * MAX_DISTANCE_PER_SIZE {
        return Ok(());
    }
    let nodes = scene.nodes();
    let reach = |i: NodeId| match &nodes[i] {
        Node::Primitive(p) => match roi::abv(p, roi[i].hi) {
            Abv::Always => 0.0,
            a => farthest(&a.aabb()),
        },
        _ => 0.0,
    };
    let culprit = scene.post_order().iter().copied().fold(scene.root(), |best, i| if reach(i) > reach(best) { i } else { best });
    let (field, value) = blamed_field(&nodes[culprit]);
    Err(SceneError::at(
        culprit,
        &field,
        format!(
            "{} puts the scene {} from the origin, over {} times its size ({}): the GPU's f32 arithmetic cannot resolve it there; move the scene near the origin",
            show_number(value),
            show_number(far),
            show_number(MAX_DISTANCE_PER_SIZE),
            show_number(size)
        ),
    ))
}

/// The largest absolute coordinate of a box (NaN counts as infinite).
fn farthest(b: &Aabb) -> f64 {
    b.min.iter().chain(&b.max).map(|c| if c.is_nan() { f64::INFINITY } else { c.abs() }).fold(0.0, f64::max)
}

/// Of the ancestors of primitive `i`, the one with the largest parameter:
/// ranges of interest grow by operator ranges and unary parameters on the
/// way down, so that one grew the primitive's volume most.
fn widest_ancestor(scene: &Scene, i: NodeId) -> NodeId {
    let nodes = scene.nodes();
    let mut parent = vec![usize::MAX; nodes.len()];
    for (k, n) in nodes.iter().enumerate() {
        for &c in n.children().iter() {
            parent[c] = k;
        }
    }
    let size = |k: NodeId| largest_field(&nodes[k]).map_or(0.0, |(_, v)| v.abs());
    let mut best = i;
    let mut m = parent[i];
    while m != usize::MAX {
        if best == i || size(m) > size(best) {
            best = m;
        }
        m = parent[m];
    }
    best
}

/// The field a message blames in `node`: its largest, but a blend's β
/// rather than the r_o it implies when r_o was left at its default.
fn blamed_field(node: &Node) -> (String, f64) {
    if let Node::Operator { op, .. } = node {
        if let Some(b) = op.blend.filter(|b| b.range == crate::sdf::operator::DEFAULT_RANGE_FACTOR * b.beta) {
            return ("beta".into(), b.beta);
        }
    }
    largest_field(node).unwrap_or_default()
}

/// The node's numeric field of largest magnitude, as its path within the
/// node (`translate[0]`, `warp.scale`, `beta`) and its value; directions,
/// rotations and operand indices, which place nothing, are left out.
fn largest_field(node: &Node) -> Option<(String, f64)> {
    let v: Value = serde_json::from_str(&super::format::node_json(node)).ok()?;
    let mut best: Option<(String, f64)> = None;
    let mut todo = vec![(String::new(), &v)];
    while let Some((path, v)) = todo.pop() {
        match v {
            Value::Object(m) => {
                for (k, x) in m {
                    if !matches!(k.as_str(), "rotate" | "normal" | "left" | "right" | "child" | "type") {
                        todo.push((if path.is_empty() { k.clone() } else { format!("{path}.{k}") }, x));
                    }
                }
            }
            Value::Array(a) => todo.extend(a.iter().enumerate().map(|(k, x)| (format!("{path}[{k}]"), x))),
            Value::Number(n) => {
                let x = n.as_f64().unwrap_or(0.0);
                if best.as_ref().is_none_or(|b| x.abs() > b.1.abs()) {
                    best = Some((path, x));
                }
            }
            _ => {}
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(json: &str) -> String {
        let scene = crate::scene::format::parse(json).unwrap();
        check(&scene, &roi::ranges(&scene)).unwrap_err().to_string()
    }

    #[test]
    fn the_field_that_throws_the_bounds_out_is_named() {
        let one = |node: &str| err(&format!("{{\"isotrace_scene\": 1, \"root\": 0, \"nodes\": [{node}]}}"));
        assert_eq!(
            one(r#"{"type": "sphere", "radius": 1, "translate": [0, 1e308, 0]}"#),
            "nodes[0].translate[1]: 1e308 puts the scene's bounds at 1e308, beyond the limit of 1e18 (the GPU computes in f32, where squared distances that far out overflow)"
        );
        assert!(one(r#"{"type": "box", "half": [1, 2e20, 1]}"#).starts_with("nodes[0].half[1]: 2e20 puts the scene's bounds at 2e20,"));
        assert!(one(r#"{"type": "plane", "normal": [0, 0, 1], "offset": -1e19}"#).starts_with("nodes[0].offset: -1e19 puts the scene's bounds at 1e19,"));
        let two = |op: &str| {
            err(&format!(
                "{{\"isotrace_scene\": 1, \"root\": 2, \"nodes\": [{{\"type\": \"sphere\", \"radius\": 1}}, {{\"type\": \"sphere\", \"radius\": 1}}, {op}]}}"
            ))
        };
        assert!(two(r#"{"type": "smooth_union", "left": 0, "right": 1, "beta": 1e300}"#).starts_with("nodes[2].beta: 1e300 puts the scene's bounds at 2e300,"));
        let e = err(r#"{"isotrace_scene": 1, "root": 1, "nodes": [{"type": "sphere", "radius": 1}, {"type": "offset", "child": 0, "distance": 1e300}]}"#);
        assert!(e.starts_with("nodes[1].distance: 1e300 puts"), "{e}");
        assert_eq!(
            one(r#"{"type": "sphere", "radius": 1, "translate": [0, 0, 1e17]}"#),
            "nodes[0].translate[2]: 1e17 puts the scene 1e17 from the origin, over 1048576 times its size (2): the GPU's f32 arithmetic cannot resolve it there; move the scene near the origin"
        );
        let two_far = r#"{"isotrace_scene": 1, "root": 2, "nodes": [{"type": "sphere", "radius": 1, "translate": [3e6, 0, 0]}, {"type": "sphere", "radius": 1, "translate": [3e6, 0, 0]}, {"type": "union", "left": 0, "right": 1}]}"#;
        assert!(err(two_far).starts_with("nodes[0].translate[0]: 3000000 puts the scene 3000001 from the origin, over 1048576 times its size (2)"));
    }
}
