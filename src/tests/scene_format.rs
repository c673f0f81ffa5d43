//! The `.scene.json` format: exact error messages with JSON paths, round
//! trips, the read limit; and the generated scenes' primitive counts.

use crate::scene::format::{self, FormatError, MAX_SCENE_BYTES};
use crate::scene::generate::{generate, Blending, Kind, MAX_LEVEL};
use crate::scene::linear::Linear;

fn err(json: &str) -> String {
    format::parse(json).unwrap_err().to_string()
}

/// A file with `nodes` (JSON text of the list's items) and `root`.
fn file(nodes: &str, root: usize) -> String {
    format!("{{\"isotrace_scene\": 1, \"root\": {root}, \"nodes\": [{nodes}]}}")
}

const S: &str = "{\"type\": \"sphere\", \"radius\": 1}";

#[test]
fn parameter_errors_name_the_field() {
    let cases: &[(&str, &str)] = &[
        ("{\"type\": \"sphere\", \"radius\": 0}", "nodes[0].radius: must be > 0"),
        ("{\"type\": \"sphere\"}", "nodes[0].radius: missing"),
        ("{\"type\": \"sphere\", \"radius\": \"big\"}", "nodes[0].radius: expected a number, found \"big\""),
        ("{\"type\": \"sphere\", \"radiu\": 1}", "nodes[0].radiu: unknown field for a sphere; expected radius, translate, rotate, scale or warp"),
        ("{\"type\": \"sphre\", \"radius\": 1}", "nodes[0].type: unknown type 'sphre'; did you mean 'sphere'?"),
        ("{\"type\": \"blob\"}", "nodes[0].type: unknown type 'blob'; did you mean 'box'?"),
        ("{\"radius\": 1}", "nodes[0].type: missing"),
        ("3", "nodes[0]: expected an object, found 3"),
        ("{\"type\": \"box\", \"half\": [1, 2]}", "nodes[0].half: expected 3 numbers, found 2"),
        ("{\"type\": \"box\", \"half\": [1, -2, 3]}", "nodes[0].half[1]: must be > 0"),
        ("{\"type\": \"box\", \"half\": [1, null, 3]}", "nodes[0].half[1]: expected a number, found null"),
        ("{\"type\": \"box\", \"half\": 1}", "nodes[0].half: expected 3 numbers, found 1"),
        ("{\"type\": \"round_box\", \"half\": [1, 0.5, 2], \"radius\": 0.75}", "nodes[0].radius: must be >= 0 and <= the smallest half extent (0.5)"),
        ("{\"type\": \"plane\", \"normal\": [0, 0, 0], \"offset\": 1}", "nodes[0].normal: must not be zero"),
        ("{\"type\": \"torus\", \"major\": 1, \"minor\": 0}", "nodes[0].minor: must be > 0"),
        ("{\"type\": \"sphere\", \"radius\": 1, \"scale\": -2}", "nodes[0].scale: must be > 0"),
        ("{\"type\": \"sphere\", \"radius\": 1, \"rotate\": [0, 0, 0, 1]}", "nodes[0].rotate: the rotation axis must not be zero"),
        ("{\"type\": \"sphere\", \"radius\": 1, \"rotate\": [0, 0, 1]}", "nodes[0].rotate: expected 4 numbers, found 3"),
        ("{\"type\": \"sphere\", \"radius\": 1e999}", "nodes[0]: number out of range at line 1 column 77"),
    ];
    for (node, message) in cases {
        assert_eq!(err(&file(node, 0)), *message, "{node}");
    }
}

