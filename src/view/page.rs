//! The page's assets, embedded in the binary so `cargo install` is enough:
//! the HTML, the controls (`web/app.js`), the WebGPU host (`web/host.js`), lil-gui (vendored from npm
//! with its licence), and the self-contained page of `--export`.

/// `web/index.html`: the page, with a marker where its script goes.
const INDEX: &str = include_str!("../../web/index.html");
/// `web/app.js`: the thin WebGPU host and the controls.
const APP: &str = include_str!("../../web/app.js");
/// `web/host.js`: the WebGPU host that runs a program.
const HOST: &str = include_str!("../../web/host.js");
/// lil-gui 0.21.0 (`npm pack lil-gui`), MIT.
const LIL_GUI: &str = include_str!("../../web/vendor/lil-gui.esm.min.js");
/// lil-gui's licence, served next to it.
const LIL_GUI_LICENSE: &str = include_str!("../../web/vendor/lil-gui-LICENSE.md");

/// The marker in `index.html` replaced by the page's scripts.
const BOOT: &str = "<!--isotrace:boot-->";

/// An asset by URL path, with its MIME type.
pub fn asset(path: &str) -> Option<(Vec<u8>, &'static str)> {
    match path {
        "/" | "/index.html" => Some((served_index().into_bytes(), "text/html; charset=utf-8")),
        "/app.js" => Some((APP.as_bytes().to_vec(), "text/javascript; charset=utf-8")),
        "/host.js" => Some((HOST.as_bytes().to_vec(), "text/javascript; charset=utf-8")),
        "/lil-gui.esm.min.js" => Some((LIL_GUI.as_bytes().to_vec(), "text/javascript; charset=utf-8")),
        "/lil-gui-LICENSE.md" => Some((LIL_GUI_LICENSE.as_bytes().to_vec(), "text/plain; charset=utf-8")),
        _ => None,
    }
}

fn served_index() -> String {
    INDEX.replace(BOOT, r#"<script type="module" src="/app.js"></script>"#)
}

/// Most characters of user text a message quotes.
pub const QUOTE_CHARS: usize = 200;

/// User text (a path, a flag, a header) as a message may quote it:
/// control characters shown as symbols ([`crate::diag::user_text`]), and
/// past [`QUOTE_CHARS`] characters cut,
/// with the whole text's length: `abc… (52428800 bytes)`.
pub fn printable(text: &str) -> String {
    crate::diag::user_text(text, QUOTE_CHARS)
}

/// Export failures.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// An asset would end its inline `<script>` early.
    #[error("cannot inline {0}: it contains '</script'")]
    Script(&'static str),
}

/// The self-contained page: the start state (program, view, controls) as
/// JSON, lil-gui and the host inline. It needs no server; what does (the
/// formula editor, scene edits, saving PNG / EXR) says so in the page.
pub fn export(start: &serde_json::Value) -> Result<String, ExportError> {
    for (name, text) in [("web/app.js", APP), ("web/host.js", HOST), ("lil-gui", LIL_GUI)] {
        if text.contains("</script") {
            return Err(ExportError::Script(name));
        }
    }
    // `</` inside JSON strings becomes `<\/` (the same string), so the data
    // cannot close its script element.
    let data = start.to_string().replace("</", "<\\/");
    let license = LIL_GUI_LICENSE.replace("--", "- -");
    let scripts = format!(
        "<!-- lil-gui 0.21.0, embedded under its licence:\n{license}\n-->\n\
         <script type=\"application/json\" id=\"isotrace-start\">{data}</script>\n\
         <script type=\"text/plain\" id=\"isotrace-lil-gui\">{LIL_GUI}</script>\n\
         <script type=\"text/plain\" id=\"isotrace-host\">{HOST}</script>\n\
         <script type=\"module\">{APP}</script>"
    );
    Ok(INDEX.replace(BOOT, &scripts))
}
