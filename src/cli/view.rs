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
use isotrace::field::FieldSource;
use isotrace::render::{Settings, Traversal};
use isotrace::view::{Api, ApiError, Reply, Route};
use serde_json::{json, Value};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Mutex;

/// `isotrace view` flags.
#[derive(Args, Debug)]
pub struct ViewArgs {
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
}

/// The render flags a page may send. Anything else (files to read or
/// write, frames, batch flags) is refused: the server reads only the file
/// named on its command line.
const ALLOWED: &[&str] = &[
    "--size", "--box", "--eye", "--target", "--up", "--fov", "--eps", "--t", "--param", "--algebra", "--max-iter", "--clip", "--debug-unresolved", "--unresolved",
    "--method", "--lipschitz", "--omega", "--no-screen-space", "--no-dynamic-eps", "--eps-min", "--fixpoint", "--bound", "--no-bound", "--max-steps",
    "--min-step", "--shadows", "--glass", "--light", "--shadow-eps", "--opacity", "--layers", "--iso", "--reflect", "--reflectivity", "--color",
];

fn is_scene(s: &str) -> bool {
    s.ends_with(".scene.json")
}

/// The page's requests, answered for the input of the command line.
struct Backend {
    input: String,
    gpu: Mutex<Option<isotrace::gpu::Gpu>>,
}

fn bad(e: CliError) -> ApiError {
    ApiError::bad(e.text(false))
}

impl Backend {
    /// The body's `args` checked and parsed as `isotrace render` flags.
    fn args(&self, body: &Value) -> Result<(Vec<String>, RenderArgs), ApiError> {
        let list = body.get("args").and_then(Value::as_array).ok_or_else(|| ApiError::bad("the request needs \"args\": the render command's arguments"))?;
        let args: Vec<String> = list.iter().map(|v| v.as_str().map(str::to_string)).collect::<Option<_>>().ok_or_else(|| ApiError::bad("\"args\" must be strings"))?;
        let Some(first) = args.first() else { return Err(ApiError::bad("\"args\" is empty: the first one is the formula")) };
        let file_like = first == "-" || first.ends_with(".iso") || is_scene(first);
        if file_like && *first != self.input {
            return Err(ApiError::bad(format!("the viewer reads only the file named on its command line ('{}'), not '{}'", self.input, isotrace::view::page::printable(first))));
        }
        for a in &args[1..] {
            let name = a.split('=').next().unwrap_or("");
            let flag_like = a.starts_with("--") || (a.starts_with('-') && a[1..].starts_with(|c: char| c.is_ascii_alphabetic()));
            if flag_like && !ALLOWED.contains(&name) {
                return Err(ApiError::bad(format!("{} is not available in the viewer", isotrace::view::page::printable(name))));
            }
        }
        let argv = ["isotrace", "render"].into_iter().map(String::from).chain(args.iter().cloned()).chain(["-o".into(), "view.png".into()]);
        let cli = <super::Cli as clap::Parser>::try_parse_from(argv).map_err(|e| ApiError::bad(e.to_string()))?;
        let super::Command::Render(r) = cli.command else { return Err(ApiError::bad("not a render command")) };
        if r.formula.file.is_some() || r.formula.inline.is_some() {
            return Err(ApiError::bad("-f and --inline are not available in the viewer"));
        }
        Ok((args, r))
    }

    /// The scene of a request: the edited one in the body, else the file.
    fn scene(&self, body: &Value) -> Result<isotrace::scene::Scene, ApiError> {
        match body.get("scene") {
            // Grid files are found next to the scene file, as when it is loaded.
            Some(v) if !v.is_null() => {
                let base = std::path::Path::new(&self.input).parent().unwrap_or(std::path::Path::new(""));
                isotrace::scene::format::parse_in(&v.to_string(), base).map_err(|e| ApiError::bad(format!("the edited scene: {e}")))
            }
            _ => isotrace::scene::format::load(std::path::Path::new(&self.input)).map_err(|e| ApiError::bad(e.to_string())),
        }
    }

    /// Compiles the request's render into the page's state.
    fn program(&self, body: &Value) -> Result<Value, ApiError> {
        let (args, r) = self.args(body)?;
        let t0 = std::time::Instant::now();
        let first = &args[0];
        let (program, settings, traversal, color, extra) = if is_scene(first) {
            let scene = self.scene(body)?;
            let p = super::scene_render::plan(&r, &scene, std::path::Path::new(first)).map_err(bad)?;
            let data = p.lin.field_data();
            let t = Traversal::Sphere(p.options.clone());
            let program = isotrace::view::program(FieldSource::Scene(&data), &t, &p.settings).map_err(|e| bad(super::render_error(e)))?;
            let scene_json: Value = serde_json::from_str(&isotrace::scene::format::to_json(&scene)).unwrap_or(Value::Null);
            (program, p.settings, t, r.color.clone(), json!({ "scene": scene_json, "params": [], "scene_features": data.features }))
        } else {
            let p = super::render::plan(&r).map_err(bad)?;
            let program = isotrace::view::program(FieldSource::Compiled(&p.loaded.formula.ir), &p.traversal, &p.settings).map_err(|e| bad(super::render_error(e)))?;
            let names = p.loaded.formula.ir.params.iter().map(|(n, _)| n.clone());
            let params: Vec<Value> = names.zip(&p.settings.params).map(|(n, v)| json!({ "name": n, "value": v })).collect();
            let f = &p.loaded.formula;
            (program, p.settings, p.traversal, p.color_text, json!({ "formula": f.source, "origin": f.origin, "params": params, "scene": null }))
        };
        let mut state = json!({
            "args": args,
            "input": self.input,
            "program": program,
            "view": view_json(&settings),
            "options": options_json(&traversal, &color),
            "compile_ms": t0.elapsed().as_secs_f64() * 1e3,
        });
        merge(&mut state, extra);
        Ok(state)
    }

