//! The viewer's HTTP/1.1 wire layer on a blocking [`TcpStream`]: one
//! request per connection (every answer closes it), its head parsed by
//! `httparse` in a fixed buffer, so what a client can make the server hold
//! is bounded before anything is parsed: [`MAX_HEAD_BYTES`] of head with at
//! most [`MAX_HEADERS`] fields, a body of at most
//! [`super::server::MAX_BODY_BYTES`] announced by `Content-Length`, each
//! read under a deadline so that a slow client times out instead of
//! holding its thread.

use super::server::ApiError;
use std::io::{Read, Write};
use std::net::{Shutdown, TcpStream};
use std::time::{Duration, Instant};

/// Largest request head (request line and header fields): browsers send
/// a few KiB.
pub const MAX_HEAD_BYTES: usize = 32 << 10;
/// Most header fields in a request head.
pub const MAX_HEADERS: usize = 100;
/// Longest request line (method, path and query, version).
pub const MAX_REQUEST_LINE_BYTES: usize = 8 << 10;
/// Time a client has to send a whole request head.
pub const HEAD_DEADLINE: Duration = Duration::from_secs(10);
/// Time a client has to send a whole body (8 MiB over loopback takes
/// milliseconds; a slow network link gets a generous margin).
pub const BODY_DEADLINE: Duration = Duration::from_secs(30);
/// Longest a write to a client that does not read may block.
pub const WRITE_TIMEOUT: Duration = Duration::from_secs(30);
/// After answering, how long the rest of a refused request is read and
/// dropped: closing a socket with unread data resets the connection, and
/// the client could lose the answer that says why it was refused.
const LINGER: Duration = Duration::from_secs(2);
/// At most this much of a refused request is read and dropped.
const LINGER_BYTES: usize = 16 << 20;

/// A parsed request head.
pub struct Head {
    /// `GET`, `POST`, …
    pub method: String,
    /// The request target: path and query.
    pub target: String,
    /// Header fields, names in lower case, values as (lossy) text.
    headers: Vec<(String, String)>,
    /// Bytes read past the head: the start of the body.
    rest: Vec<u8>,
}

impl Head {
    /// The first value of header `name` (lower case).
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_str())
    }

    /// Every value of header `name` (lower case), in order.
    pub fn headers<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a str> + 'a {
        self.headers.iter().filter(move |(n, _)| n == name).map(|(_, v)| v.as_str())
    }

    /// The target's path, without the query.
    pub fn path(&self) -> &str {
        self.target.split('?').next().unwrap_or("")
    }

    /// The value of query parameter `key` (no percent-decoding: the
    /// parameters the server reads are plain ASCII).
    pub fn query(&self, key: &str) -> Option<&str> {
        let query = self.target.split_once('?')?.1;
        query.split('&').find_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))
    }
}

fn refused(status: u16, message: impl Into<String>) -> ApiError {
    ApiError { status, message: message.into() }
}

/// What reading under a deadline gave.
enum Got {
    Bytes(usize),
    End,
    Late,
    Failed,
}

/// One read into `buf` that gives up at `deadline`.
fn read_before(stream: &mut TcpStream, buf: &mut [u8], deadline: Instant) -> Got {
    let left = deadline.saturating_duration_since(Instant::now());
    if left.is_zero() || stream.set_read_timeout(Some(left)).is_err() {
        return Got::Late;
    }
    match stream.read(buf) {
        Ok(0) => Got::End,
        Ok(n) => Got::Bytes(n),
        Err(e) if matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => Got::Late,
        Err(e) if e.kind() == std::io::ErrorKind::Interrupted => Got::Bytes(0),
        Err(_) => Got::Failed,
    }
}

/// Reads one request head. `Ok(None)`: the client sent nothing before it
/// closed the connection or the deadline passed (nobody to answer).
pub fn read_head(stream: &mut TcpStream, deadline: Instant) -> Result<Option<Head>, ApiError> {
    // The one buffer a request head may fill: nothing grows past it.
    let mut buf = vec![0u8; MAX_HEAD_BYTES];
    let mut len = 0;
    let mut line_end = None;
    loop {
        let n = match read_before(stream, &mut buf[len..], deadline) {
            Got::Bytes(n) => n,
            Got::End | Got::Failed if len == 0 => return Ok(None),
            Got::Late if len == 0 => return Ok(None),
            Got::End | Got::Failed => return Err(refused(400, "the request head ended before its blank line")),
            Got::Late => return Err(refused(408, format!("the request head did not arrive within {} s", HEAD_DEADLINE.as_secs()))),
        };
        // Only the new bytes are searched (with the three before them for
        // a blank line split between reads).
        let searched = len.saturating_sub(3);
        if line_end.is_none() {
            line_end = buf[len..len + n].iter().position(|&b| b == b'\n').map(|i| len + i);
        }
        len += n;
        if line_end.unwrap_or(len) > MAX_REQUEST_LINE_BYTES {
            return Err(refused(414, format!("the request line is over the limit of {} KiB", MAX_REQUEST_LINE_BYTES >> 10)));
        }
        if ends_head(&buf[searched..len]) {
            return parse(&buf[..len]).map(Some);
        }
        if len == buf.len() {
            return Err(refused(431, format!("the request head is over the limit of {} KiB", MAX_HEAD_BYTES >> 10)));
        }
    }
}

/// Whether `bytes` hold the blank line that ends a head (`httparse`
/// accepts bare line feeds as well).
fn ends_head(bytes: &[u8]) -> bool {
    bytes.windows(4).any(|w| w == b"\r\n\r\n") || bytes.windows(2).any(|w| w == b"\n\n")
}

