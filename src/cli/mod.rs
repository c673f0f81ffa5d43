//! Subcommands and their arguments (clap), and the one place errors are
//! rendered for the terminal.

mod animate;
mod batch;
mod bench;
mod bench_scenes;
mod eval;
mod frames;
mod input;
mod modality;
mod notice;
mod render;
mod report;
mod scene;
mod scene_render;
mod shell;
mod view;
mod wgsl;
pub mod signals;

use clap::{Args, Parser, Subcommand, ValueEnum};
use isotrace::ir::Domain;
use isotrace::{Formula, FormulaError, validate};
use std::io::{IsTerminal, Write};
use std::process::ExitCode;

pub use input::FormulaArgs;

const ABOUT: &str = "Robust ray tracing of implicit surfaces f(x,y,z) = 0 on the GPU.\n\
Formulas compile to WGSL interval / reduced-affine evaluators, validated by naga and run with wgpu.";

#[derive(Parser, Debug)]
#[command(name = "isotrace", version, about = ABOUT, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Print nothing on success (warnings and errors still print).
    #[arg(long, short = 'q', global = true)]
    quiet: bool,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Parse and analyse a formula: normalised form, variables, parameters, degree.
    #[command(after_help = "Examples:\n  isotrace check 'x^2 + y^2 + z^2 - 1'\n  isotrace check -f surface.iso\n  echo 'p = 2; x^p - y' | isotrace check -\n  isotrace check @tangle --json")]
    Check(CheckArgs),
    /// Print the complete generated WGSL shader (validated with naga).
    #[command(after_help = "Examples:\n  isotrace wgsl 'x^2 + y^2 + z^2 - 1' --algebra raa\n  isotrace wgsl 'sin(x) - z' --kernel eval --algebra ia -o eval.wgsl")]
    Wgsl(wgsl::WgslArgs),
    /// Ray trace the surface f = 0 into a PNG or EXR image.
    #[command(after_help = "Examples:\n  isotrace render 'x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8' --box=-3,3 -o tangle.png\n  isotrace render 'x^2 + y^2 + z^2 - r^2' --param r=1.2 --size 800x600 -o sphere.exr --stats\n  isotrace render 'z - 0.1*sin(4*x + t)' --box=-4,4,-4,4,-1,1 --frames 30 --t0 0 --t1 6.28 -o frames/f_%04d.png\n  isotrace render @water --frames 960 -o frames/f_%04d.png --shard auto --skip-existing    # one task of a Slurm array")]
    Render(render::RenderArgs),
    /// Evaluate the generated scalar / interval / affine evaluator on boxes, on the device.
    #[command(after_help = "Boxes are read one per line: x0 x1 y0 y1 z0 z1 [t0 t1]; with --algebra scalar a line is a point x y z [t].\nOutput: one line per box, 'lo hi' or 'empty' (scalar: the value).\n\nExamples:\n  echo '-1 1 -1 1 -1 1' | isotrace eval 'x^2 + y^2 + z^2 - 1' --algebra ia\n  isotrace eval 'sqrt(x) - y' --algebra raa --boxes boxes.txt --cpu\n  echo '0.5 0 0' | isotrace eval 'x^2 - a' --algebra scalar --param a=2")]
    Eval(eval::EvalArgs),
    /// List the named surfaces of the catalog (render one with @name).
    #[command(after_help = "Examples:\n  isotrace list\n  isotrace list --long\n  isotrace render @tangle -o tangle.png")]
    List(ListArgs),
    /// Benchmark surfaces × algebras: Knoll-style table, JSON, Markdown, images, contact sheet.
    #[command(after_help = "Examples:\n  isotrace bench --suite knoll --out bench-out --json bench.json --markdown bench.md\n  isotrace bench tangle barth-sextic --algebra ia,raa --size 512 --repeat 3\n  isotrace bench --suite all --shard 0/4 --json part0.json    # spread over 4 machines\n  isotrace bench --merge part*.json --json all.json --markdown all.md\n  isotrace bench sphere --find-eps")]
    Bench(bench::BenchArgs),
    /// Batch work: summarise the manifests `render --frames` writes next to the frames of each shard.
    #[command(after_help = "Examples:\n  isotrace manifest merge frames/f_.shard-*-of-16.manifest.json\n  isotrace manifest merge 'frames/*.manifest.json' --json summary.json")]
    Manifest(batch::ManifestArgs),
    /// Blobtree scenes (.scene.json): generate the paper's synthetic scenes, validate a file.
    #[command(after_help = "Examples:\n  isotrace scene gen aggregate --level 2 --smooth -o aggregate-2.scene.json\n  isotrace scene check aggregate-2.scene.json --probe 1000")]
    Scene(scene::SceneArgs),
    /// Serve an interactive WebGPU page of a formula or a scene (the same WGSL kernels as render).
    #[command(after_help = "Examples:\n  isotrace view @sphere\n  isotrace view examples/blobs.scene.json --port 8080 --open\n  isotrace view 'x^2 + y^2 + z^2 - r^2' --export sphere.html    # a static page, no server")]
    View(view::ViewerArgs),
    /// Print a shell completion script to stdout.
    #[command(after_help = "Examples:\n  isotrace completions bash > ~/.local/share/bash-completion/completions/isotrace\n  isotrace completions zsh > \"${fpath[1]}/_isotrace\"\n  isotrace completions fish > ~/.config/fish/completions/isotrace.fish")]
    Completions(shell::CompletionsArgs),
    /// Print the man page (roff) to stdout, or write it with -o.
    #[command(after_help = "Examples:\n  isotrace man | man -l -\n  isotrace man -o isotrace.1\n  isotrace man render -o isotrace-render.1")]
    Man(shell::ManArgs),
}