    /// An edited scene laid out: its buffers, no shader.
    fn scene_edit(&self, body: &Value) -> Result<Value, ApiError> {
        let (args, r) = self.args(body)?;
        if !is_scene(&args[0]) {
            return Err(ApiError::bad("this view is not of a scene"));
        }
        let t0 = std::time::Instant::now();
        let scene = self.scene(body)?;
        let p = super::scene_render::plan(&r, &scene, std::path::Path::new(&args[0])).map_err(bad)?;
        let buffers = isotrace::view::scene_buffers(&p.lin.field_data());
        Ok(json!({ "buffers": buffers, "features": p.lin.features, "layout_ms": t0.elapsed().as_secs_f64() * 1e3 }))
    }

    /// A full-size PNG or EXR of the request through the render path.
    fn render(&self, body: &Value) -> Result<Reply, ApiError> {
        let (args, r) = self.args(body)?;
        let exr = match body.get("format").and_then(Value::as_str) {
            Some("png") | None => false,
            Some("exr") => true,
            Some(other) => return Err(ApiError::bad(format!("unknown format '{}': png or exr", isotrace::view::page::printable(other)))),
        };
        let mut guard = self.gpu.lock().unwrap_or_else(|e| e.into_inner());
        if guard.is_none() {
            *guard = Some(super::render::open_gpu(None).map_err(bad)?);
        }
        let gpu = guard.as_ref().expect("opened above");
        let mut frame = if is_scene(&args[0]) {
            let scene = self.scene(body)?;
            let p = super::scene_render::plan(&r, &scene, std::path::Path::new(&args[0])).map_err(bad)?;
            let data = p.lin.field_data();
            let renderer = isotrace::gpu::Renderer::new(gpu, FieldSource::Scene(&data), Traversal::Sphere(p.options)).map_err(|e| bad(super::render_error(e)))?;
            let mut f = renderer.render(&p.settings).map_err(|e| bad(super::render_error(e)))?;
            isotrace::output::recolor(&mut f, p.color);
            f
        } else {
            let p = super::render::plan(&r).map_err(bad)?;
            let renderer = isotrace::gpu::Renderer::new(gpu, FieldSource::Compiled(&p.loaded.formula.ir), p.traversal).map_err(|e| bad(super::render_error(e)))?;
            let mut f = renderer.render(&p.settings).map_err(|e| bad(super::render_error(e)))?;
            isotrace::output::recolor(&mut f, p.color);
            f
        };
        let bytes = encode(&mut frame, exr).map_err(ApiError::bad)?;
        let (content_type, name) = if exr { ("image/x-exr", "isotrace-view.exr") } else { ("image/png", "isotrace-view.png") };
        Ok(Reply::File { data: bytes, content_type, name: name.into() })
    }
}

/// The frame as PNG or EXR bytes, written as `render -o` writes them.
fn encode(frame: &mut isotrace::render::Frame, exr: bool) -> Result<Vec<u8>, String> {
    if !exr {
        let rgb = isotrace::output::try_frame_rgb8(frame).map_err(|e| e.to_string())?;
        let mut out = Vec::new();
        isotrace::output::encode_png(&mut out, frame.width, frame.height, &rgb)?;
        return Ok(out);
    }
    // The EXR writer writes a file: a private one in the temporary folder.
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let path = std::env::temp_dir().join(format!("isotrace-view-{}-{n}.exr", std::process::id()));
    let result = isotrace::output::write_exr(&path, frame).map_err(|e| e.to_string()).and_then(|_| std::fs::read(&path).map_err(|e| e.to_string()));
    let _ = std::fs::remove_file(&path);
    result
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
                "method": "bisect", "algebra": super::domain_name(b.algebra), "color": color, "shadows": m.shadows, "layers": m.layers, "opacity": m.opacity,
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
    isotrace::view::present_shader().map_err(|e| ApiError { status: 500, message: e.to_string() })
}

fn is_loopback(host: &str) -> bool {
    host == "localhost" || host.parse::<std::net::IpAddr>().is_ok_and(|a| a.is_loopback())
}

pub fn run(a: ViewArgs) -> Result<ExitCode, CliError> {
    let backend = Backend { input: a.input.clone(), gpu: Mutex::new(None) };
    if a.input == "-" {
        return Err(CliError::Input("isotrace view reads no formula from stdin: give it as an argument, @name or a file".into()));
    }
    // The first state is computed before anything is served or written:
    // a bad formula is the CLI's error, with its exit code.
    let start = backend.call(Route::Start, &Value::Null).map_err(|e| CliError::Rendered(e.message))?;
    let Reply::Json(mut start) = start else { unreachable!("start answers JSON") };
    if let Some(path) = &a.export {
        merge(&mut start, json!({ "server": false }));
        let page = isotrace::view::page::export(&start).map_err(|e| CliError::Internal(e.to_string()))?;
        super::input::write_atomic(path, page.as_bytes()).map_err(CliError::Input)?;
        eprintln!("wrote {} (a static page: serve it over http(s), e.g. python3 -m http.server; WebGPU needs a secure context)", path.display());
        return Ok(ExitCode::SUCCESS);
    }
    if !is_loopback(&a.host) {
        eprintln!("warning: --host {} makes the viewer reachable from other machines; it has no authentication", a.host);
    }
    let server = isotrace::view::Server::bind(&a.host, a.port).map_err(|e| CliError::Input(e.to_string()))?;
    let url = server.url();
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
