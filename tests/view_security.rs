//! The `isotrace view` server's boundaries, over real HTTP against a real
//! server process: what a request may name (the allow-list, the input),
//! who may call (Host, Origin, JSON content type, the session token), the
//! wire limits (head size, header count, request line), concurrency
//! (the page served during a render, stalled clients, the connection
//! bound) and how messages quote user text.

mod view_common;

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use view_common::{read_response, start, Server};

/// The status and error message of `POST /api/program` with `args`.
fn refused(s: &Server, args: &[&str]) -> (u16, String) {
    let r = s.program(args);
    (r.status, r.error())
}

fn bad(message: &str) -> (u16, String) {
    (400, message.to_string())
}

#[test]
fn every_argument_passes_the_allow_list_and_the_input_is_the_command_lines() {
    let s = start("@sphere");
    let env = bad("--env is not available in the viewer");
    // The first argument too; a file that exists and one that does not get
    // the same answer (neither is opened).
    assert_eq!(refused(&s, &["--env=/etc/passwd", "x^2+y^2+z^2-1"]), env);
    assert_eq!(refused(&s, &["--env=/no/such/image.png", "x^2+y^2+z^2-1"]), env);
    assert_eq!(refused(&s, &["x^2+y^2+z^2-1", "--env=/etc/passwd"]), env);
    assert_eq!(refused(&s, &["--size=16", "x"]), bad("the first argument is the input ('@sphere' or an edited formula), not the flag --size"));
    assert_eq!(refused(&s, &["x", "-f", "/etc/passwd"]), bad("-f is not available in the viewer"));
    for file in ["examples/torus.iso", "/etc/passwd.scene.json", "-"] {
        let message = format!("the viewer reads only the file named on its command line ('@sphere'), not '{file}'");
        assert_eq!(refused(&s, &[file]), bad(&message));
    }
    assert_eq!(
        refused(&s, &["x", "--field", "tape"]),
        bad("--field is not available in the viewer: the page runs the formula's generated kernel (`isotrace render --field …` renders with another field source)")
    );
    let long = "9".repeat(5000);
    assert_eq!(refused(&s, &["x", "--size", &long]), bad("argument 3 is 5000 bytes long: a flag or its value takes at most 4096"));
    let many = vec!["--shadows"; 300];
    assert_eq!(refused(&s, &many), bad("\"args\" has 300 arguments: the viewer takes at most 200"));
    // An edited formula, even one that starts with a minus sign, is the input.
    let r = s.program(&["-x^2-y^2-z^2+1", "--size", "16"]);
    assert_eq!(r.status, 200, "{}", r.text());
    let v: serde_json::Value = serde_json::from_slice(&r.body).unwrap();
    assert_eq!(v["formula"], "-x^2-y^2-z^2+1");

    // A scene view takes no other input.
    let scene = start("examples/blobs.scene.json");
    assert_eq!(
        refused(&scene, &["x^2+y^2+z^2-1"]),
        bad("this view is of the scene 'examples/blobs.scene.json': the first argument is that file, not 'x^2+y^2+z^2-1'")
    );
    assert_eq!(scene.program(&["examples/blobs.scene.json", "--size", "16"]).status, 200);
}

