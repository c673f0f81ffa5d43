//! isotrace: a shader-metaprogramming compiler that ray traces implicit
//! surfaces f(x, y, z) = 0 robustly on the GPU, and blobtree scenes of
//! distance-field primitives kept as data.
//!
//! Pipeline: formula text → parser → semantic checks → [`ir`] → a field
//! source ([`field`]: the formula compiled into WGSL, a tape, or a scene)
//! → render kernel (one traversal × one field source) → naga validation
//! → [`gpu`] (wgpu, headless) → [`output`] (PNG / EXR).
//!
//! The types to start from: [`Formula`], [`Gpu`], [`Renderer`],
//! [`Settings`], [`Frame`], [`Image`] and, for scenes, [`Scene`]. A
//! formula to an RGBA picture and a PNG:
//!
//! ```
//! use isotrace::{Formula, Gpu, Image, Renderer, Settings};
//!
//! let formula = Formula::compile("<tangle>", "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8")?;
//! let gpu = Gpu::new()?; // the Vulkan device (lavapipe on a machine without a GPU)
//! let renderer = Renderer::for_formula(&gpu, &formula)?; // compiles the kernels once
//! let frame = renderer.render(&Settings::for_box([-3.0, 3.0, -3.0, 3.0, -3.0, 3.0], 96, 96))?;
//! let image = Image::from_frame(&frame);
//! assert_eq!(image.rgba.len(), 96 * 96 * 4);
//! assert!(frame.stats.hits > 1000, "the tangle fills much of the frame");
//! image.save_png(std::env::temp_dir().join("isotrace-doc-tangle.png"))?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! `examples/render_formula.rs` and `examples/edit_scene.rs` (`cargo run
//! --release --example edit_scene`) show more: settings, a scene built in
//! code, edited and rendered again without a new shader.
#![warn(missing_docs)]

/// An internal module: crate-private, or public (and hidden from the
/// documentation) with the `internals` feature, which the benchmarks in
/// `benches/` build with. Nothing outside the benchmarks should use it: its
/// items change without notice.
macro_rules! internal_mod {
    ($name:ident) => {
        #[cfg(feature = "internals")]
        #[doc(hidden)]
        pub mod $name;
        #[cfg(not(feature = "internals"))]
        pub(crate) mod $name;
    };
}

internal_mod!(analysis);
internal_mod!(batch);
internal_mod!(bench);
pub mod bindings;
internal_mod!(bounded);
internal_mod!(catalog);
internal_mod!(choice);
mod cli;
pub mod codegen;
pub mod diag;
pub mod field;
pub mod gpu;
internal_mod!(inline);
pub mod ir;
internal_mod!(kernel);
internal_mod!(layout);
internal_mod!(memory);
pub mod output;
internal_mod!(reference);
pub mod render;
pub mod scene;
internal_mod!(sdf);
internal_mod!(sema);
internal_mod!(syntax);
internal_mod!(validate);
internal_mod!(view);

#[cfg(test)]
mod tests;

pub use gpu::{Gpu, Renderer};
pub use output::Image;
pub use render::{Frame, Settings};
pub use scene::Scene;

use diag::Diagnostic;

/// The `isotrace` command line, which `src/main.rs` runs: parses the
/// process's arguments, runs the command and returns its exit code.
#[doc(hidden)]
pub fn command_line() -> std::process::ExitCode {
    cli::main()
}

/// A formula that parsed and passed the semantic checks.
#[derive(Debug, Clone)]
pub struct Formula {
    /// Where it came from (`<formula>`, a file path, `@name`).
    pub origin: String,
    /// The text.
    pub source: String,
    /// The compiled form.
    pub ir: ir::Ir,
}

/// A formula error: the diagnostic plus the text it points into.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{}", .diagnostic.render(.origin, .text, false))]
pub struct FormulaError {
    /// Where the text came from.
    pub origin: String,
    /// The text.
    pub text: String,
    /// What is wrong.
    pub diagnostic: Diagnostic,
}

impl Formula {
    /// Parses and analyses `source`.
    pub fn compile(origin: &str, source: &str) -> Result<Formula, FormulaError> {
        Self::compile_with(origin, source, &[])
    }

