//! Subcommands and their arguments (clap), and the commands too small for
//! a file of their own (`check`, `list`). Flags shared by commands become
//! typed settings in [`args`]; errors have their one home in [`error`].

mod animate;
mod args;
mod batch;
mod bench;
mod bench_scenes;
mod error;
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

use clap::{Args, Parser, Subcommand};
use std::io::Write;
use std::process::ExitCode;

pub use error::CliError;
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

/// The command line: parses the arguments, runs the command, renders any
/// error once and maps it to an exit code (1: bad input, 2: no usable GPU
/// device, 3: internal error).
pub fn main() -> ExitCode {
    // Usage errors exit with 1 like every other bad input (clap's default
    // is 2, which isotrace keeps for "no GPU device").
    let args = match Cli::try_parse() {
        Ok(a) => a,
        Err(e) => {
            // clap quotes the arguments it rejects, and on a terminal it
            // passes escape sequences in them through. With a control
            // character in any argument the message is printed plain
            // (clap strips the sequences) with the rest made visible.
            let control = std::env::args_os().any(|a| a.to_string_lossy().chars().any(|c| c.is_control() && c != '\t'));
            if control && e.use_stderr() {
                eprint!("{}", crate::diag::escape_controls(&e.render().to_string()));
            } else {
                let _ = e.print();
            }
            return ExitCode::from(if e.use_stderr() { 1 } else { 0 });
        }
    };
    signals::remove_temporaries_on_termination();
    match run(args) {
        Ok(code) => code,
        Err(e) => {
            eprint!("{}", e.render());
            ExitCode::from(e.exit_code())
        }
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
    let algebra = args::algebra_name(crate::choose_algebra(ir));
    // The runs of same-shaped terms and the polynomials the compiled field writes as loops.
    let (gathered, plan) = crate::field::compiled::term_loops::written_plan(ir);
    let code = gathered.as_ref().unwrap_or(ir);
    let looped: usize = plan.loops.iter().map(|l| l.unroll * l.iterations).sum();
    let mut out = std::io::stdout().lock();
    if a.json {
        let v = serde_json::json!({
            "formula": f.normalized(), "variables": vars, "parameters": params, "degree": ir.degree(),
            "operations": { "total": ir.live().len(), "products": products, "integer_powers": powers },
            "loops": { "runs": plan.loops.len(), "terms": looped, "written_nodes": plan.emitted_nodes(code), "polynomials": plan.horners.iter().map(|h| h.monomials).collect::<Vec<_>>() },
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
        Some(crate::ir::Ir::DEGREE_MAX) => format!("{} or more (too large to count)", crate::ir::Ir::DEGREE_MAX),
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
            let _ = writeln!(out, "loops:      {n} {runs} of same-shaped terms compiled as loops ({looped} terms; {} nodes written out)", plan.emitted_nodes(code));
        }
    }
    for h in &plan.horners {
        let _ = writeln!(out, "polynomial: {} monomials compiled as one Horner loop", h.monomials);
    }
    let _ = writeln!(out, "algebra:    {algebra} (auto)");
    Ok(ExitCode::SUCCESS)
}

/// `ISOTRACE_MEMORY_BUDGET`: the largest frame-sized host allocation
/// (pixels, packed records, encoded image), in bytes or with a k/M/G/T
/// suffix. Unset: only the allocator refuses.
fn memory_budget_from_env() -> Result<(), CliError> {
    let Some(v) = std::env::var_os("ISOTRACE_MEMORY_BUDGET") else { return Ok(()) };
    let v = v.to_string_lossy();
    let bytes = crate::memory::parse_budget(&v)
        .ok_or_else(|| CliError::Input(format!("invalid ISOTRACE_MEMORY_BUDGET '{v}': expected a number of bytes, optionally with a suffix k, M, G or T (e.g. 8G)")))?;
    crate::memory::set_budget(Some(bytes));
    Ok(())
}
fn list(a: ListArgs) -> Result<ExitCode, CliError> {
    let mut out = std::io::stdout().lock();
    for e in crate::catalog::builtin() {
        let h = &e.header;
        let title = h.title.clone().unwrap_or_default();
        if a.long {
            let b = h.bbox;
            let status = match h.status {
                Some(crate::catalog::Status::Published) => "published",
                Some(crate::catalog::Status::Reconstruction) => "reconstruction",
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