#[derive(Args, Debug)]
struct ListArgs {
    /// Also show box, degree, status and source.
    #[arg(long)]
    long: bool,
}

#[derive(Args, Debug)]
struct CheckArgs {
    #[command(flatten)]
    formula: FormulaArgs,
    /// Print the analysis as one JSON object on stdout.
    #[arg(long)]
    json: bool,
}

/// Number domain of the generated evaluator.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum AlgebraArg {
    /// Plain f32 values (points).
    Scalar,
    /// Interval arithmetic.
    Ia,
    /// Reduced affine arithmetic (AF1).
    Raa,
    /// IA or RAA, chosen per formula.
    Auto,
}

/// `--field`: the field source.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum FieldArg {
    /// The formula generated into the shader.
    Compiled,
    /// The formula as a tape run by a fixed interpreter.
    Tape,
    /// A formula of distance forms lowered to its blobtree scene (sphere tracing).
    Scene,
    /// Chosen by formula size, algebra and method.
    Auto,
}

/// The flag value of a field kind (a header's `field`).
pub(crate) fn field_arg(k: isotrace::field::FieldKind) -> FieldArg {
    match k {
        isotrace::field::FieldKind::Compiled => FieldArg::Compiled,
        isotrace::field::FieldKind::Tape => FieldArg::Tape,
        isotrace::field::FieldKind::Scene => FieldArg::Scene,
        isotrace::field::FieldKind::Auto => FieldArg::Auto,
    }
}

/// The field kind of a flag value.
pub(crate) fn field_kind(a: FieldArg) -> isotrace::field::FieldKind {
    match a {
        FieldArg::Compiled => isotrace::field::FieldKind::Compiled,
        FieldArg::Tape => isotrace::field::FieldKind::Tape,
        FieldArg::Scene => isotrace::field::FieldKind::Scene,
        FieldArg::Auto => isotrace::field::FieldKind::Auto,
    }
}

