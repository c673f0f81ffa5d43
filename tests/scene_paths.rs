//! A scene's grid `file` stays inside the scene file's directory unless the
//! user passes `--allow-scene-paths` (every command that loads a scene
//! file), and the viewer's server reads no grid file a request names.
//! Exact messages and exit codes; the server's exact status and body.

mod cli_common;
mod view_common;
use cli_common::*;
use std::path::{Path, PathBuf};

const PEBBLE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/pebble.npy");

/// `d/outside.npy`, `d/sub/in.npy`, `d/sub/link.npy` (a symbolic link to
/// the outside one) and, in `d/sub`, one scene per way of naming a grid.
struct Layout {
    dir: PathBuf,
    sub: PathBuf,
}

impl Layout {
    fn new(name: &str) -> Layout {
        let dir = dir(name);
        let sub = dir.join("sub");
        std::fs::create_dir_all(sub.join("deeper")).unwrap();
        std::fs::copy(PEBBLE, dir.join("outside.npy")).unwrap();
        std::fs::copy(PEBBLE, sub.join("in.npy")).unwrap();
        std::fs::copy(PEBBLE, sub.join("other.npy")).unwrap();
        #[cfg(unix)]
        std::os::unix::fs::symlink(dir.join("outside.npy"), sub.join("link.npy")).unwrap();
        Layout { dir, sub }
    }

    /// A scene in `sub` whose one grid node names `file`.
    fn scene(&self, name: &str, file: &str) -> PathBuf {
        let p = self.sub.join(format!("{name}.scene.json"));
        std::fs::write(&p, scene_text(file)).unwrap();
        p
    }
}

fn scene_text(file: &str) -> String {
    format!(r#"{{"isotrace_scene": 1, "root": 0, "nodes": [{{"type": "grid", "file": "{file}", "spacing": 0.05, "origin": [-1.175, -1.175, -1.175]}}]}}"#)
}

fn outside_message(scene: &Path, shown: &str) -> String {
    format!(
        "error: {}: nodes[0].file: the grid file '{shown}' is outside the directory of the scene file; give --allow-scene-paths to read it (only for files you trust)\n",
        s(scene)
    )
}

#[test]
fn a_grid_outside_the_scene_directory_is_refused_unless_allowed() {
    let l = Layout::new("scene-paths");
    let outside = l.dir.join("outside.npy");
    let mut cases = vec![
        (l.scene("abs", s(&outside)), s(&outside).to_string()),
        (l.scene("up", "../outside.npy"), format!("{}/../outside.npy", s(&l.sub))),
        (l.scene("climb", "deeper/../../outside.npy"), format!("{}/deeper/../../outside.npy", s(&l.sub))),
    ];
    #[cfg(unix)]
    cases.push((l.scene("link", "link.npy"), format!("{}/link.npy", s(&l.sub))));
    let out = l.dir.join("o.png");
    for (scene, shown) in &cases {
        let refused = outside_message(scene, shown);
        assert_error(&isotrace(&["scene", "check", s(scene)]), &refused);
        assert_error(&isotrace(&["scene", "formula", s(scene)]), &refused);
        // Refused before any GPU work (exit 1, not the missing device's 2).
        assert_error(&isotrace_without_gpu(&["render", s(scene), "--size", "8", "-o", s(&out)]), &refused);
        assert_error(&isotrace_with_stdin(&["eval", s(scene), "--algebra", "scalar", "--cpu"], "0 0 0\n"), &refused);
        assert_error(&isotrace(&["view", s(scene), "--export", s(&l.dir.join("v.html"))]), &refused);
        // With the flag the grid is read.
        let o = isotrace(&["scene", "check", s(scene), "--allow-scene-paths"]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(String::from_utf8_lossy(&o.stdout).contains("primitives:    grid 1"), "{}", String::from_utf8_lossy(&o.stdout));
        let o = isotrace_with_stdin(&["eval", s(scene), "--algebra", "scalar", "--cpu", "--allow-scene-paths"], "0 0 0\n");
        assert!(o.status.success(), "{}", stderr(&o));
    }
    // Inside the directory, relative to the scene file: read without the flag.
    let o = isotrace(&["scene", "check", s(&l.scene("in", "in.npy"))]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (scene, _) = &cases[0];
    let o = isotrace(&["render", s(scene), "--size", "8", "-o", s(&out), "--allow-scene-paths"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.is_file());
}

/// One POST of JSON with the session token; the status and the body.
fn post(s: &view_common::Server, path: &str, body: &str) -> (u16, String) {
    let r = s.request("POST", path, body.as_bytes());
    (r.status, r.text())
}

#[test]
fn the_server_reads_no_grid_file_a_request_names() {
    let l = Layout::new("scene-paths-server");
    let scene = l.scene("in", "in.npy");
    let server = view_common::start(s(&scene));
    let edit = |file: &str, spacing: f64| {
        let mut v: serde_json::Value = serde_json::from_str(&scene_text(file)).unwrap();
        v["nodes"][0]["spacing"] = spacing.into();
        serde_json::json!({ "args": [s(&scene)], "scene": v }).to_string()
    };
    // The scene's own grid, placed anew from memory.
    let (status, body) = post(&server, "/api/scene", &edit("in.npy", 0.04));
    assert_eq!(status, 200, "{body}");
    assert!(body.contains("\"buffers\""), "{body}");
    // Any other file, existing or not, inside the directory or out: the
    // same refusal, so the answer tells nothing about the file system.
    let refused = r#"{"error":"the edited scene: nodes[0].file: not a grid file of the loaded scene; an edit may use only the grids its scene file names"}"#;
    let outside = l.dir.join("outside.npy");
    for file in ["other.npy", "nothere.npy", "../outside.npy", s(&outside), "/nonexistent/x.npy"] {
        let (status, body) = post(&server, "/api/scene", &edit(file, 0.05));
        assert_eq!((status, body.as_str()), (400, refused), "{file}");
    }
}