#[test]
fn operator_and_structure_errors_name_the_node() {
    let op = |t: &str, rest: &str| format!("{S}, {S}, {{\"type\": \"{t}\", \"left\": 0, \"right\": 1{rest}}}");
    let cases: Vec<(String, usize, &str)> = vec![
        (op("smooth_union", ", \"beta\": 0.3, \"r_o\": 0.3"), 2, "nodes[2].r_o: must be >= 7/6 of beta (0.35): below it the compact blend is discontinuous"),
        (op("smooth_union", ", \"beta\": -1"), 2, "nodes[2].beta: must be > 0"),
        (op("smooth_union", ""), 2, "nodes[2].beta: missing"),
        (op("union", ", \"beta\": 0.3"), 2, "nodes[2].beta: unknown field for a union; expected left or right"),
        (format!("{S}, {S}, {{\"type\": \"union\", \"left\": 0}}"), 2, "nodes[2].right: missing"),
        (format!("{S}, {S}, {{\"type\": \"union\", \"left\": -1, \"right\": 1}}"), 2, "nodes[2].left: expected a node index (a whole number >= 0), found -1"),
        (format!("{S}, {S}, {{\"type\": \"union\", \"left\": 0, \"right\": 7}}"), 2, "nodes[2].right: refers to nodes[7], but the scene has 3 nodes"),
        (format!("{S}, {S}, {{\"type\": \"union\", \"left\": 0, \"right\": 1}}"), 5, "root: refers to nodes[5], but the scene has 3 nodes"),
        (format!("{S}, {S}, {{\"type\": \"union\", \"left\": 0, \"right\": 1}}, {S}"), 2, "nodes[3]: is not reachable from the root, nodes[2]"),
        (
            format!("{S}, {S}, {{\"type\": \"union\", \"left\": 0, \"right\": 1}}, {{\"type\": \"union\", \"left\": 4, \"right\": 5}}, {{\"type\": \"union\", \"left\": 3, \"right\": 6}}, {S}, {S}"),
            2,
            "nodes[3]: is on a cycle (it is its own descendant)",
        ),
        (format!("{S}, {{\"type\": \"union\", \"left\": 0, \"right\": 0}}"), 1, "nodes[1].right: nodes[0] is already the left operand"),
        (format!("{S}, {S}, {{\"type\": \"union\", \"left\": 0, \"right\": 1}}, {{\"type\": \"difference\", \"left\": 0, \"right\": 2}}"), 3, "nodes[3].left: nodes[0] is already an operand of nodes[2] (a node has one parent)"),
    ];
    for (nodes, root, message) in &cases {
        assert_eq!(err(&file(nodes, *root)), *message, "{nodes}");
    }
}

#[test]
fn file_level_errors() {
    assert_eq!(err("{\"isotrace_scene\": 2, \"root\": 0, \"nodes\": []}"), "isotrace_scene: version 2 is not supported (this isotrace reads version 1)");
    assert_eq!(err("{\"isotrace_scene\": \"1\", \"root\": 0, \"nodes\": []}"), "isotrace_scene: expected the format version 1, found \"1\"");
    assert_eq!(err(&format!("{{\"root\": 0, \"nodes\": [{S}]}}")), "isotrace_scene: missing: a scene file starts with \"isotrace_scene\": 1");
    assert_eq!(err(&format!("{{\"isotrace_scene\": 1, \"nodes\": [{S}]}}")), "root: missing: a scene file names its root node");
    assert_eq!(err("{\"isotrace_scene\": 1, \"root\": 0}"), "nodes: missing: a scene file lists its nodes");
    assert_eq!(err("{\"isotrace_scene\": 1, \"root\": 0, \"nodes\": []}"), "nodes: a scene needs at least one node");
    assert_eq!(err(&format!("{{\"isotrace_scene\": 1, \"root\": 0, \"root\": 0, \"nodes\": [{S}]}}")), "root: given twice");
    assert_eq!(err(&format!("{{\"isotrace_scene\": 1, \"root\": 0, \"nodes\": [{S}], \"camera\": 1}}")), "camera: unknown field; a scene file has isotrace_scene, nodes and root");
    assert_eq!(err("[1, 2]"), "invalid type: sequence, expected a scene object {\"isotrace_scene\": 1, \"nodes\": [...], \"root\": N} at line 1 column 1");
    assert_eq!(err(&format!("{{\"isotrace_scene\": 1, \"root\": 0, \"nodes\": [{S}")), "EOF while parsing a list at line 1 column 74");
    assert_eq!(err(&format!("{} x", file(S, 0))), "trailing characters at line 1 column 78");
}