/// The field source of `--field` (default auto) for formula `f` with
/// parameter values `params`, traced by `t`. A scene needs the Lipschitz
/// bound of its operators: unless `--lipschitz` was given, sphere tracing
/// takes at least that.
/// `frames`: how many frames the job renders with the field (auto weighs
/// the tape's sooner first frame against its slower later ones).
pub fn prepare_field(arg: Option<FieldArg>, f: &isotrace::Formula, params: &[f32], t: &mut isotrace::render::Traversal, lipschitz_given: bool, frames: u64) -> Result<isotrace::choice::PreparedField, CliError> {
    use isotrace::choice::{self, FieldError, SceneFieldError};
    use isotrace::field::{FieldKind, TapeError};
    let kind = field_kind(arg.unwrap_or(FieldArg::Auto));
    if kind == FieldKind::Auto {
        if let Some((field, lipschitz)) = choice::auto_scene(f, params, t) {
            if let (isotrace::render::Traversal::Sphere(o), false) = (t, lipschitz_given) {
                o.lipschitz = o.lipschitz.max(lipschitz);
            }
            return Ok(field);
        }
    }
    if kind == FieldKind::Scene {
        let (field, lipschitz) = choice::scene(f, params, t).map_err(|e| match e {
            SceneFieldError::NotBlobtree(n) => {
                let d = isotrace::diag::Diagnostic::error(format!("--field scene: not a blobtree: {}", n.reason), n.span, "here")
                    .with_note("a scene is built from distance forms (sphere, box, translate, union, smooth_union, ...) with constant arguments; render it with --field compiled (or auto)");
                CliError::Rendered(d.render(&f.origin, &f.source, false))
            }
            SceneFieldError::NotSphere => CliError::Input(format!("--field scene: {e}; add --method sphere")),
            SceneFieldError::Layout(_) => CliError::Input(format!("--field scene: in the scene the formula lowers to (`isotrace scene lower` writes it), {e}")),
        })?;
        if let (isotrace::render::Traversal::Sphere(o), false) = (t, lipschitz_given) {
            o.lipschitz = o.lipschitz.max(lipschitz);
        }
        return Ok(field);
    }
    choice::choose_for(kind, f, params, t, frames).map_err(|e| {
        let fix = match &e {
            FieldError::Tape(TapeError::UserFunction(_) | TapeError::Hooks) => "the functions and hooks of --inline need --field compiled (or auto)",
            _ => "render it with --field compiled (or auto)",
        };
        CliError::Input(format!("--field {}: {e}; {fix}", if kind == FieldKind::Tape { "tape" } else { "auto" }))
    })
}

/// Any failure of a command, rendered once.
#[derive(Debug)]
pub enum CliError {
    /// A formula diagnostic.
    Formula(FormulaError),
    /// Bad input that is not in a formula (a flag, a file).
    Input(String),
    /// An isotrace bug (naga rejected generated code, …).
    Internal(String),
    /// No usable GPU device (exit code 2).
    NoDevice(String),
    /// Bad input with a diagnostic already rendered (exit code 1).
    Rendered(String),
}

impl CliError {
    /// The text for stderr. Messages quote user text (file names, header
    /// values, box lines), so control characters in them are made visible
    /// ([`isotrace::diag::escape_controls`]): no input reaches the terminal raw.
    pub fn render(&self) -> String {
        self.text(std::io::stderr().is_terminal())
    }

    /// The message, with terminal colours or without (for the viewer's page).
    pub fn text(&self, color: bool) -> String {
        use isotrace::diag::escape_controls as esc;
        match self {
            CliError::Formula(e) => e.diagnostic.render(&e.origin, &e.text, color),
            CliError::Input(m) if color => format!("\x1b[1;31merror\x1b[0m: {}\n", esc(m)),
            CliError::Input(m) => format!("error: {}\n", esc(m)),
            CliError::Internal(m) => format!("{}\n", esc(m)),
            CliError::NoDevice(m) => format!("error: {}\n", esc(m)),
            CliError::Rendered(m) => esc(m).into_owned(),
        }
    }
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Formula(_) | CliError::Input(_) | CliError::Rendered(_) => 1,
            CliError::Internal(_) => 3,
            CliError::NoDevice(_) => 2,
        }
    }
}

impl From<FormulaError> for CliError {
    fn from(e: FormulaError) -> Self {
        CliError::Formula(e)
    }
}
impl From<validate::ValidateError> for CliError {
    fn from(e: validate::ValidateError) -> Self {
        CliError::Internal(e.to_string())
    }
}

