//! The viewer's HTTP server: the page's own assets (embedded in the
//! binary) and a small JSON API whose work an [`Api`] does (the CLI's:
//! compile a formula, lay out a scene, render a PNG or EXR). Every bad
//! request is answered with a status and `{"error": message}`; nothing a
//! client sends can stop the server or make it hold more than the limits
//! of [`super::http`] (the API is called under `catch_unwind` as a last
//! guard).
//!
//! Each connection has its own thread, at most [`MAX_CONNECTIONS`] at
//! once, so the page and cheap calls are answered while a render runs.
//! Work is bounded apart from connections: [`MAX_RENDERS`] render at a
//! time (a second is refused at once: it would wait for as long as the
//! first takes), [`MAX_CALLS`] other API calls (a further one waits up to
//! [`CALL_WAIT`]). Who may call is [`super::access`]'s: Host, Origin and
//! the session token.

use super::access::{Access, TokenError};
use super::http::{self, Answer, Head};
use super::page;
use std::net::TcpStream;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::{Condvar, Mutex};
use std::time::{Duration, Instant};

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

/// Connections served at once; a further one is answered 503.
pub const MAX_CONNECTIONS: usize = 32;
/// Renders (`/api/render`) at once: the device renders one frame at a time.
pub const MAX_RENDERS: usize = 1;
/// Other API calls (compiles, scene layouts) at once.
pub const MAX_CALLS: usize = 4;
/// How long an API call waits for one of the [`MAX_CALLS`] before it is
/// answered 503.
pub const CALL_WAIT: Duration = Duration::from_secs(30);
/// Longest error message sent: a message that quotes a huge input is cut
/// (a diagnostic of a formula at its 64 KiB limit, with its caret line, fits).
pub const MAX_MESSAGE_BYTES: usize = 256 << 10;
/// Stack of a connection's thread: the main thread's usual size, which the
/// API's recursive passes (parser, scene lowering) were written for.
const HANDLER_STACK_BYTES: usize = 8 << 20;

/// A refused request: HTTP status and the message the page shows.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ApiError {
    /// 400 for a bad request, 403, 404, 413, 415, 431, 500, 503, …
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

/// What the server asks of its owner; called from several threads.
pub trait Api: Sync {
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
    /// No session token.
    #[error(transparent)]
    Token(#[from] TokenError),
}

/// A bound server.
pub struct Server {
    listener: std::net::TcpListener,
    access: Access,
    url: String,
}

impl Server {
    /// Listens on `host:port` (port 0: any free port) with a fresh
    /// session token.
    pub fn bind(host: &str, port: u16) -> Result<Server, ServerError> {
        let addr = if host.contains(':') && !host.starts_with('[') { format!("[{host}]:{port}") } else { format!("{host}:{port}") };
        let bind_error = |e: std::io::Error| ServerError::Bind { addr: addr.clone(), reason: e.to_string() };
        let listener = std::net::TcpListener::bind(&addr).map_err(bind_error)?;
        let bound = listener.local_addr().map_err(bind_error)?;
        let access = Access::new(host, bound)?;
        // Bound to every interface: the URL for this machine's browser.
        let ip = match bound.ip() {
            std::net::IpAddr::V4(a) if a.is_unspecified() => std::net::Ipv4Addr::LOCALHOST.into(),
            std::net::IpAddr::V6(a) if a.is_unspecified() => std::net::Ipv6Addr::LOCALHOST.into(),
            ip => ip,
        };
        let url = std::net::SocketAddr::new(ip, bound.port());
        let url = format!("http://{url}/?token={}", access.token());
        Ok(Server { listener, access, url })
    }

    /// The page's address, with the session token.
    pub fn url(&self) -> &str {
        &self.url
    }