    /// Like [`Formula::compile`], with user functions from `--inline` WGSL
    /// (name, arity) callable from the formula.
    pub fn compile_with(origin: &str, source: &str, externs: &[(String, usize)]) -> Result<Formula, FormulaError> {
        let err = |diagnostic| FormulaError { origin: origin.to_string(), text: source.to_string(), diagnostic };
        let program = syntax::parse(source).map_err(|e| err(e.to_diagnostic()))?;
        let ir = sema::analyze_with(&program, externs).map_err(|e| err(e.to_diagnostic()))?;
        Ok(Formula { origin: origin.to_string(), source: source.to_string(), ir })
    }

    /// The formula with definitions inlined and every operation
    /// parenthesised (cut after 4000 bytes: inlining can grow exponentially).
    pub fn normalized(&self) -> String {
        ir::display_limited(&self.ir, self.ir.root, 4000)
    }
}

/// The inclusion algebra `--algebra auto` picks for a formula.
///
/// Reduced affine arithmetic keeps the ray depth as a symbol, so correlated
/// terms cancel (x^4 - 5x^2 of the tangle cube, the factors of the Barth
/// and Mitchell surfaces). On the Knoll suite RAA is the faster for
/// polynomials of degree 4 to 10 (chosen by measurement on lavapipe,
/// docs/benchmarks.md). It loses elsewhere:
/// - degree 2: fewer evaluations a pixel, but each costs more;
/// - degree 12 and up, or a power of 16 and up: its error terms grow (the
///   decocube, the 4-bretzel, and far worse the superquadric x^200, as
///   Knoll et al. also found);
/// - transcendental functions, division, min/max/abs (CSG): RAA goes
///   through IA for them at extra cost (cloth, sq.csg).
///
/// Since IA bisection takes polynomial nodes of degree 3 to 6 from their
/// polynomials along the ray (`field::compiled::ray_polys`), which keeps what RAA
/// kept and more, IA is the faster of the two on a small formula with such
/// nodes (the Barth decic and sextic, the heart, Steiner, the tangle,
/// Mitchell and the Klein bottle; the two cubics are even, and only the
/// teardrop is a little slower). A large formula (more than
/// [`RAY_POLY_AUTO_NODES`] live nodes) may run as a tape, which has no ray
/// forms, and keeps RAA.
///
/// A polynomial of thousands of monomials, whatever its degree, is faster
/// in RAA ([`horner_pays`]).
pub fn choose_algebra(ir: &ir::Ir) -> ir::Domain {
    if horner_pays(ir) {
        return ir::Domain::Affine;
    }
    if affine_pays(ir) && !(ir.live().len() <= RAY_POLY_AUTO_NODES && field::compiled::takes_ray_polynomials(ir)) { ir::Domain::Affine } else { ir::Domain::Interval }
}

/// Whether RAA beats IA on `ir` where nothing takes its polynomials along
/// the ray (a tape, a scene's formula leaf): a polynomial of degree 4 to
/// 10 with powers below 16, no min, max or CSG ([`choose_algebra`] says
/// why).
pub fn affine_pays(ir: &ir::Ir) -> bool {
    let (minmax, max_power) = ir.shape();
    matches!(ir.degree(), Some(4..=10)) && max_power < 16 && minmax == 0 && !ir.is_csg()
}

/// Whether the compiled field computes a polynomial as one loop over its
/// Horner form (`field::compiled::term_loops::horner`; also one gathered
/// from a sum with other terms) in a formula without min, max or CSG.
/// Each step multiplies by x, y or z, which are exact affine forms along
/// the ray, so RAA keeps what the nested form's
/// cancellations need where IA loses it: the 2,646 monomials of
/// `distinct` (scripts/big-formulas.py, degree 42) take fewer evaluations
/// a pixel and come sooner in RAA (docs/notes/2026-12-07-fixed-costs.md).
pub fn horner_pays(ir: &ir::Ir) -> bool {
    let (minmax, _) = ir.shape();
    minmax == 0 && !ir.is_csg() && !field::compiled::term_loops::written_plan(ir).1.horners.is_empty()
}

/// The most live nodes of a formula for which `choose_algebra` weighs ray
/// polynomials: well inside what `Auto` compiles rather than runs as a tape
/// in IA (`crate::choice::CROSSOVER_BISECT_IA` instructions).
pub const RAY_POLY_AUTO_NODES: usize = 300;
