//! `isotrace view` as a server: bad requests get a JSON error with a clear
//! message, and the server keeps answering (it never panics on input).

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};

struct Server {
    child: Child,
    addr: String,
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn start(input: &str) -> Server {
    let mut child = Command::new(env!("CARGO_BIN_EXE_isotrace"))
        .args(["view", input, "--port", "0"])
        .env("NODEVICE_SELECT", "1")
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("isotrace starts");
    let mut line = String::new();
    BufReader::new(child.stdout.take().expect("stdout")).read_line(&mut line).expect("a URL line");
    let addr = line.trim().trim_start_matches("isotrace view: http://").trim_end_matches('/').to_string();
    Server { child, addr }
}

/// One raw HTTP/1.1 request; the status and the body.
fn request(s: &Server, method: &str, path: &str, body: &[u8]) -> (u16, String) {
    let mut c = TcpStream::connect(&s.addr).expect("connects");
    let head = format!("{method} {path} HTTP/1.0\r\nHost: x\r\nConnection: close\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n", body.len());
    c.write_all(head.as_bytes()).unwrap();
    let _ = c.write_all(body);
    let mut out = Vec::new();
    let _ = c.read_to_end(&mut out);
    let text = String::from_utf8_lossy(&out).to_string();
    let status = text.split(' ').nth(1).and_then(|s| s.parse().ok()).unwrap_or(0);
    let body = text.split_once("\r\n\r\n").map(|(_, b)| b.to_string()).unwrap_or_default();
    (status, body)
}

fn error_of(body: &str) -> String {
    let v: serde_json::Value = serde_json::from_str(body).unwrap_or_else(|_| panic!("JSON: {body}"));
    v["error"].as_str().unwrap_or_else(|| panic!("an error: {body}")).to_string()
}

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
        let (got, text) = request(&s, method, path, body);
        assert_eq!(got, *status, "{method} {path} {}: {text}", String::from_utf8_lossy(body));
        let e = error_of(&text);
        assert!(e.contains(needle), "{method} {path}: '{e}' lacks '{needle}'");
    }
    // A formula over the front end's 64 KiB limit, and a body over 8 MiB.
    let long = format!(r#"{{"args": ["{}"]}}"#, "x+".repeat(40_000) + "x");
    let (got, text) = request(&s, "POST", "/api/program", long.as_bytes());
    assert_eq!(got, 400, "{text}");
    let (got, _) = request(&s, "POST", "/api/program", &vec![b' '; 9 << 20]);
    assert_eq!(got, 413);
    // Still serving, and the page's first state is a validated program.
    let (got, text) = request(&s, "GET", "/api/start", b"");
    assert_eq!(got, 200);
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["program"]["method"], "bisect");
    assert!(v["program"]["wgsl"].as_str().unwrap().contains("fn main"));
    assert!(v["present"].as_str().unwrap().contains("fn fs"));
    let (got, text) = request(&s, "GET", "/", b"");
    assert_eq!(got, 200);
    assert!(text.contains("/app.js"));
}

#[test]
fn the_page_renders_a_png_through_the_cli_path() {
    let s = start("@sphere");
    let (got, text) = request(&s, "POST", "/api/render", br#"{"args": ["@sphere", "--size", "32"], "format": "png"}"#);
    assert_eq!(got, 200, "{text}");
    assert!(text.as_bytes().starts_with(b"\x89PNG") || text.starts_with('\u{FFFD}'), "a PNG");
}

#[test]
fn a_bad_formula_on_the_command_line_is_the_cli_error() {
    let out = Command::new(env!("CARGO_BIN_EXE_isotrace")).args(["view", "x^2 + (", "--port", "0"]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("expected an expression"));
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