/// Runs one command.
pub fn run(cli: Cli) -> Result<ExitCode, CliError> {
    notice::begin(cli.quiet);
    memory_budget_from_env()?;
    match cli.command {
        Command::Check(a) => check(a),
        Command::Wgsl(a) => wgsl::run(a),
        Command::Render(a) => render::run(a),
        Command::Eval(a) => eval::run(a),
        Command::List(a) => list(a),
        Command::Bench(a) => bench::run(a),
        Command::Manifest(a) => batch::run(a),
        Command::Scene(a) => scene::run(a),
        Command::View(a) => view::run(a),
        Command::Completions(a) => shell::completions(a),
        Command::Man(a) => shell::man(a),
    }
}

fn check(a: CheckArgs) -> Result<ExitCode, CliError> {
    if let Some(p) = a.formula.scene_path() {
        let p = p.display();
        return Err(CliError::Input(format!("'{p}' is a scene file, not a formula: check it with `isotrace scene check {p}`")));
    }
    let loaded = a.formula.load_with_header()?;
    let f = &loaded.formula;
    if let Some(user) = &loaded.inline {
        wgsl::check_inline(f, user)?;
    }
    let ir = &f.ir;
    let vars: Vec<&str> = ir.variables().iter().map(|v| v.name()).collect();
    let params: Vec<&str> = ir.params.iter().map(|(n, _)| n.as_str()).collect();
    let (products, powers) = ir.nonconstant_products();
    let algebra = domain_name(isotrace::choose_algebra(ir));
    // The runs of same-shaped terms the compiled field writes as loops.
    let plan = isotrace::field::compiled::term_loops::plan(ir);
    let looped: usize = plan.loops.iter().map(|l| l.unroll * l.iterations).sum();
    let mut out = std::io::stdout().lock();
    if a.json {
        let v = serde_json::json!({
            "formula": f.normalized(), "variables": vars, "parameters": params, "degree": ir.degree(),
            "operations": { "total": ir.live().len(), "products": products, "integer_powers": powers },
            "loops": { "runs": plan.loops.len(), "terms": looped, "written_nodes": plan.emitted_nodes(ir) },
            "algebra": algebra,
        });
        let _ = writeln!(out, "{v}");
        return Ok(ExitCode::SUCCESS);
    }
    let _ = writeln!(out, "formula:    {}", f.normalized());
    let _ = writeln!(out, "variables:  {}", if vars.is_empty() { "(none)".into() } else { vars.join(" ") });
    let _ = writeln!(out, "parameters: {}", if params.is_empty() { "(none)".into() } else { params.join(" ") });
    let degree = match ir.degree() {
        None => "not a polynomial".to_string(),
        Some(isotrace::ir::Ir::DEGREE_MAX) => format!("{} or more (too large to count)", isotrace::ir::Ir::DEGREE_MAX),
        Some(d) => d.to_string(),
    };
    let _ = writeln!(out, "degree:     {degree}");
    let _ = writeln!(out, "operations: {} ({} products of non-constant terms, {} integer powers)", ir.live().len(), products, powers);
    match plan.loops.len() {
        0 => {
            let _ = writeln!(out, "loops:      none");
        }
        n => {
            let runs = if n == 1 { "run" } else { "runs" };
            let _ = writeln!(out, "loops:      {n} {runs} of same-shaped terms compiled as loops ({looped} terms; {} nodes written out)", plan.emitted_nodes(ir));
        }
    }
    let _ = writeln!(out, "algebra:    {algebra} (auto)");
    Ok(ExitCode::SUCCESS)
}

fn domain_name(d: Domain) -> &'static str {
    match d {
        Domain::Scalar => "scalar",
        Domain::Interval => "ia",
        Domain::Affine => "raa",
    }
}

/// The domain an `--algebra` value stands for with this formula.
pub fn resolve_algebra(a: AlgebraArg, ir: &isotrace::ir::Ir) -> Domain {
    match a {
        AlgebraArg::Scalar => Domain::Scalar,
        AlgebraArg::Ia => Domain::Interval,
        AlgebraArg::Raa => Domain::Affine,
        AlgebraArg::Auto => isotrace::choose_algebra(ir),
    }
}