    /// Answers requests until the process ends.
    pub fn run(&self, api: &dyn Api) {
        let work = Work { access: &self.access, renders: Slots::new(MAX_RENDERS), calls: Slots::new(MAX_CALLS) };
        let connections = Slots::new(MAX_CONNECTIONS);
        std::thread::scope(|scope| {
            for stream in self.listener.incoming() {
                let Ok(mut stream) = stream else {
                    // Out of file descriptors, say: wait for some to close.
                    std::thread::sleep(Duration::from_millis(50));
                    continue;
                };
                let Some(slot) = connections.take(Duration::ZERO) else {
                    let busy = ApiError { status: 503, message: format!("isotrace view is busy: {MAX_CONNECTIONS} connections are open; try again in a moment") };
                    // A fresh connection's send buffer is empty: this
                    // short answer does not block the accepting thread.
                    http::send(&mut stream, &json_error(busy));
                    continue;
                };
                let work = &work;
                let handler = move || {
                    let _slot = slot;
                    let _ = catch_unwind(AssertUnwindSafe(|| serve(stream, work, api)));
                };
                // A thread that cannot be made drops its connection (and slot).
                let _ = std::thread::Builder::new().name("isotrace-view".into()).stack_size(HANDLER_STACK_BYTES).spawn_scoped(scope, handler);
            }
        });
    }
}

/// What the connections share: the access rules and the work bounds.
struct Work<'a> {
    access: &'a Access,
    renders: Slots,
    calls: Slots,
}

/// A counting semaphore.
struct Slots {
    used: Mutex<usize>,
    freed: Condvar,
    max: usize,
}

/// One of a [`Slots`]' places, given back when dropped.
struct Slot<'a>(&'a Slots);

impl Slots {
    fn new(max: usize) -> Slots {
        Slots { used: Mutex::new(0), freed: Condvar::new(), max }
    }

    /// A place, waiting at most `wait` for one.
    fn take(&self, wait: Duration) -> Option<Slot<'_>> {
        let deadline = Instant::now() + wait;
        let mut used = self.used.lock().unwrap_or_else(|e| e.into_inner());
        while *used >= self.max {
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return None;
            }
            used = self.freed.wait_timeout(used, left).unwrap_or_else(|e| e.into_inner()).0;
        }
        *used += 1;
        Some(Slot(self))
    }
}

impl Drop for Slot<'_> {
    fn drop(&mut self) {
        *self.0.used.lock().unwrap_or_else(|e| e.into_inner()) -= 1;
        self.0.freed.notify_one();
    }
}

/// One connection: one request and its answer.
fn serve(mut stream: TcpStream, work: &Work, api: &dyn Api) {
    let answer = match http::read_head(&mut stream, Instant::now() + http::HEAD_DEADLINE) {
        Ok(None) => return,
        Ok(Some(head)) => answer(&head, &mut stream, work, api).unwrap_or_else(json_error),
        Err(e) => json_error(e),
    };
    http::send(&mut stream, &answer);
    http::linger(stream);
}

fn json_error(e: ApiError) -> Answer {
    let mut message = e.message;
    if message.len() > MAX_MESSAGE_BYTES {
        let total = message.len();
        let mut cut = MAX_MESSAGE_BYTES;
        while !message.is_char_boundary(cut) {
            cut -= 1;
        }
        message.truncate(cut);
        message.push_str(&format!("\n… (the message is cut: {total} bytes in all)"));
    }
    let body = serde_json::json!({ "error": message }).to_string().into_bytes();
    Answer { status: e.status, content_type: "application/json", extra: vec![], body }
}

fn status(status: u16, message: String) -> ApiError {
    ApiError { status, message }
}

/// One request: an asset, or the API.
fn answer(head: &Head, stream: &mut TcpStream, work: &Work, api: &dyn Api) -> Result<Answer, ApiError> {
    let path = head.path();
    work.access.check_host(head)?;
    work.access.check_origin(head, path.starts_with("/api/"))?;
    if let Some((body, content_type)) = page::asset(path) {
        if head.method != "GET" {
            return Err(status(405, format!("{path} is read with GET")));
        }
        let extra = work.access.page_cookie(head)?.map(|c| ("Set-Cookie", c)).into_iter().collect();
        return Ok(Answer { status: 200, content_type, extra, body });
    }
    let route = route(path, &head.method)?;
    work.access.check_token(head)?;
    let body = if head.method == "POST" { json_body(stream, head)? } else { serde_json::Value::Null };
    let _slot = match route {
        Route::Render => work.renders.take(Duration::ZERO).ok_or_else(|| status(503, "another render is running (one at a time): try again when it has finished".into()))?,
        _ => match work.calls.take(Duration::ZERO) {
            Some(slot) => slot,
            None => {
                let busy = || status(503, format!("isotrace view is busy: {MAX_CALLS} requests are being computed; try again in a moment"));
                let slot = work.calls.take(CALL_WAIT).ok_or_else(busy)?;
                // Nobody is left to answer after the wait: skip the work.
                if http::client_gone(stream) {
                    return Err(status(400, "the client closed its connection while the request waited".into()));
                }
                slot
            }
        },
    };
    call(api, route, &body)
}

