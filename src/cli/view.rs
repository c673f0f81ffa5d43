//! `isotrace view`: its flags, and the page's requests answered with the
//! render command's own code. The page describes a view as the argument
//! list of `isotrace render` (the line its "copy CLI command" button
//! gives); the server parses it with the same clap definition, refuses
//! flags that would read or write files, and plans it with
//! [`super::render::plan`] / [`super::scene_render::plan`], so a view and
//! `render` of the same line are the same frame.

use super::render::RenderArgs;
use super::CliError;
use clap::Args;
use crate::render::{Settings, Traversal};
use crate::view::page::printable;
use crate::view::{Api, ApiError, Reply, Route};
use serde_json::{json, Value};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Mutex;

/// `isotrace view` flags.
#[derive(Args, Debug)]
pub struct ViewerArgs {
    /// The formula, @name of a catalog surface, a path ending in .iso, or a .scene.json scene.
    #[arg(value_name = "FORMULA|@name|FILE.iso|SCENE.json", allow_hyphen_values = true)]
    input: String,
    /// Port to listen on (0: any free port).
    #[arg(long, value_name = "N", default_value_t = 8737)]
    port: u16,
    /// Open the page in the default browser (xdg-open).
    #[arg(long)]
    open: bool,
    /// Address to listen on; anything but loopback exposes the server to the network.
    #[arg(long, value_name = "H", default_value = "127.0.0.1")]
    host: String,
    /// Write a self-contained static page (no server) to this file and exit.
    #[arg(long, value_name = "page.html")]
    export: Option<PathBuf>,
    #[arg(long, help = super::scene::ALLOW_SCENE_PATHS_HELP)]
    allow_scene_paths: bool,
}

/// The render flags a page may send. Anything else (files to read or
/// write, frames, batch flags) is refused: the server reads only the file
/// named on its command line.
const ALLOWED: &[&str] = &[
    "--size", "--box", "--eye", "--target", "--up", "--fov", "--eps", "--t", "--param", "--algebra", "--max-iter", "--clip", "--debug-unresolved", "--unresolved",
    "--method", "--lipschitz", "--omega", "--no-screen-space", "--no-dynamic-eps", "--eps-min", "--fixpoint", "--bound", "--no-bound", "--max-steps",
    "--min-step", "--shadows", "--glass", "--light", "--shadow-eps", "--opacity", "--layers", "--iso", "--reflect", "--reflectivity", "--color",
];

/// Most arguments in a request.
const MAX_ARGS: usize = 200;
/// Longest flag or flag value in a request (the formula has the front
/// end's own limit).
const MAX_FLAG_ARG_BYTES: usize = 4096;

fn is_scene(s: &str) -> bool {
    s.ends_with(".scene.json")
}

/// `--name` of `--name=value`.
fn flag_name(arg: &str) -> &str {
    arg.split('=').next().unwrap_or("")
}

/// A flag a request may give, or why not.
fn check_flag(arg: &str) -> Result<(), ApiError> {
    let name = flag_name(arg);
    if ALLOWED.contains(&name) {
        return Ok(());
    }
    let why = match name {
        // The page runs the generated kernel; the tape and the scene field
        // are the command line's.
        "--field" => ": the page runs the formula's generated kernel (`isotrace render --field …` renders with another field source)",
        _ => "",
    };
    Err(ApiError::bad(format!("{} is not available in the viewer{why}", printable(name))))
}

/// A render error as the viewer says it: the advice names no flag the
/// viewer refuses.
fn view_render_error(e: crate::gpu::RenderError) -> ApiError {
    match e {
        e @ crate::gpu::RenderError::ShaderTooLarge { .. } => ApiError::bad(format!(
            "error: {e}; the viewer runs the formula as generated code: simplify the formula (a repeated subexpression written once as a definition 'name = ...;' is generated once), or render it on the command line with `isotrace render … --field tape` (or auto), which runs the formula from a buffer in a fixed interpreter\n"
        )),
        e => bad(super::error::render_error(e)),
    }
}

