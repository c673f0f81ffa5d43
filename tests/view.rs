//! `isotrace view` as a server: bad requests get a JSON error with a clear
//! message, and the server keeps answering (it never panics on input).

mod view_common;

use std::process::Command;
use view_common::start;

#[test]
fn bad_requests_are_json_errors_and_the_server_goes_on() {
    let s = start("@sphere");
    let cases: &[(&str, &str, &[u8], u16, &str)] = &[
        ("GET", "/etc/passwd", b"", 404, "no such page"),
        ("GET", "/../Cargo.toml", b"", 404, "no such page"),
        ("POST", "/api/program", b"{not json", 400, "not JSON"),
        ("POST", "/api/program", b"{}", 400, "\"args\""),
        ("POST", "/api/program", br#"{"args": []}"#, 400, "empty"),
        ("POST", "/api/program", br#"{"args": [1, 2]}"#, 400, "strings"),
        ("POST", "/api/program", br#"{"args": ["examples/torus.iso"]}"#, 400, "only the file named on its command line"),
        ("POST", "/api/program", br#"{"args": ["x", "--inline", "a.wgsl"]}"#, 400, "--inline is not available"),
        ("POST", "/api/program", br#"{"args": ["x", "-o", "/tmp/x.png"]}"#, 400, "-o is not available"),
        ("POST", "/api/program", br#"{"args": ["x", "--env", "/etc/passwd"]}"#, 400, "--env is not available"),
        ("POST", "/api/program", br#"{"args": ["x", "--scene-walk", "tile"]}"#, 400, "--scene-walk is not available"),
        ("POST", "/api/program", br#"{"args": ["x", "--size", "0"]}"#, 400, "invalid --size"),
        ("POST", "/api/program", br#"{"args": ["x^2 + ("]}"#, 400, "expected an expression"),
        ("POST", "/api/render", br#"{"args": ["@sphere"], "format": "gif"}"#, 400, "unknown format"),
        ("POST", "/api/scene", br#"{"args": ["@sphere"]}"#, 400, "not of a scene"),
        ("GET", "/api/program", b"", 405, "wrong method"),
    ];
    for (method, path, body, status, needle) in cases {
        let r = s.request(method, path, body);
        assert_eq!(r.status, *status, "{method} {path} {}: {}", String::from_utf8_lossy(body), r.text());
        let e = r.error();
        assert!(e.contains(needle), "{method} {path}: '{e}' lacks '{needle}'");
    }
    // A formula over the front end's 64 KiB limit, and a body over 8 MiB.
    let long = format!(r#"{{"args": ["{}"]}}"#, "x+".repeat(40_000) + "x");
    let r = s.request("POST", "/api/program", long.as_bytes());
    assert_eq!(r.status, 400, "{}", r.text());
    let r = s.request("POST", "/api/program", &vec![b' '; 9 << 20]);
    assert_eq!((r.status, r.error().as_str()), (413, "the request body is over the limit of 8 MiB"));
    // Still serving, and the page's first state is a validated program.
    let r = s.request("GET", "/api/start", b"");
    assert_eq!(r.status, 200);
    let v: serde_json::Value = serde_json::from_slice(&r.body).unwrap();
    assert_eq!(v["program"]["method"], "bisect");
    assert!(v["program"]["wgsl"].as_str().unwrap().contains("fn main"));
    assert!(v["present"].as_str().unwrap().contains("fn fs"));
    let r = s.request("GET", "/", b"");
    assert_eq!(r.status, 200);
    assert!(r.text().contains("/app.js"));
}

#[test]
fn the_page_renders_a_png_through_the_cli_path() {
    let s = start("@sphere");
    let r = s.request("POST", "/api/render", br#"{"args": ["@sphere", "--size", "32"], "format": "png"}"#);
    assert_eq!(r.status, 200, "{}", r.text());
    assert!(r.body.starts_with(b"\x89PNG\r\n\x1a\n"), "a PNG");
    assert_eq!(r.header("content-disposition").as_deref(), Some("attachment; filename=\"isotrace-view.png\""));
}

#[test]
fn a_bad_formula_on_the_command_line_is_the_cli_error() {
    let out = Command::new(env!("CARGO_BIN_EXE_isotrace")).args(["view", "x^2 + (", "--port", "0"]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("expected an expression"));
}

#[test]
fn a_missing_scene_on_the_command_line_is_named() {
    let out = Command::new(env!("CARGO_BIN_EXE_isotrace")).args(["view", "nothere.scene.json", "--port", "0"]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(String::from_utf8_lossy(&out.stderr), "error: cannot read scene file 'nothere.scene.json': No such file or directory (os error 2)\n");
}

#[test]
fn export_writes_a_self_contained_page() {
    let dir = std::env::temp_dir().join(format!("isotrace-view-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let page = dir.join("sphere.html");
    let out = Command::new(env!("CARGO_BIN_EXE_isotrace")).args(["view", "@sphere", "--export"]).arg(&page).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let html = std::fs::read_to_string(&page).unwrap();
    for needle in ["id=\"isotrace-start\"", "id=\"isotrace-lil-gui\"", "\"server\":false", "Controller", "createComputePipelineAsync"] {
        assert!(html.contains(needle), "{needle}");
    }
    assert!(!html.contains("src=\"/app.js\""), "no server asset referenced");
    let _ = std::fs::remove_dir_all(&dir);
}