#[test]
fn reads_are_bounded() {
    // One byte over the limit (a sparse file: nothing is written).
    let big = std::env::temp_dir().join(format!("isotrace-scene-format-{}-big.scene.json", std::process::id()));
    std::fs::File::create(&big).unwrap().set_len(MAX_SCENE_BYTES + 1).unwrap();
    let e = format::load(&big).unwrap_err();
    let _ = std::fs::remove_file(&big);
    assert!(matches!(e, FormatError::Read(crate::bounded::ReadError::TooLarge { limit: MAX_SCENE_BYTES })), "{e}");
    assert_eq!(e.to_string(), "larger than the limit of 67108864 bytes (64 MiB)");
    // An endless device is not opened at all.
    let e = format::load(std::path::Path::new("/dev/zero")).unwrap_err();
    assert_eq!(e.to_string(), "not a regular file (a character device)");
}

#[test]
fn examples_load_and_round_trip() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.to_string_lossy().ends_with(".scene.json") {
            let scene = format::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            // Grid files are relative to the scene's directory.
            assert_eq!(format::parse_in(&format::to_json(&scene), &dir).unwrap(), scene);
            Linear::new(&scene).unwrap();
            n += 1;
        }
    }
    assert!(n >= 3, "{n} example scenes");
}

/// The paper's counts: Fig. 16 10 … 111110, Fig. 18 boxes 16 … 4096 and
/// sphere pairs 24 … 6144; every level linearises with a small stack.
#[test]
fn generated_scenes_have_the_papers_counts() {
    let expect = [(Kind::Aggregate, [10, 110, 1110, 11110, 111110]), (Kind::Boxes, [16, 64, 256, 1024, 4096]), (Kind::SpherePairs, [24, 96, 384, 1536, 6144])];
    for (kind, counts) in expect {
        for level in 0..=MAX_LEVEL {
            let blending = [Blending::Sharp, Blending::SmoothInside, Blending::Smooth][level as usize % 3];
            let scene = generate(kind, level, blending, 1).unwrap();
            assert_eq!(scene.primitive_count(), counts[level as usize], "{kind:?} level {level}");
            assert_eq!(scene.len(), 2 * counts[level as usize] - 1);
            let lin = Linear::new(&scene).unwrap();
            assert!(lin.stack_depth <= 2 + level + 2, "{kind:?} {level}: stack {}", lin.stack_depth);
            assert!(lin.bounds.is_bounded() && !lin.bounds.is_empty());
        }
    }
    // The largest fits the read limit.
    let big = format::to_json(&generate(Kind::Aggregate, MAX_LEVEL, Blending::Smooth, 1).unwrap());
    assert!((big.len() as u64) < MAX_SCENE_BYTES, "{} bytes", big.len());
    assert!(generate(Kind::Boxes, MAX_LEVEL + 1, Blending::Sharp, 1).is_err());
}

/// Every non-sphere primitive of a generated scene is rotated; the smooth
/// variants use compact unions with r_o = 2β.
#[test]
fn generated_scenes_rotate_and_blend_as_described() {
    use crate::scene::{Node, Shape};
    for kind in [Kind::Aggregate, Kind::Boxes, Kind::SpherePairs] {
        let scene = generate(kind, 1, Blending::Smooth, 2).unwrap();
        let mut smooth = 0;
        for n in scene.nodes() {
            match n {
                Node::Primitive(p) => assert_eq!(p.transform.rotate.is_some(), !matches!(p.shape, Shape::Sphere { .. })),
                Node::Operator { op, .. } => {
                    if let Some(b) = op.blend {
                        assert_eq!(b.range, 2.0 * b.beta);
                        smooth += 1;
                    }
                }
                Node::Unary { .. } => panic!("generated scenes have no unary nodes"),
            }
        }
        assert!(smooth > 0);
        let sharp = generate(kind, 1, Blending::Sharp, 2).unwrap();
        assert!(sharp.nodes().iter().all(|n| !matches!(n, Node::Operator { op, .. } if op.blend.is_some())));
    }
}