/// Parses a complete head; `buf` may hold the start of the body after it.
fn parse(buf: &[u8]) -> Result<Head, ApiError> {
    let mut fields = [httparse::EMPTY_HEADER; MAX_HEADERS];
    let mut req = httparse::Request::new(&mut fields);
    let end = match req.parse(buf) {
        Ok(httparse::Status::Complete(end)) => end,
        Ok(httparse::Status::Partial) => return Err(refused(400, "the request head is incomplete")),
        Err(httparse::Error::TooManyHeaders) => return Err(refused(431, format!("the request has over {MAX_HEADERS} header fields"))),
        Err(e) => return Err(refused(400, format!("malformed request head: {e}"))),
    };
    let headers = req.headers.iter().map(|h| (h.name.to_ascii_lowercase(), String::from_utf8_lossy(h.value).into_owned())).collect();
    Ok(Head {
        method: req.method.unwrap_or("").to_string(),
        target: req.path.unwrap_or("").to_string(),
        headers,
        rest: buf[end..].to_vec(),
    })
}

/// The body `Content-Length` announces, at most `limit` bytes, read
/// before `deadline`.
pub fn read_body(stream: &mut TcpStream, head: &Head, limit: usize, deadline: Instant) -> Result<Vec<u8>, ApiError> {
    if head.header("transfer-encoding").is_some() {
        return Err(refused(501, "chunked request bodies are not accepted: send Content-Length"));
    }
    let mut lengths = head.headers("content-length").map(str::trim);
    let n = match lengths.next() {
        None => return Ok(Vec::new()),
        Some(v) => v.parse::<u64>().ok().filter(|_| v.bytes().all(|b| b.is_ascii_digit())),
    };
    let Some(n) = n.filter(|&n| lengths.all(|v| v.parse() == Ok(n))) else {
        return Err(refused(400, "the request's Content-Length is not one number"));
    };
    if n > limit as u64 {
        return Err(refused(413, format!("the request body is over the limit of {} MiB", limit >> 20)));
    }
    if head.header("expect").is_some_and(|e| e.eq_ignore_ascii_case("100-continue")) {
        let _ = stream.write_all(b"HTTP/1.1 100 Continue\r\n\r\n");
    }
    let n = n as usize;
    let mut body = vec![0u8; n];
    let mut len = head.rest.len().min(n);
    body[..len].copy_from_slice(&head.rest[..len]);
    while len < n {
        match read_before(stream, &mut body[len..], deadline) {
            Got::Bytes(k) => len += k,
            Got::Late => return Err(refused(408, format!("the request body did not arrive within {} s", BODY_DEADLINE.as_secs()))),
            Got::End | Got::Failed => return Err(refused(400, format!("the request body ended after {len} of its {n} bytes"))),
        }
    }
    Ok(body)
}

/// An answer to send.
pub struct Answer {
    /// HTTP status.
    pub status: u16,
    /// MIME type of the body.
    pub content_type: &'static str,
    /// Header fields besides the ones every answer has.
    pub extra: Vec<(&'static str, String)>,
    /// The body.
    pub body: Vec<u8>,
}

fn reason(status: u16) -> &'static str {
    match status {
        200 => "OK",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        408 => "Request Timeout",
        413 => "Content Too Large",
        414 => "URI Too Long",
        415 => "Unsupported Media Type",
        431 => "Request Header Fields Too Large",
        501 => "Not Implemented",
        503 => "Service Unavailable",
        _ => "Internal Server Error",
    }
}

/// Writes `answer` (every answer closes its connection).
pub fn send(stream: &mut TcpStream, answer: &Answer) {
    let _ = stream.set_write_timeout(Some(WRITE_TIMEOUT));
    let mut head = format!("HTTP/1.1 {} {}\r\nContent-Type: {}\r\nContent-Length: {}\r\n", answer.status, reason(answer.status), answer.content_type, answer.body.len());
    // No caching, no MIME sniffing, no framing by other pages, no token
    // in a Referer.
    head.push_str("Cache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nX-Frame-Options: DENY\r\nReferrer-Policy: no-referrer\r\nConnection: close\r\n");
    for (name, value) in &answer.extra {
        head.push_str(&format!("{name}: {value}\r\n"));
    }
    head.push_str("\r\n");
    let _ = stream.write_all(head.as_bytes()).and_then(|_| stream.write_all(&answer.body));
}

/// Closes a connection whose answer is sent: the write side at once, the
/// read side once the client has closed its own (or after `LINGER`).
pub fn linger(mut stream: TcpStream) {
    if stream.shutdown(Shutdown::Write).is_err() {
        return;
    }
    let deadline = Instant::now() + LINGER;
    let mut sink = [0u8; 8192];
    let mut dropped = 0;
    while dropped < LINGER_BYTES {
        match read_before(&mut stream, &mut sink, deadline) {
            Got::Bytes(n) => dropped += n,
            Got::End | Got::Late | Got::Failed => break,
        }
    }
}

/// Whether the client has closed its side of the connection (its request
/// has been read: what is left is at most its end of stream).
pub fn client_gone(stream: &TcpStream) -> bool {
    if stream.set_nonblocking(true).is_err() {
        return false;
    }
    let gone = match stream.peek(&mut [0u8; 1]) {
        Ok(n) => n == 0,
        Err(e) => e.kind() != std::io::ErrorKind::WouldBlock,
    };
    let _ = stream.set_nonblocking(false);
    gone
}
