//! Who may use the viewer's server: requests addressed to this server by
//! a name that cannot be rebound ([`Access::check_host`]), not sent by
//! another site's page ([`Access::check_origin`]), and, for the API,
//! carrying the session's token ([`Access::check_token`]). The token is
//! random from the OS, printed in the page's URL; loading the page with it
//! sets an `HttpOnly`, `SameSite=Strict` cookie that the page's own
//! requests carry. A web page the user visits knows neither, so it can
//! neither call the API nor read its answers, even under DNS rebinding.

use super::http::Head;
use super::page::printable;
use super::server::ApiError;
use std::net::{IpAddr, SocketAddr};

/// Bytes of randomness in a session token (shown as hex).
const TOKEN_BYTES: usize = 32;

/// The session's token and the names this server answers to.
pub struct Access {
    token: String,
    port: u16,
    /// Host names (lower case; IPv6 in brackets) a request may address.
    names: Vec<String>,
    /// Bound to every interface: any IP literal addresses this server (a
    /// literal cannot be rebound; a DNS name can).
    any_ip: bool,
}

/// Errors making the session token.
#[derive(Debug, thiserror::Error)]
#[error("cannot get random bytes from the OS for the session token: {0}")]
pub struct TokenError(String);

fn forbidden(message: String) -> ApiError {
    ApiError { status: 403, message }
}

/// `host` as it appears in a Host header: IPv6 literals in brackets.
fn host_form(host: &str) -> String {
    let bare = host.trim_start_matches('[').trim_end_matches(']');
    match bare.parse::<IpAddr>() {
        Ok(IpAddr::V6(a)) => format!("[{a}]"),
        Ok(a) => a.to_string(),
        Err(_) => bare.to_ascii_lowercase(),
    }
}

impl Access {
    /// The rules for a server bound to `bound`, asked for with `--host`
    /// `host`; makes a fresh token.
    pub fn new(host: &str, bound: SocketAddr) -> Result<Access, TokenError> {
        let mut bytes = [0u8; TOKEN_BYTES];
        getrandom::fill(&mut bytes).map_err(|e| TokenError(e.to_string()))?;
        let token = bytes.iter().map(|b| format!("{b:02x}")).collect();
        let mut names: Vec<String> = ["localhost", "127.0.0.1", "[::1]"].into_iter().map(String::from).collect();
        names.push(host_form(&bound.ip().to_string()));
        names.push(host_form(host));
        Ok(Access { token, port: bound.port(), names, any_ip: bound.ip().is_unspecified() })
    }

    /// The session token.
    pub fn token(&self) -> &str {
        &self.token
    }

    /// The cookie that carries the token; named by port, since cookies are
    /// shared by every port of a host and two viewers may run at once.
    fn cookie_name(&self) -> String {
        format!("isotrace_view_{}", self.port)
    }

    /// Whether `authority` (`name[:port]`) names this server.
    fn is_ours(&self, authority: &str) -> bool {
        let (name, port) = match authority.rsplit_once(':') {
            Some((n, p)) if !p.contains(']') => (n, p.parse::<u16>().ok()),
            _ => (authority, Some(80)),
        };
        let name = name.to_ascii_lowercase();
        let literal = name.trim_start_matches('[').trim_end_matches(']').parse::<IpAddr>().is_ok();
        port == Some(self.port) && (self.names.contains(&name) || (self.any_ip && literal))
    }

    /// The Host header names this server: a page on another name that
    /// resolves here (DNS rebinding) is refused.
    pub fn check_host(&self, head: &Head) -> Result<(), ApiError> {
        match head.header("host") {
            Some(h) if self.is_ours(h.trim()) => Ok(()),
            Some(h) => Err(forbidden(format!(
                "the request is addressed to '{}', not to this server: open the URL isotrace view printed (http://127.0.0.1:{}/?token=…)",
                printable(h),
                self.port
            ))),
            None => Err(ApiError::bad("the request has no Host header")),
        }
    }

    /// No `Origin` but this server's, and for the API no `Sec-Fetch-Site`
    /// but same-origin or none (typed in, a bookmark).
    pub fn check_origin(&self, head: &Head, api: bool) -> Result<(), ApiError> {
        if let Some(origin) = head.header("origin")
            && !origin.strip_prefix("http://").is_some_and(|a| self.is_ours(a))
        {
            return Err(forbidden(format!("the request comes from another site's page (Origin: {}): isotrace view answers only its own page", printable(origin))));
        }
        match head.header("sec-fetch-site") {
            Some(site) if api && !matches!(site, "same-origin" | "none") => {
                Err(forbidden(format!("the request comes from another site's page (Sec-Fetch-Site: {}): isotrace view answers only its own page", printable(site))))
            }
            _ => Ok(()),
        }
    }

    /// The token, in the session cookie or an `Authorization: token …`
    /// header.
    pub fn check_token(&self, head: &Head) -> Result<(), ApiError> {
        let name = self.cookie_name();
        let from_cookie = head.headers("cookie").flat_map(|c| c.split(';')).filter_map(|kv| kv.trim().split_once('=')).filter(|(k, _)| *k == name).map(|(_, v)| v);
        let from_header = head.headers("authorization").filter_map(|a| a.trim().strip_prefix("token ")).map(str::trim);
        if from_cookie.chain(from_header).any(|t| self.matches(t)) {
            return Ok(());
        }
        Err(forbidden("this request has no valid session token: open the URL isotrace view printed (it ends in ?token=…)".into()))
    }

    /// For a page loaded with `?token=`: the cookie to set, or a refusal
    /// of a wrong token. `None` without a token (the page then says, from
    /// the API's answer, which URL to open).
    pub fn page_cookie(&self, head: &Head) -> Result<Option<String>, ApiError> {
        match head.query("token") {
            None => Ok(None),
            Some(t) if self.matches(t) => Ok(Some(format!("{}={}; Path=/; HttpOnly; SameSite=Strict", self.cookie_name(), self.token))),
            Some(_) => Err(forbidden("the token in this URL is not this server's: open the URL isotrace view printed".into())),
        }
    }

    /// Compares in time independent of where `given` first differs.
    fn matches(&self, given: &str) -> bool {
        let (a, b) = (self.token.as_bytes(), given.as_bytes());
        a.len() == b.len() && a.iter().zip(b).fold(0u8, |d, (x, y)| d | (x ^ y)) == 0
    }
}