/// The page's requests, answered for the input of the command line.
struct Backend {
    input: String,
    gpu: Mutex<Option<crate::gpu::Gpu>>,
    allow_scene_paths: bool,
}

fn bad(e: CliError) -> ApiError {
    ApiError::bad(e.text(false))
}

impl Backend {
    /// The body's `args` checked and parsed as `isotrace render` flags.
    /// The first is the input: the command line's, or an edited formula.
    fn args(&self, body: &Value) -> Result<(Vec<String>, RenderArgs), ApiError> {
        let list = body.get("args").and_then(Value::as_array).ok_or_else(|| ApiError::bad("the request needs \"args\": the render command's arguments"))?;
        if list.len() > MAX_ARGS {
            return Err(ApiError::bad(format!("\"args\" has {} arguments: the viewer takes at most {MAX_ARGS}", list.len())));
        }
        let args: Vec<String> = list.iter().map(|v| v.as_str().map(str::to_string)).collect::<Option<_>>().ok_or_else(|| ApiError::bad("\"args\" must be strings"))?;
        let Some((first, flags)) = args.split_first() else { return Err(ApiError::bad("\"args\" is empty: the first one is the formula")) };
        self.check_input(first)?;
        for (i, a) in flags.iter().enumerate() {
            if a.len() > MAX_FLAG_ARG_BYTES {
                return Err(ApiError::bad(format!("argument {} is {} bytes long: a flag or its value takes at most {MAX_FLAG_ARG_BYTES}", i + 2, a.len())));
            }
            let flag_like = a.starts_with("--") || (a.starts_with('-') && a[1..].starts_with(|c: char| c.is_ascii_alphabetic()));
            if flag_like {
                check_flag(a)?;
            }
        }
        // The input after `--`: whatever it holds, clap takes it as the
        // formula, never as a flag.
        let argv = ["isotrace", "render"].into_iter().map(String::from).chain(flags.iter().cloned()).chain(["-o", "view.png", "--"].map(String::from)).chain([first.clone()]);
        let cli = <super::Cli as clap::Parser>::try_parse_from(argv).map_err(|e| ApiError::bad(e.to_string()))?;
        let super::Command::Render(r) = cli.command else { return Err(ApiError::bad("not a render command")) };
        if r.formula.file.is_some() || r.formula.inline.is_some() || r.formula.formula.as_deref() != Some(first.as_str()) {
            return Err(ApiError::bad(format!("the viewer reads only the input named on its command line ('{}')", printable(&self.input))));
        }
        Ok((args, r))
    }

    /// A request's first argument: the command line's input, or (unless
    /// that is a scene) a formula text, which reads no file. Nothing a
    /// request names is opened, so no answer tells whether it exists.
    fn check_input(&self, first: &str) -> Result<(), ApiError> {
        if first == self.input {
            return Ok(());
        }
        if first.starts_with("--") {
            check_flag(first)?;
            return Err(ApiError::bad(format!("the first argument is the input ('{}' or an edited formula), not the flag {}", printable(&self.input), printable(flag_name(first)))));
        }
        if is_scene(&self.input) {
            return Err(ApiError::bad(format!("this view is of the scene '{}': the first argument is that file, not '{}'", printable(&self.input), printable(first))));
        }
        if first == "-" || first.ends_with(".iso") || is_scene(first) {
            return Err(ApiError::bad(format!("the viewer reads only the file named on its command line ('{}'), not '{}'", printable(&self.input), printable(first))));
        }
        Ok(())
    }

    /// The scene of a request: the file of the command line (its grid
    /// files as `--allow-scene-paths` allows), or the edited one in the
    /// body, which may name only the grid files that file names: their
    /// grids are taken from memory, so no file a request names is read.
    fn scene(&self, body: &Value) -> Result<crate::scene::Scene, ApiError> {
        use crate::scene::format::{self, GridPaths};
        let file = std::path::Path::new(&self.input);
        let loaded = super::scene::load(file, self.allow_scene_paths).map_err(bad)?;
        match body.get("scene") {
            Some(v) if !v.is_null() => {
                let base = file.parent().unwrap_or(std::path::Path::new(""));
                format::parse_with(&v.to_string(), base, &GridPaths::loaded_by(&loaded)).map_err(|e| ApiError::bad(format!("the edited scene: {e}")))
            }
            _ => Ok(loaded),
        }
    }