/// Maps a render error to the CLI's error kinds.
pub fn render_error(e: isotrace::gpu::RenderError) -> CliError {
    use isotrace::gpu::RenderError as R;
    match e {
        R::Validate(v) => CliError::Internal(v.to_string()),
        R::Gpu(g) => CliError::Internal(g.to_string()),
        R::Settings(s) => CliError::Input(settings_message(&s)),
        R::Inline(m) => CliError::Rendered(m),
        R::Memory(m) => CliError::Input(memory_message(&m.to_string(), &m)),
        e @ R::ShaderTooLarge { .. } => CliError::Input(format!(
            "{e}; render it with --field tape (or auto), which runs the formula from a buffer in a fixed interpreter, simplify the formula (a repeated subexpression written once as a definition 'name = ...;' is generated once), or split the surface into several renders"
        )),
    }
}

/// After how long a pipeline build is reported on stderr.
const COMPILE_NOTE_AFTER: std::time::Duration = std::time::Duration::from_secs(2);
/// After how long a frame still rendering is reported on stderr.
const RENDER_NOTE_AFTER: std::time::Duration = std::time::Duration::from_secs(5);

/// Runs `build` (naga, then the driver's shader compiler). When it takes
/// longer than [`COMPILE_NOTE_AFTER`] (or `ISOTRACE_COMPILE_NOTE_MS`, a
/// test hook), a note on stderr says what is happening, with the shader's
/// size from `wgsl_bytes`, so that a long compile does not look like a
/// hang.
pub fn with_compile_note<T>(wgsl_bytes: impl FnOnce() -> usize + Send, build: impl FnOnce() -> T) -> T {
    with_note("ISOTRACE_COMPILE_NOTE_MS", COMPILE_NOTE_AFTER, || format!("compiling the shader ({} KB of WGSL)", wgsl_bytes().div_ceil(1000)), build)
}

/// Runs `render` (one frame). When it takes longer than
/// [`RENDER_NOTE_AFTER`] (or `ISOTRACE_RENDER_NOTE_MS`, a test hook), a note
/// on stderr says what is rendering: a CPU device compiles the kernel at
/// its first dispatch, and a big formula's tape takes seconds to minutes a
/// frame there.
pub fn with_render_note<T>(what: impl FnOnce() -> String + Send, render: impl FnOnce() -> T) -> T {
    with_note("ISOTRACE_RENDER_NOTE_MS", RENDER_NOTE_AFTER, || format!("still rendering {}", what()), render)
}

/// Runs `work`; if it is not done after `after` (or the milliseconds in
/// the environment variable `hook`), prints `note: {note()} …` on stderr.
/// A delay of zero prints the note before `work` starts: a timer of zero
/// would race a quick `work` and make the hook's tests depend on speed.
fn with_note<T>(hook: &str, after: std::time::Duration, note: impl FnOnce() -> String + Send, work: impl FnOnce() -> T) -> T {
    let after = std::env::var(hook).ok().and_then(|v| v.parse().ok()).map_or(after, std::time::Duration::from_millis);
    if after.is_zero() {
        eprintln!("note: {} …", note());
        return work();
    }
    let (done, wait) = std::sync::mpsc::channel::<()>();
    std::thread::scope(|scope| {
        scope.spawn(move || {
            if let Err(std::sync::mpsc::RecvTimeoutError::Timeout) = wait.recv_timeout(after) {
                eprintln!("note: {} …", note());
            }
        });
        let out = work();
        drop(done);
        out
    })
}

/// `ISOTRACE_MEMORY_BUDGET`: the largest frame-sized host allocation
/// (pixels, packed records, encoded image), in bytes or with a k/M/G/T
/// suffix. Unset: only the allocator refuses.
fn memory_budget_from_env() -> Result<(), CliError> {
    let Some(v) = std::env::var_os("ISOTRACE_MEMORY_BUDGET") else { return Ok(()) };
    let v = v.to_string_lossy();
    let bytes = isotrace::memory::parse_budget(&v)
        .ok_or_else(|| CliError::Input(format!("invalid ISOTRACE_MEMORY_BUDGET '{v}': expected a number of bytes, optionally with a suffix k, M, G or T (e.g. 8G)")))?;
    isotrace::memory::set_budget(Some(bytes));
    Ok(())
}

