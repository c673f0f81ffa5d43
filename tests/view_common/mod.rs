//! Helpers of the `isotrace view` server tests: a real server process on a
//! free port, and raw HTTP/1.1 requests (with or without the session
//! token, any header) read to the end.
#![allow(dead_code)]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};

pub struct Server {
    child: Child,
    /// `127.0.0.1:PORT`.
    pub addr: String,
    pub port: u16,
    pub token: String,
    /// The line the server printed: `isotrace view: URL`.
    pub line: String,
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Starts `isotrace view INPUT --port 0` and reads its URL.
pub fn start(input: &str) -> Server {
    let mut child = Command::new(env!("CARGO_BIN_EXE_isotrace"))
        .args(["view", input, "--port", "0"])
        .env("NODEVICE_SELECT", "1")
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("isotrace starts");
    let mut line = String::new();
    BufReader::new(child.stdout.take().expect("stdout")).read_line(&mut line).expect("a URL line");
    let url = line.trim().strip_prefix("isotrace view: http://").unwrap_or_else(|| panic!("a URL line: {line}"));
    let (addr, token) = url.split_once("/?token=").unwrap_or_else(|| panic!("a token in {line}"));
    let port = addr.rsplit_once(':').and_then(|(_, p)| p.parse().ok()).expect("a port");
    Server { child, addr: addr.to_string(), port, token: token.to_string(), line }
}

/// An answer: status, header block and body.
pub struct Response {
    pub status: u16,
    pub head: String,
    pub body: Vec<u8>,
}

impl Response {
    pub fn text(&self) -> String {
        String::from_utf8_lossy(&self.body).into_owned()
    }

    /// The `error` of a JSON error body.
    pub fn error(&self) -> String {
        let v: serde_json::Value = serde_json::from_slice(&self.body).unwrap_or_else(|_| panic!("JSON: {}", self.text()));
        v["error"].as_str().unwrap_or_else(|| panic!("an error: {}", self.text())).to_string()
    }

    /// The value of header `name` (case-insensitive).
    pub fn header(&self, name: &str) -> Option<String> {
        self.head.lines().find_map(|l| l.split_once(':').filter(|(n, _)| n.eq_ignore_ascii_case(name)).map(|(_, v)| v.trim().to_string()))
    }
}

/// Reads an answer to the end of the connection.
pub fn read_response(mut c: TcpStream) -> Response {
    let mut out = Vec::new();
    let _ = c.read_to_end(&mut out);
    let split = out.windows(4).position(|w| w == b"\r\n\r\n").unwrap_or(out.len());
    let head = String::from_utf8_lossy(&out[..split]).into_owned();
    let status = head.split(' ').nth(1).and_then(|s| s.parse().ok()).unwrap_or(0);
    let body = out.get(split + 4..).unwrap_or_default().to_vec();
    Response { status, head, body }
}

impl Server {
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    pub fn connect(&self) -> TcpStream {
        TcpStream::connect(&self.addr).expect("connects")
    }

    /// Sends `raw` as it is (a write the server cuts short is ignored) and
    /// reads the answer.
    pub fn raw(&self, raw: &[u8]) -> Response {
        let mut c = self.connect();
        let _ = c.write_all(raw);
        read_response(c)
    }

    /// A request with exactly the header lines `headers` (besides
    /// Content-Length and Connection).
    pub fn send(&self, method: &str, path: &str, headers: &[String], body: &[u8]) -> Response {
        let mut head = format!("{method} {path} HTTP/1.1\r\nConnection: close\r\nContent-Length: {}\r\n", body.len());
        for h in headers {
            head.push_str(h);
            head.push_str("\r\n");
        }
        head.push_str("\r\n");
        let mut raw = head.into_bytes();
        raw.extend_from_slice(body);
        self.raw(&raw)
    }

    /// The headers of the page's own requests: Host, the token, JSON.
    pub fn page_headers(&self) -> Vec<String> {
        vec![format!("Host: {}", self.addr), format!("Authorization: token {}", self.token), "Content-Type: application/json".into()]
    }

    /// A request as the page makes it.
    pub fn request(&self, method: &str, path: &str, body: &[u8]) -> Response {
        self.send(method, path, &self.page_headers(), body)
    }

    /// The page's headers with `name` left out and `extra` added.
    pub fn request_without(&self, name: &str, extra: &[String], method: &str, path: &str, body: &[u8]) -> Response {
        let mut headers: Vec<String> = self.page_headers().into_iter().filter(|h| !h.to_ascii_lowercase().starts_with(&format!("{}:", name.to_ascii_lowercase()))).collect();
        headers.extend_from_slice(extra);
        self.send(method, path, &headers, body)
    }

    /// The page's headers and `extra`.
    pub fn request_with(&self, extra: &[String], method: &str, path: &str, body: &[u8]) -> Response {
        let mut headers = self.page_headers();
        headers.extend_from_slice(extra);
        self.send(method, path, &headers, body)
    }

    /// `POST /api/program` with `args`.
    pub fn program(&self, args: &[&str]) -> Response {
        self.request("POST", "/api/program", serde_json::json!({ "args": args }).to_string().as_bytes())
    }
}