    /// Compiles the request's render into the page's state.
    fn program(&self, body: &Value) -> Result<Value, ApiError> {
        let (mut args, mut r) = self.args(body)?;
        let t0 = std::time::Instant::now();
        let (program, settings, traversal, color, extra) = if is_scene(&args[0]) {
            let scene = self.scene(body)?;
            let p = super::scene_render::plan(&r, &scene, std::path::Path::new(&args[0])).map_err(bad)?;
            let data = p.lin.field_data();
            let t = p.traversal.clone();
            let program = crate::view::program(&data, &t, &p.settings).map_err(view_render_error)?;
            let scene_json: Value = serde_json::from_str(&crate::scene::format::to_json(&scene)).unwrap_or(Value::Null);
            (program, p.settings, t, r.color.clone(), json!({ "scene": scene_json, "params": [], "new_params": [], "scene_features": data.features }))
        } else {
            let loaded = r.formula.load_with_header().map_err(bad)?;
            let new_params = default_params(&loaded, &mut r, &mut args)?;
            let p = super::render::plan_loaded(&r, loaded).map_err(bad)?;
            let program = crate::view::program(&p.loaded.formula.ir, &p.traversal, &p.settings).map_err(view_render_error)?;
            let names = p.loaded.formula.ir.params.iter().map(|(n, _)| n.clone());
            let params: Vec<Value> = names.zip(&p.settings.params).map(|(n, v)| json!({ "name": n, "value": v })).collect();
            let f = &p.loaded.formula;
            (program, p.settings, p.traversal, p.color_text, json!({ "formula": f.source, "origin": f.origin, "params": params, "new_params": new_params, "scene": null }))
        };
        let mut state = json!({
            "args": args,
            "input": self.input,
            "program": program,
            "view": view_json(&settings),
            "options": options_json(&traversal, &color),
            "warnings": frame_warnings(&traversal),
            "compile_ms": t0.elapsed().as_secs_f64() * 1e3,
        });
        merge(&mut state, extra);
        Ok(state)
    }

    /// An edited scene laid out: its buffers (no shader), and what the
    /// edit moves with them as `render` of the edited scene would: the
    /// framing the request's flags leave to the scene (its box, and the
    /// camera and eps when not given), the Lipschitz bound in the uniforms.
    fn scene_edit(&self, body: &Value) -> Result<Value, ApiError> {
        let (args, r) = self.args(body)?;
        if !is_scene(&args[0]) {
            return Err(ApiError::bad("this view is not of a scene"));
        }
        let t0 = std::time::Instant::now();
        let scene = self.scene(body)?;
        let p = super::scene_render::plan(&r, &scene, std::path::Path::new(&args[0])).map_err(bad)?;
        let buffers = crate::view::field_buffers(&p.lin.field_data());
        let t = p.traversal.clone();
        let uniforms = crate::view::program::uniforms(&t, &p.settings).map_err(|e| bad(super::error::render_error(e)))?;
        Ok(json!({
            "buffers": buffers,
            "features": p.lin.features,
            "view": view_json(&p.settings),
            "options": options_json(&t, &r.color),
            "uniforms": uniforms,
            "warnings": frame_warnings(&t),
            "layout_ms": t0.elapsed().as_secs_f64() * 1e3,
        }))
    }