/// The API route of `path` and `method`.
fn route(path: &str, method: &str) -> Result<Route, ApiError> {
    match (path, method) {
        ("/api/start", "GET") => Ok(Route::Start),
        ("/api/program", "POST") => Ok(Route::Program),
        ("/api/scene", "POST") => Ok(Route::Scene),
        ("/api/render", "POST") => Ok(Route::Render),
        ("/api/start" | "/api/program" | "/api/scene" | "/api/render", _) => Err(status(405, format!("wrong method {} for {path}", page::printable(method)))),
        _ => Err(status(404, format!("no such page or API: {}", page::printable(path)))),
    }
}

/// The JSON body of an API POST: `Content-Type: application/json` (a page
/// of another site cannot send that without a CORS preflight, which this
/// server never grants), at most [`MAX_BODY_BYTES`] (`null` when empty).
fn json_body(stream: &mut TcpStream, head: &Head) -> Result<serde_json::Value, ApiError> {
    let content_type = head.header("content-type").unwrap_or("");
    let mime = content_type.split(';').next().unwrap_or("").trim();
    if !mime.eq_ignore_ascii_case("application/json") {
        return Err(status(415, format!("the API takes a JSON body with Content-Type: application/json, not '{}'", page::printable(content_type))));
    }
    let buf = http::read_body(stream, head, MAX_BODY_BYTES, Instant::now() + http::BODY_DEADLINE)?;
    if buf.iter().all(u8::is_ascii_whitespace) {
        return Ok(serde_json::Value::Null);
    }
    serde_json::from_slice(&buf).map_err(|e| ApiError::bad(format!("the request body is not JSON: {e}")))
}

/// The API's answer to `route`, a panic made a 500.
fn call(api: &dyn Api, route: Route, body: &serde_json::Value) -> Result<Answer, ApiError> {
    match catch_unwind(AssertUnwindSafe(|| api.call(route, body))) {
        Ok(Ok(Reply::Json(v))) => Ok(Answer { status: 200, content_type: "application/json", extra: vec![], body: v.to_string().into_bytes() }),
        Ok(Ok(Reply::File { data, content_type, name })) => {
            let disposition = format!("attachment; filename=\"{}\"", name.replace(['"', '\\', '\r', '\n'], "_"));
            Ok(Answer { status: 200, content_type, extra: vec![("Content-Disposition", disposition)], body: data })
        }
        Ok(Err(e)) => Err(e),
        Err(_) => Err(status(500, "internal error: the request made isotrace panic (a bug; the server goes on)".into())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn error_of(a: &Answer) -> String {
        let v: serde_json::Value = serde_json::from_slice(&a.body).unwrap();
        v["error"].as_str().unwrap().to_string()
    }

    #[test]
    fn a_huge_message_is_cut_on_a_character_boundary() {
        // 'é' is two bytes: the limit falls inside one.
        let message = format!("x{}", "é".repeat(MAX_MESSAGE_BYTES));
        let a = json_error(ApiError::bad(message.clone()));
        assert_eq!(a.status, 400);
        let expected = format!("{}\n… (the message is cut: {} bytes in all)", &message[..MAX_MESSAGE_BYTES - 1], message.len());
        assert_eq!(error_of(&a), expected);
        let short = json_error(ApiError::bad("é".repeat(100)));
        assert_eq!(error_of(&short), "é".repeat(100));
    }
}