#[test]
fn host_origin_content_type_and_token_guard_the_server() {
    let s = start("@sphere");
    let line = s.line.trim();
    assert!(line.starts_with(&format!("isotrace view: http://127.0.0.1:{}/?token=", s.port)), "{line}");
    assert!(s.token.len() == 64 && s.token.bytes().all(|b| b.is_ascii_hexdigit()), "{line}");
    let port = s.port;
    let wrong_host = |host: &str| {
        let r = s.request_without("Host", &[format!("Host: {host}")], "GET", "/api/start", b"");
        let expected = format!("the request is addressed to '{host}', not to this server: open the URL isotrace view printed (http://127.0.0.1:{port}/?token=…)");
        assert_eq!((r.status, r.error()), (403, expected), "Host: {host}");
    };
    wrong_host(&format!("attacker.example:{port}"));
    wrong_host("attacker.example");
    wrong_host(&format!("127.0.0.1:{}", port.wrapping_add(1)));
    for host in [format!("localhost:{port}"), format!("[::1]:{port}"), format!("LOCALHOST:{port}")] {
        assert_eq!(s.request_without("Host", &[format!("Host: {host}")], "GET", "/api/start", b"").status, 200, "Host: {host}");
    }
    let r = s.request_without("Host", &[], "GET", "/", b"");
    assert_eq!((r.status, r.error()), (400, "the request has no Host header".into()));

    for origin in ["http://attacker.example", "null", &format!("https://127.0.0.1:{port}")] {
        let r = s.request_with(&[format!("Origin: {origin}")], "GET", "/api/start", b"");
        let expected = format!("the request comes from another site's page (Origin: {origin}): isotrace view answers only its own page");
        assert_eq!((r.status, r.error()), (403, expected));
    }
    assert_eq!(s.request_with(&[format!("Origin: http://127.0.0.1:{port}")], "GET", "/api/start", b"").status, 200);
    let r = s.request_with(&["Sec-Fetch-Site: cross-site".into()], "POST", "/api/program", br#"{"args": ["x"]}"#);
    let expected = "the request comes from another site's page (Sec-Fetch-Site: cross-site): isotrace view answers only its own page";
    assert_eq!((r.status, r.error().as_str()), (403, expected));
    // The page itself is public: a link from elsewhere opens it.
    assert_eq!(s.request_with(&["Sec-Fetch-Site: cross-site".into()], "GET", "/", b"").status, 200);

    // A cross-site form or `fetch` without a preflight sends text/plain.
    let r = s.request_without("Content-Type", &["Content-Type: text/plain".into()], "POST", "/api/render", br#"{"args": ["@sphere"]}"#);
    assert_eq!((r.status, r.error().as_str()), (415, "the API takes a JSON body with Content-Type: application/json, not 'text/plain'"));
    let r = s.request_without("Content-Type", &[], "POST", "/api/program", br#"{"args": ["x"]}"#);
    assert_eq!((r.status, r.error().as_str()), (415, "the API takes a JSON body with Content-Type: application/json, not ''"));
    let r = s.request_without("Content-Type", &["Content-Type: application/json; charset=utf-8".into()], "POST", "/api/program", br#"{"args": ["x"]}"#);
    assert_eq!(r.status, 200, "{}", r.text());

    // The token: none, a wrong one, in the cookie or the header.
    let no_token = (403, "this request has no valid session token: open the URL isotrace view printed (it ends in ?token=…)".to_string());
    let wrong = "0".repeat(64);
    let cookie = |t: &str| format!("Cookie: other=1; isotrace_view_{port}={t}");
    for extra in [vec![], vec![format!("Authorization: token {wrong}")], vec![cookie(&wrong)], vec![format!("Cookie: isotrace_view_1={}", s.token)]] {
        let r = s.request_without("Authorization", &extra, "GET", "/api/start", b"");
        assert_eq!((r.status, r.error()), no_token, "{extra:?}");
    }
    assert_eq!(s.request_without("Authorization", &[cookie(&s.token)], "GET", "/api/start", b"").status, 200);
    assert_eq!(s.request("GET", "/api/start", b"").status, 200);

    // The printed URL sets the cookie; a wrong token in a URL is refused.
    let host = format!("Host: {}", s.addr);
    let r = s.send("GET", &format!("/?token={}&size=128", s.token), &[host.clone()], b"");
    assert_eq!(r.status, 200);
    assert_eq!(r.header("set-cookie"), Some(format!("isotrace_view_{port}={}; Path=/; HttpOnly; SameSite=Strict", s.token)));
    let r = s.send("GET", &format!("/?token={wrong}"), &[host.clone()], b"");
    assert_eq!((r.status, r.error().as_str()), (403, "the token in this URL is not this server's: open the URL isotrace view printed"));
    let r = s.send("GET", "/", &[host], b"");
    assert_eq!((r.status, r.header("set-cookie")), (200, None));
}

#[cfg(target_os = "linux")]
fn peak_rss_kib(s: &Server) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{}/status", s.pid())).unwrap();
    status.lines().find_map(|l| l.strip_prefix("VmHWM:")).and_then(|v| v.trim().trim_end_matches(" kB").parse().ok()).expect("VmHWM")
}

#[test]
fn oversized_request_heads_are_refused_within_their_limits() {
    let s = start("@sphere");
    let host = format!("Host: {}", s.addr);
    #[cfg(target_os = "linux")]
    let peak = peak_rss_kib(&s);
    // One 12 MiB header field: answered after the first 32 KiB.
    let r = s.send("GET", "/", &[host.clone(), format!("X-Big: {}", "a".repeat(12 << 20))], b"");
    assert_eq!((r.status, r.error().as_str()), (431, "the request head is over the limit of 32 KiB"));
    #[cfg(target_os = "linux")]
    {
        let grown = peak_rss_kib(&s).saturating_sub(peak);
        assert!(grown < 4 << 10, "the server's peak memory grew by {grown} KiB");
    }
    let many: Vec<String> = std::iter::once(host.clone()).chain((0..150).map(|i| format!("X-{i}: 1"))).collect();
    let r = s.send("GET", "/", &many, b"");
    assert_eq!((r.status, r.error().as_str()), (431, "the request has over 100 header fields"));
    let r = s.send("GET", &format!("/{}", "a".repeat(20_000)), &[host.clone()], b"");
    assert_eq!((r.status, r.error().as_str()), (414, "the request line is over the limit of 8 KiB"));
    let r = s.raw(b"GET / HTTP/1.1\r\nHost: x\r\nBad Header\r\n\r\n");
    assert_eq!((r.status, r.error().as_str()), (400, "malformed request head: invalid header name"));
    let r = s.request("POST", "/api/program", br#"{"args": ["x"]}"#.as_slice());
    assert_eq!(r.status, 200, "still serving: {}", r.text());
    // A body announced over the limit is refused before it is read.
    let mut c = s.connect();
    let head = format!("POST /api/program HTTP/1.1\r\n{host}\r\nAuthorization: token {}\r\nContent-Type: application/json\r\nContent-Length: 999999999999\r\n\r\n", s.token);
    c.write_all(head.as_bytes()).unwrap();
    let r = read_response(c);
    assert_eq!((r.status, r.error().as_str()), (413, "the request body is over the limit of 8 MiB"));
}

/// A sum of many trigonometric terms: a few seconds to render on the CPU
/// device at the size used below.
fn slow_formula() -> String {
    let terms: Vec<String> = (0..150).map(|i| format!("0.01*sin({}*x+{}*y)*cos({}*z)", i % 7 + 1, i % 5 + 1, i % 3 + 1)).collect();
    format!("{} + x^2+y^2+z^2-1", terms.join(" + "))
}

#[test]
fn the_page_is_served_while_a_render_runs() {
    let s = Arc::new(start("@sphere"));
    let done = Arc::new(AtomicBool::new(false));
    let render = {
        let (s, done) = (s.clone(), done.clone());
        std::thread::spawn(move || {
            let body = serde_json::json!({ "args": [slow_formula(), "--size", "384"], "format": "png" }).to_string();
            // Until this render is the one running (a probe below may
            // hold the render slot for a moment).
            let r = loop {
                let r = s.request("POST", "/api/render", body.as_bytes());
                if r.status != 503 {
                    break r;
                }
            };
            done.store(true, Ordering::SeqCst);
            r
        })
    };
    // A render that fails at once holds the slot for a moment; 503 means
    // the slow render holds it.
    let busy = (503, "another render is running (one at a time): try again when it has finished".to_string());
    loop {
        assert!(!done.load(Ordering::SeqCst), "the slow render finished before a probe saw it running");
        let r = s.request("POST", "/api/render", br#"{"args": []}"#);
        if r.status == 503 {
            assert_eq!((r.status, r.error()), busy);
            break;
        }
        assert_eq!(r.error(), "\"args\" is empty: the first one is the formula");
    }
    let page = s.request("GET", "/", b"");
    assert_eq!(page.status, 200);
    let start = s.request("GET", "/api/start", b"");
    assert_eq!(start.status, 200);
    assert!(!done.load(Ordering::SeqCst), "the page and /api/start were answered only after the render");
    let r = render.join().unwrap();
    assert_eq!(r.status, 200, "{}", r.text());
    assert!(r.body.starts_with(b"\x89PNG"));
}

#[test]
fn stalled_clients_block_nobody_and_connections_are_bounded() {
    let s = start("@sphere");
    // A head without its end, and a body that stops half way.
    let mut head = s.connect();
    head.write_all(format!("GET / HTTP/1.1\r\nHost: {}\r\n", s.addr).as_bytes()).unwrap();
    let mut body = s.connect();
    let partial = format!("POST /api/program HTTP/1.1\r\nHost: {}\r\nAuthorization: token {}\r\nContent-Type: application/json\r\nContent-Length: 100\r\n\r\n{{\"args\"", s.addr, s.token);
    body.write_all(partial.as_bytes()).unwrap();
    assert_eq!(s.request("GET", "/api/start", b"").status, 200);
    assert_eq!(s.request("GET", "/", b"").status, 200);
    drop((head, body));

    // 32 connections that send nothing hold every place; the next is told.
    let idle: Vec<_> = (0..32).map(|_| s.connect()).collect();
    let r = read_response(s.connect());
    assert_eq!((r.status, r.error().as_str()), (503, "isotrace view is busy: 32 connections are open; try again in a moment"));
    drop(idle);
    // Their places come back as the server sees them close.
    let served = (0..500).any(|_| {
        let r = s.request("GET", "/", b"");
        if r.status != 200 {
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        r.status == 200
    });
    assert!(served, "the server serves again once the idle connections are closed");
}

#[test]
fn messages_quote_user_text_cut_and_printable() {
    let s = start("@sphere");
    let path = format!("/{}\x1b[2J", "a".repeat(300));
    let r = s.request("GET", &path.replace('\x1b', "%1b"), b"");
    assert_eq!((r.status, r.error()), (404, format!("no such page or API: /{}… (307 bytes)", "a".repeat(199))));
    let flag = format!("--\x1b[2J{}", "b".repeat(1000));
    assert_eq!(refused(&s, &["x", &flag]), bad(&format!("--\u{241b}[2J{}… (1006 bytes) is not available in the viewer", "b".repeat(194))));
    let format = "g".repeat(1 << 20);
    let r = s.request("POST", "/api/render", serde_json::json!({ "args": ["@sphere"], "format": format }).to_string().as_bytes());
    assert_eq!((r.status, r.error()), (400, format!("unknown format '{}… (1048576 bytes)': png or exr", "g".repeat(200))));
}

#[test]
fn the_viewer_advises_no_flag_it_refuses() {
    let s = start("@sphere");
    // 3000 monomials with distinct powers (no like terms to collect):
    // over 1 MB of WGSL.
    let terms: Vec<String> = (0..3000).map(|i| format!("{}.5*x^{}*y^{}*z^{}", i % 9 + 1, i % 21, (i / 21) % 21, i / 441)).collect();
    let (status, e) = refused(&s, &[&terms.join(" + ")]);
    assert_eq!(status, 400);
    assert!(e.starts_with("error: the generated shader is ") && e.ends_with(
        " KB of WGSL code, over the limit of 500 KB: the driver would compile it for many minutes; the viewer runs the formula as generated code: simplify the formula (a repeated subexpression written once as a definition 'name = ...;' is generated once), or render it on the command line with `isotrace render … --field tape` (or auto), which runs the formula from a buffer in a fixed interpreter\n"
    ), "{e}");
}
