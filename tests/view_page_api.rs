//! The viewer's JSON answers that the page follows: a scene edit carries
//! the framing and uniforms of the edited scene (as `render` of it), a
//! formula's parameters that nothing sets get a value and are named, and a
//! sphere traced program carries the CLI's Lipschitz warning as a template.

mod view_common;

use serde_json::{json, Value};

use std::process::Command;
use view_common::{start, Server};

/// One request with a JSON body and the session token; the status and the JSON answer.
fn call(s: &Server, method: &str, path: &str, body: &Value) -> (u16, Value) {
    let body = if body.is_null() { String::new() } else { body.to_string() };
    let r = s.request(method, path, body.as_bytes());
    let text = r.text();
    (r.status, serde_json::from_str(&text).unwrap_or_else(|_| panic!("JSON: {text}")))
}

fn post(s: &Server, route: &str, body: Value) -> Value {
    let (status, v) = call(s, "POST", &format!("/api/{route}"), &body);
    assert_eq!(status, 200, "{route}: {v}");
    v
}

#[test]
fn a_scene_edit_answers_the_framing_and_uniforms_of_the_edited_scene() {
    let file = "examples/procedural.scene.json";
    let s = start(file);
    let (status, first) = call(&s, "GET", "/api/start", &Value::Null);
    assert_eq!(status, 200);
    assert!(first["view"]["box"][1].as_f64().unwrap() < 2.72, "{}", first["view"]);
    // Node 0, a box of half width 1.7, grows to 2.72.
    let mut scene = first["scene"].clone();
    scene["nodes"][0]["half"][0] = json!(2.72);
    let args = json!([file, "--size", "128"]);
    let edit = post(&s, "scene", json!({ "args": args, "scene": scene }));
    let b = &edit["view"]["box"];
    assert!(b[0].as_f64().unwrap() < -2.72 && b[1].as_f64().unwrap() > 2.72, "the box holds the grown solid: {b}");
    // The same view and uniforms as a program of the edited scene: the
    // render command's planning of it.
    let program = post(&s, "program", json!({ "args": args, "scene": scene }));
    assert_eq!(edit["view"], program["view"]);
    assert_eq!(edit["options"], program["options"]);
    assert_eq!(edit["uniforms"], program["program"]["uniforms"]);
    // A box, camera and eps the request gives stay.
    let fixed = json!([file, "--size", "128", "--box=-2,2,-1.5,1.5,-1.5,1.5", "--eye=6,5,4", "--eps=0.002"]);
    let kept = post(&s, "scene", json!({ "args": fixed, "scene": scene }));
    assert_eq!(kept["view"]["box"], json!([-2.0, 2.0, -1.5, 1.5, -1.5, 1.5]));
    assert_eq!(kept["view"]["eye"], json!([6.0, 5.0, 4.0]));
    assert_eq!(kept["view"]["eps"], json!(0.002));
    // A twist's rate raises the scene's Lipschitz bound: the uniforms follow.
    scene["nodes"][3]["warp"]["rate"] = json!(4.8);
    let twisted = post(&s, "scene", json!({ "args": args, "scene": scene }));
    let program = post(&s, "program", json!({ "args": args, "scene": scene }));
    assert!(twisted["options"]["lipschitz"].as_f64().unwrap() > edit["options"]["lipschitz"].as_f64().unwrap() + 1.0, "{}", twisted["options"]);
    assert_eq!(twisted["uniforms"], program["program"]["uniforms"]);
}

#[test]
fn a_scene_is_bisected_when_the_page_asks() {
    let file = "examples/blobs.scene.json";
    let s = start(file);
    let v = post(&s, "program", json!({ "args": [file, "--size", "64", "--method", "bisect"] }));
    assert_eq!(v["program"]["method"], json!("bisect"), "{}", v["program"]["method"]);
    assert_eq!(v["options"]["algebra"], json!("ia"), "{}", v["options"]);
    assert!(v["program"]["wgsl"].as_str().unwrap().contains("fn surf_ia("), "the page's kernel has the scene's enclosures");
    // RAA is refused by name.
    let (status, e) = call(&s, "POST", "/api/program", &json!({ "args": [file, "--method", "bisect", "--algebra", "raa"] }));
    assert_eq!(status, 400, "{e}");
    assert!(e.to_string().contains("--algebra raa: a scene's nodes are enclosed in interval arithmetic, and formula leaves of degree 4 to 10 in RAA, node by node"), "{e}");
}

#[test]
fn parameters_that_nothing_sets_get_the_value_one_and_are_named() {
    let s = start("@sphere");
    let v = post(&s, "program", json!({ "args": ["x^2+y^2+z^2-r^2"] }));
    assert_eq!(v["params"], json!([{ "name": "r", "value": 1.0 }]));
    assert_eq!(v["new_params"], json!(["r"]));
    assert_eq!(v["args"], json!(["x^2+y^2+z^2-r^2", "--param", "r=1"]));
    // A value given is kept, and nothing is new.
    let v = post(&s, "program", json!({ "args": ["x^2+y^2+z^2-r^2", "--param", "r=0.5"] }));
    assert_eq!(v["params"], json!([{ "name": "r", "value": 0.5 }]));
    assert_eq!(v["new_params"], json!([]));
    // A header's values count as set.
    let s = start("tests/browser/torus-ia.iso");
    let v = post(&s, "program", json!({ "args": ["tests/browser/torus-ia.iso"] }));
    assert_eq!(v["params"], json!([{ "name": "R", "value": 1.0 }, { "name": "r", "value": 0.3499999940395355 }]));
    assert_eq!(v["new_params"], json!([]));
    // The command line's formula too: `view` has no --param.
    let s = start("x^2+y^2+z^2-r^2");
    let (status, v) = call(&s, "GET", "/api/start", &Value::Null);
    assert_eq!(status, 200, "{v}");
    assert_eq!(v["new_params"], json!(["r"]));
}

#[test]
fn a_sphere_traced_program_carries_the_cli_lipschitz_warning() {
    let formula = "x^2+y^2-z^2-0.1";
    let s = start(formula);
    let v = post(&s, "program", json!({ "args": [formula, "--method", "sphere"] }));
    assert_eq!(v["program"]["ray_stats"], json!(1));
    let template = v["warnings"]["lipschitz"].as_str().expect("a Lipschitz warning template").to_string();
    // The CLI's own warning for this formula is the template filled in.
    let dir = std::env::temp_dir().join(format!("isotrace-view-page-api-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_isotrace"))
        .args(["render", formula, "--method", "sphere", "--size", "64", "-o"])
        .arg(dir.join("hyperboloid.png"))
        .env("NODEVICE_SELECT", "1")
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    let line = stderr.lines().find(|l| l.contains("changed faster")).unwrap_or_else(|| panic!("a Lipschitz warning: {stderr}"));
    let after = |key: &str| line.split(key).nth(1).and_then(|t| t.split(' ').next()).unwrap().to_string();
    let filled = template.replace("{violations}", &after("on ")).replace("{lipschitz}", "1").replace("{seen}", &after("up to "));
    assert_eq!(filled, line);
    // Bisection has no such warning, and no per-ray statistics.
    let v = post(&s, "program", json!({ "args": [formula] }));
    assert_eq!(v["warnings"], json!({}));
    assert_eq!(v["program"]["ray_stats"], Value::Null);
}