    /// A full-size PNG or EXR of the request through the render path.
    fn render(&self, body: &Value) -> Result<Reply, ApiError> {
        let (args, r) = self.args(body)?;
        let exr = match body.get("format").and_then(Value::as_str) {
            Some("png") | None => false,
            Some("exr") => true,
            Some(other) => return Err(ApiError::bad(format!("unknown format '{}': png or exr", printable(other)))),
        };
        let mut guard = self.gpu.lock().unwrap_or_else(|e| e.into_inner());
        if guard.is_none() {
            *guard = Some(super::args::open_gpu(None).map_err(bad)?);
        }
        let gpu = guard.as_ref().expect("opened above");
        let mut frame = if is_scene(&args[0]) {
            let scene = self.scene(body)?;
            let p = super::scene_render::plan(&r, &scene, std::path::Path::new(&args[0])).map_err(bad)?;
            let data = p.lin.field_data();
            let renderer = crate::gpu::Renderer::new(gpu, &data, p.traversal).map_err(view_render_error)?;
            let mut f = renderer.render(&p.settings).map_err(view_render_error)?;
            crate::output::recolor(&mut f, p.color);
            f
        } else {
            let p = super::render::plan(&r).map_err(bad)?;
            let renderer = crate::gpu::Renderer::new(gpu, &p.loaded.formula.ir, p.traversal).map_err(view_render_error)?;
            let mut f = renderer.render(&p.settings).map_err(view_render_error)?;
            crate::output::recolor(&mut f, p.color);
            f
        };
        let bytes = encode(&mut frame, exr).map_err(ApiError::bad)?;
        let (content_type, name) = if exr { ("image/x-exr", "isotrace-view.exr") } else { ("image/png", "isotrace-view.png") };
        Ok(Reply::File { data: bytes, content_type, name: name.into() })
    }
}

/// The frame as PNG or EXR bytes, written as `render -o` writes them.
fn encode(frame: &mut crate::render::Frame, exr: bool) -> Result<Vec<u8>, String> {
    if !exr {
        let rgb = crate::output::try_frame_rgb8(frame).map_err(|e| e.to_string())?;
        let mut out = Vec::new();
        crate::output::encode_png(&mut out, frame.width, frame.height, &rgb)?;
        return Ok(out);
    }
    // The EXR writer writes a file: a private one in the temporary folder.
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let path = std::env::temp_dir().join(format!("isotrace-view-{}-{n}.exr", std::process::id()));
    let result = crate::output::write_exr(&path, frame).map_err(|e| e.to_string()).and_then(|_| std::fs::read(&path).map_err(|e| e.to_string()));
    let _ = std::fs::remove_file(&path);
    result
}

/// The value the viewer gives a parameter that nothing else does: the
/// CLI's advice (`--param NAME=1.0`); the page shows it with a slider.
const NEW_PARAM_VALUE: f64 = 1.0;

/// Gives each parameter of the formula that neither its header nor a
/// `--param` sets [`NEW_PARAM_VALUE`], as a `--param` of the request (so
/// the page's CLI line gives it too); their names.
fn default_params(loaded: &super::input::Loaded, r: &mut RenderArgs, args: &mut Vec<String>) -> Result<Vec<String>, ApiError> {
    let given = super::args::parse_params(&r.settings.params).map_err(bad)?;
    let header = loaded.header.as_ref().map(|h| h.view().params).unwrap_or_default();
    let set = |name: &str| given.iter().chain(&header).any(|(n, _)| n == name);
    let missing: Vec<String> = loaded.formula.ir.params.iter().map(|(n, _)| n.clone()).filter(|n| !set(n)).collect();
    for name in &missing {
        let p = format!("{name}={NEW_PARAM_VALUE}");
        r.settings.params.push(p.clone());
        args.extend(["--param".to_string(), p]);
    }
    Ok(missing)
}

/// The CLI's warnings about a frame, as templates the page fills from the
/// statistics of its own frames (`{violations}`, `{lipschitz}`, `{seen}`).
fn frame_warnings(t: &Traversal) -> Value {
    match t {
        Traversal::Sphere(_) => json!({ "lipschitz": super::report::lipschitz_warning(&"{violations}", &"{lipschitz}", &"{seen}") }),
        Traversal::Bisect(_) => json!({}),
    }
}

fn merge(a: &mut Value, b: Value) {
    if let (Value::Object(a), Value::Object(b)) = (a, b) {
        a.extend(b);
    }
}

