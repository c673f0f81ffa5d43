//! Every operator style of the table (`crate::sdf::operator::STYLES`) end
//! to end, from its descriptor alone: for each of its operations the
//! formula form's IR agrees with the style's f64 reference at random
//! points, the formula lowers to the scene node the style is kept as, whose
//! f64 value and device value (the scene interpreter) agree with that
//! style's reference; a style with nodes of its own reads and writes its
//! scene file node, prints as its own formula form, has its type codes, and
//! refuses a bad parameter naming its field. A new style is checked here
//! without a line of its own.

use crate::reference::eval_scalar;
use crate::scene::generate::Rng;
use crate::scene::linear::{Linear, NODE_TYPE_MASK, NODE_TYPE_SHIFT};
use crate::scene::operator::Typed;
use crate::scene::{format, Node, Operator};
use crate::sdf::operator::{OperatorStyle, KINDS, STYLES};
use crate::sdf::primitive::Params;

/// The operands: a sphere and a box that overlaps it, so every operation
/// blends somewhere in the sampled cube.
const LEFT: &str = "sphere(0.8)";
const RIGHT: &str = "translate(0.7, 0.1, 0, box(0.5, 0.6, 0.4))";

/// Parameters every style accepts: the leading ones a formula must give.
fn given(style: &OperatorStyle) -> Vec<f64> {
    style.params.iter().filter(|f| f.default.is_none()).map(|_| 0.25).collect()
}

fn formula(src: &str) -> crate::Formula {
    crate::Formula::compile("<test>", src).unwrap_or_else(|e| panic!("{src}: {e}"))
}

fn at(f: &crate::Formula, p: [f64; 3]) -> f64 {
    eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[])
}

/// `name(LEFT, RIGHT, v…)`.
fn call(name: &str, v: &[f64]) -> String {
    let args: String = v.iter().map(|x| format!(", {x}")).collect();
    format!("{name}({LEFT}, {RIGHT}{args})")
}

#[test]
fn each_styles_form_and_scene_agree_with_its_f64_reference() {
    let mut rng = Rng::new(11);
    let (left, right) = (formula(LEFT), formula(RIGHT));
    for style in STYLES {
        let v = style.with_defaults(&given(style));
        let (kept, kv) = style.in_scene(&v);
        for (k, info) in style.forms.iter().enumerate() {
            let kind = KINDS[k];
            let f = formula(&call(info.name, &given(style)));
            let scene = crate::scene::from_formula(&f, &[]).unwrap_or_else(|e| panic!("{}: {e}", info.name));
            let root = &scene.nodes()[scene.root()];
            assert!(matches!(root, Node::Operator { op, .. } if matches!(op.typed(), Typed::Style(s, w) if s == kept && w == kv) && op.kind == kind), "{}: {root:?}", info.name);
            for _ in 0..300 {
                let p = [0, 1, 2].map(|_| rng.range(-1.5, 1.5));
                let (a, b) = (at(&left, p), at(&right, p));
                let want = (style.apply)(kind, a, b, &v);
                let got = at(&f, p);
                assert!((got - want).abs() <= 1e-9 * want.abs().max(1.0), "{} at {p:?}: formula {got}, reference {want}", info.name);
                let kept_value = (kept.apply)(kind, a, b, &kv);
                let s = scene.eval(p);
                assert!((s - kept_value).abs() <= 1e-12 * s.abs().max(1.0), "{} at {p:?}: scene {s}, reference {kept_value}", info.name);
            }
        }
    }
}

#[test]
fn each_styles_scene_interpreter_agrees_with_its_f64_reference() {
    let own = crate::gpu::Gpu::new().unwrap();
    let mut rng = Rng::new(12);
    for style in STYLES {
        for info in &style.forms {
            let f = formula(&call(info.name, &given(style)));
            let scene = crate::scene::from_formula(&f, &[]).unwrap();
            let lin = Linear::new(&scene).unwrap();
            let points: Vec<[f32; 3]> = (0..2000).map(|_| [0, 1, 2].map(|_| rng.range(-1.5, 1.5) as f32)).collect();
            let got = crate::gpu::eval::eval_points_scene(&own, &lin.field_data(), &points).unwrap();
            let worst = points.iter().zip(&got).map(|(p, g)| (*g as f64 - scene.eval(p.map(f64::from))).abs()).fold(0.0, f64::max);
            // f32 parameters and arithmetic on fields of size about 1.
            assert!(worst < 2e-4, "{}: worst difference {worst}", info.name);
        }
    }
}

#[test]
fn each_style_with_nodes_reads_writes_prints_and_codes_as_its_descriptor() {
    let shader = crate::field::scene::scene_eval_shader(u32::MAX >> 1);
    for style in STYLES {
        let (Some(names), Some(first)) = (style.scene_names(), style.first_code()) else { continue };
        let v = style.with_defaults(&given(style));
        for (k, name) in names.iter().enumerate() {
            let kind = KINDS[k];
            let op = Operator::styled(kind, style, &v);
            assert_eq!((op.name(), Operator::style_named(name)), (*name, Some((style, kind))));
            let f = formula(&call(style.forms[k].name, &v));
            let scene = crate::scene::from_formula(&f, &[]).unwrap();
            let json = format::to_json(&scene);
            assert!(json.contains(&format!("\"type\": \"{name}\"")), "{json}");
            assert_eq!(format::parse(&json).unwrap().nodes(), scene.nodes(), "{name}");
            let text = scene.to_formula().unwrap();
            assert!(text.contains(&format!("{}(", style.forms[k].name)), "{text}");
            assert_eq!(format::to_json(&crate::scene::from_formula(&formula(&text), &[]).unwrap()), json, "{name}");
            let lin = Linear::new(&scene).unwrap();
            let data = lin.field_data();
            let root = data.nodes[lin.root() as usize];
            assert_eq!((root[0] >> NODE_TYPE_SHIFT) & NODE_TYPE_MASK, first + k as u32, "{name}");
            let [beta, range] = style.row(&v);
            assert_eq!(data.params[root[1] as usize], [beta as f32, range as f32, 0.0, 0.0], "{name}");
            assert!(shader.contains(&format!("const NODE_{}: u32 = {}u;", name.to_uppercase(), first + k as u32)), "{name}");
        }
    }
}

#[test]
fn a_bad_parameter_is_refused_naming_its_field() {
    for style in STYLES {
        let Some(names) = style.scene_names() else { continue };
        let v = style.with_defaults(&given(style));
        for (k, field) in style.params.iter().enumerate() {
            for bad in [f64::NAN, -1.0] {
                let mut w = v.to_vec();
                w[k] = bad;
                let op = Operator::styled(KINDS[0], style, &Params::new(&w));
                let err = op.check().unwrap_err();
                assert_eq!(err.0, field.name, "{style:?} {bad}: {err:?}");
                if !bad.is_finite() {
                    continue;
                }
                let fields: String = style.params.iter().zip(&w).map(|(f, x)| format!(", \"{}\": {x}", f.name)).collect();
                let json = format!(r#"{{"isotrace_scene": 1, "root": 2, "nodes": [{{"type": "sphere", "radius": 1}}, {{"type": "sphere", "radius": 1}}, {{"type": "{}", "left": 0, "right": 1{fields}}}]}}"#, names[0]);
                let err = format::parse(&json).unwrap_err().to_string();
                assert!(err.starts_with(&format!("nodes[2].{}: ", field.name)), "{style:?}: {err}");
            }
        }
    }
}