/// An output file's error; a refused allocation says what to do.
pub fn output_error(e: isotrace::output::OutputError) -> CliError {
    match &e {
        isotrace::output::OutputError::Memory { source, .. } => CliError::Input(memory_message(&e.to_string(), source)),
        _ => CliError::Input(e.to_string()),
    }
}

/// `message` about a refused frame allocation, with what the user can do.
fn memory_message(message: &str, m: &isotrace::memory::MemoryError) -> String {
    match m.budget {
        Some(_) => format!("{message}; render a smaller --size, or raise ISOTRACE_MEMORY_BUDGET"),
        None => format!("{message}; render a smaller --size"),
    }
}

/// The flag a setting is given with on the command line.
fn flag(field: isotrace::render::SettingsField) -> &'static str {
    use isotrace::render::SettingsField as F;
    match field {
        F::Size => "--size",
        F::Box => "--box",
        F::Eye => "--eye",
        F::Target => "--target",
        F::Up => "--up",
        F::Fov => "--fov",
        F::Eps => "--eps",
        F::Time => "--t",
        F::Params => "--param",
        F::Clip => "--clip",
        F::MaxIter => "--max-iter",
        F::Isovalues => "--iso",
        F::Layers => "--layers",
        F::Opacity => "--opacity",
        F::Reflect => "--reflect",
        F::Reflectivity => "--reflectivity",
        F::Lipschitz => "--lipschitz",
        F::Omega => "--omega",
        F::MaxSteps => "--max-steps",
        F::Fixpoint => "--fixpoint",
        F::MinStep => "--min-step",
        F::EpsMin => "--eps-min",
        F::Features => "--method",
    }
}

/// A settings error in the words of the command line: the flag that sets
/// the value (flags and `.iso` header keys share their names).
pub fn settings_message(e: &isotrace::render::SettingsError) -> String {
    use isotrace::render::SettingsField as F;
    match (e.field, e.value.is_empty()) {
        (F::Up, true) => format!("{}: give another --up", e.reason),
        (F::Eye, true) => format!("{}: give another --eye or --target", e.reason),
        (_, true) => format!("invalid {}: {}", flag(e.field), e.reason),
        (_, false) => format!("invalid {} {}: {}", flag(e.field), e.value, e.reason),
    }
}

/// A progress bar on a terminal; `None` (plain lines elsewhere) otherwise.
pub fn progress(len: u64, what: &str) -> Option<indicatif::ProgressBar> {
    if len <= 1 || !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = indicatif::ProgressBar::new(len);
    if let Ok(style) = indicatif::ProgressStyle::with_template(&format!("{{bar:40}} {{pos}}/{{len}} {what} {{elapsed}}")) {
        bar.set_style(style);
    }
    Some(bar)
}

fn list(a: ListArgs) -> Result<ExitCode, CliError> {
    let mut out = std::io::stdout().lock();
    for e in isotrace::catalog::builtin() {
        let h = &e.header;
        let title = h.title.clone().unwrap_or_default();
        if a.long {
            let b = h.bbox;
            let status = match h.status {
                Some(isotrace::catalog::Status::Published) => "published",
                Some(isotrace::catalog::Status::Reconstruction) => "reconstruction",
                None => "-",
            };
            let _ = writeln!(out, "{:<16} {title}", e.name);
            let _ = writeln!(out, "    box [{},{}]x[{},{}]x[{},{}]  degree {}  {status}", b[0], b[1], b[2], b[3], b[4], b[5], h.degree.as_deref().unwrap_or("-"));
            if let Some(src) = &h.source {
                let _ = writeln!(out, "    source: {src}");
            }
        } else {
            let _ = writeln!(out, "{:<16} {title}", e.name);
        }
    }
    Ok(ExitCode::SUCCESS)
}