fn view_json(s: &Settings) -> Value {
    let v3 = |v: glam::DVec3| [v.x, v.y, v.z];
    let c = &s.camera;
    json!({
        "width": s.width, "height": s.height, "box": s.bbox, "eye": v3(c.eye), "target": v3(c.target), "up": v3(c.up), "fov": c.fov_deg,
        "eps": s.eps, "time": s.time, "max_iter": s.max_iter, "clip": s.clip_sphere.unwrap_or(0.0),
    })
}

fn options_json(t: &Traversal, color: &str) -> Value {
    match t {
        Traversal::Bisect(b) => {
            let m = &b.modalities;
            json!({
                "method": "bisect", "algebra": super::args::algebra_name(b.algebra), "color": color, "shadows": m.shadows, "layers": m.layers, "opacity": m.opacity,
                "iso": m.isovalues, "reflect": m.reflect, "reflectivity": m.reflectivity,
            })
        }
        Traversal::Sphere(o) => json!({
            "method": "sphere", "color": color, "shadows": o.shadows, "glass": o.glass, "omega": o.omega, "lipschitz": o.lipschitz,
            "max_steps": o.max_steps, "fixpoint": o.fixpoint,
        }),
    }
}

impl Api for Backend {
    fn call(&self, route: Route, body: &Value) -> Result<Reply, ApiError> {
        match route {
            Route::Start => {
                let mut state = self.program(&json!({ "args": [self.input] }))?;
                merge(&mut state, json!({ "server": true, "present": present()? }));
                Ok(Reply::Json(state))
            }
            Route::Program => self.program(body).map(Reply::Json),
            Route::Scene => self.scene_edit(body).map(Reply::Json),
            Route::Render => self.render(body),
        }
    }
}

fn present() -> Result<String, ApiError> {
    crate::view::present_shader().map_err(|e| ApiError { status: 500, message: e.to_string() })
}

fn is_loopback(host: &str) -> bool {
    host == "localhost" || host.parse::<std::net::IpAddr>().is_ok_and(|a| a.is_loopback())
}

pub fn run(a: ViewerArgs) -> Result<ExitCode, CliError> {
    let backend = Backend { input: a.input.clone(), gpu: Mutex::new(None), allow_scene_paths: a.allow_scene_paths };
    if a.input == "-" {
        return Err(CliError::Input("isotrace view reads no formula from stdin: give it as an argument, @name or a file".into()));
    }
    // A scene file the command line names is read as `render` reads it,
    // with its messages (which name the file).
    if is_scene(&a.input) {
        super::scene::load(std::path::Path::new(&a.input), a.allow_scene_paths)?;
    }
    // The first state is computed before anything is served or written:
    // a bad formula is the CLI's error, with its exit code.
    let start = backend.call(Route::Start, &Value::Null).map_err(|e| CliError::Rendered(e.message))?;
    let Reply::Json(mut start) = start else { unreachable!("start answers JSON") };
    if let Some(path) = &a.export {
        merge(&mut start, json!({ "server": false }));
        let page = crate::view::page::export(&start).map_err(|e| CliError::Internal(e.to_string()))?;
        super::input::write_atomic(path, page.as_bytes()).map_err(CliError::Input)?;
        super::notice::wrote(path, "a page that needs no server: open it in a browser with WebGPU");
        return Ok(ExitCode::SUCCESS);
    }
    if !is_loopback(&a.host) {
        eprintln!(
            "warning: --host {} makes the viewer reachable from other machines over plain HTTP: anyone who sees its URL (with the token) can use it",
            printable(&a.host)
        );
    }
    let server = crate::view::Server::bind(&a.host, a.port).map_err(|e| CliError::Input(e.to_string()))?;
    let url = server.url().to_string();
    println!("isotrace view: {url}");
    use std::io::Write;
    let _ = std::io::stdout().flush();
    if a.open {
        if let Err(e) = std::process::Command::new("xdg-open").arg(&url).spawn() {
            eprintln!("note: could not open a browser ({e}); open {url}");
        }
    }
    server.run(&backend);
    Ok(ExitCode::SUCCESS)
}
