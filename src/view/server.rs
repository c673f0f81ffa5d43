//! The viewer's HTTP server: the page's own assets (embedded in the
//! binary) and a small JSON API whose work an [`Api`] does (the CLI's:
//! compile a formula, lay out a scene, render a PNG or EXR). Every bad
//! request is answered with a status and `{"error": message}`; nothing a
//! client sends can stop the server (bodies are size-limited, the API is
//! called under `catch_unwind` as a last guard).

use super::page;
use std::io::Read;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Largest request body: a formula is at most 64 KiB; a scene edited in
/// the page is sent whole.
pub const MAX_BODY_BYTES: usize = 8 << 20;

/// The API's routes (`POST /api/NAME`, `GET /api/start`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Route {
    /// The first state of the page: the program for the command line's input.
    Start,
    /// Compile the render the body's `args` describe.
    Program,
    /// Lay out the edited scene in the body (no compile).
    Scene,
    /// Render the body's `args` at full size with the CLI path (`format`: png or exr).
    Render,
}

/// A successful answer.
pub enum Reply {
    /// A JSON document.
    Json(serde_json::Value),
    /// A file to download.
    File {
        /// Its bytes.
        data: Vec<u8>,
        /// MIME type.
        content_type: &'static str,
        /// Suggested file name.
        name: String,
    },
}

/// A refused request: HTTP status and the message the page shows.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ApiError {
    /// 400 for a bad request, 404, 413, 500.
    pub status: u16,
    /// Shown in the page as is (diagnostics keep their caret lines).
    pub message: String,
}

impl ApiError {
    /// A 400 with `message`.
    pub fn bad(message: impl Into<String>) -> ApiError {
        ApiError { status: 400, message: message.into() }
    }
}

/// What the server asks of its owner.
pub trait Api {
    /// Answers `route` with the parsed JSON body (`null` for GET).
    fn call(&self, route: Route, body: &serde_json::Value) -> Result<Reply, ApiError>;
}

/// Server errors.
#[derive(Debug, thiserror::Error)]
pub enum ServerError {
    /// The address could not be bound.
    #[error("cannot listen on {addr}: {reason}")]
    Bind {
        /// host:port.
        addr: String,
        /// Why.
        reason: String,
    },
}

/// A bound server.
pub struct Server {
    inner: tiny_http::Server,
}

impl Server {
    /// Listens on `host:port` (port 0: any free port).
    pub fn bind(host: &str, port: u16) -> Result<Server, ServerError> {
        let addr = if host.contains(':') { format!("[{host}]:{port}") } else { format!("{host}:{port}") };
        let inner = tiny_http::Server::http(&addr).map_err(|e| ServerError::Bind { addr: addr.clone(), reason: e.to_string() })?;
        Ok(Server { inner })
    }

    /// The page's address.
    pub fn url(&self) -> String {
        match self.inner.server_addr().to_ip() {
            Some(a) if a.is_ipv6() => format!("http://[{}]:{}/", a.ip(), a.port()),
            Some(a) => format!("http://{}:{}/", a.ip(), a.port()),
            None => "http://localhost/".into(),
        }
    }

    /// Answers requests, one at a time, until the process ends.
    pub fn run(&self, api: &dyn Api) {
        for mut req in self.inner.incoming_requests() {
            let (status, body, ctype, extra) = answer(&mut req, api);
            let mut resp = tiny_http::Response::from_data(body).with_status_code(status);
            let mut headers = vec![("Content-Type", ctype.to_string()), ("Cache-Control", "no-store".into()), ("X-Content-Type-Options", "nosniff".into())];
            headers.extend(extra);
            for (k, v) in headers {
                if let Ok(h) = tiny_http::Header::from_bytes(k.as_bytes(), v.as_bytes()) {
                    resp.add_header(h);
                }
            }
            let _ = req.respond(resp);
        }
    }
}

type Answer = (u16, Vec<u8>, &'static str, Vec<(&'static str, String)>);

fn json_error(status: u16, message: &str) -> Answer {
    (status, serde_json::json!({ "error": message }).to_string().into_bytes(), "application/json", vec![])
}

/// One request: an asset, or the API.
fn answer(req: &mut tiny_http::Request, api: &dyn Api) -> Answer {
    let path = req.url().split('?').next().unwrap_or("").to_string();
    let method = req.method().clone();
    if let Some((body, ctype)) = page::asset(&path) {
        if method != tiny_http::Method::Get {
            return json_error(405, &format!("{path} is read with GET"));
        }
        return (200, body.to_vec(), ctype, vec![]);
    }
    let route = match (path.as_str(), &method) {
        ("/api/start", tiny_http::Method::Get) => Route::Start,
        ("/api/program", tiny_http::Method::Post) => Route::Program,
        ("/api/scene", tiny_http::Method::Post) => Route::Scene,
        ("/api/render", tiny_http::Method::Post) => Route::Render,
        ("/api/start" | "/api/program" | "/api/scene" | "/api/render", _) => return json_error(405, &format!("wrong method {method} for {path}")),
        _ => return json_error(404, &format!("no such page or API: {}", page::printable(&path))),
    };
    let body = match read_body(req) {
        Ok(b) => b,
        Err(e) => return json_error(e.status, &e.message),
    };
    match catch_unwind(AssertUnwindSafe(|| api.call(route, &body))) {
        Ok(Ok(Reply::Json(v))) => (200, v.to_string().into_bytes(), "application/json", vec![]),
        Ok(Ok(Reply::File { data, content_type, name })) => (200, data, content_type, vec![("Content-Disposition", format!("attachment; filename=\"{name}\""))]),
        Ok(Err(e)) => json_error(e.status, &e.message),
        Err(_) => json_error(500, "internal error: the request made isotrace panic (a bug; the server goes on)"),
    }
}

/// The JSON body, at most [`MAX_BODY_BYTES`] (`null` when empty).
fn read_body(req: &mut tiny_http::Request) -> Result<serde_json::Value, ApiError> {
    if req.body_length().is_some_and(|n| n > MAX_BODY_BYTES) {
        return Err(ApiError { status: 413, message: format!("the request body is over the limit of {} MiB", MAX_BODY_BYTES >> 20) });
    }
    let mut buf = Vec::new();
    req.as_reader().take(MAX_BODY_BYTES as u64 + 1).read_to_end(&mut buf).map_err(|e| ApiError::bad(format!("cannot read the request body: {e}")))?;
    if buf.len() > MAX_BODY_BYTES {
        return Err(ApiError { status: 413, message: format!("the request body is over the limit of {} MiB", MAX_BODY_BYTES >> 20) });
    }
    if buf.iter().all(u8::is_ascii_whitespace) {
        return Ok(serde_json::Value::Null);
    }
    serde_json::from_slice(&buf).map_err(|e| ApiError::bad(format!("the request body is not JSON: {e}")))
}
