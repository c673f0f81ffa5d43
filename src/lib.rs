//! isotrace: a shader-metaprogramming compiler that ray traces implicit
//! surfaces f(x, y, z) = 0 robustly on the GPU.
//!
//! Pipeline: formula text → [`syntax`] (lexer, recursive-descent parser) →
//! [`sema`] (names, folding, sharing) → [`ir`] → [`codegen`] (WGSL evaluators
//! for scalar, interval and reduced affine arithmetic spliced into kernel
//! templates) → [`validate`] (naga) → [`gpu`] (wgpu, headless) → [`output`]
//! (PNG / EXR).
//!
//! ```
//! let f = isotrace::Formula::compile("<doc>", "r = 1; x^2 + y^2 + z^2 - r^2").unwrap();
//! assert_eq!(f.ir.degree(), Some(2));
//! let wgsl = isotrace::codegen::eval_shader(&f.ir, isotrace::codegen::Domain::Interval);
//! isotrace::validate::validate(&wgsl).unwrap();
//! ```
#![warn(missing_docs)]

pub mod catalog;
pub mod codegen;
pub mod diag;
pub mod gpu;
pub mod ir;
pub mod output;
pub mod reference;
pub mod render;
pub mod sema;
pub mod syntax;
pub mod validate;

use diag::Diagnostic;

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
        let err = |diagnostic| FormulaError { origin: origin.to_string(), text: source.to_string(), diagnostic };
        let program = syntax::parse(source).map_err(|e| err(e.to_diagnostic()))?;
        let ir = sema::analyze(&program).map_err(|e| err(e.to_diagnostic()))?;
        Ok(Formula { origin: origin.to_string(), source: source.to_string(), ir })
    }

    /// The formula with definitions inlined and every operation parenthesised.
    pub fn normalized(&self) -> String {
        format!("{}", ir::Display(&self.ir, self.ir.root))
    }
}

/// The inclusion algebra `--algebra auto` picks for a formula.
///
/// Reduced affine arithmetic pays off where IA overestimates: products of
/// non-constant terms (cross terms like x²y², products of factors as in the
/// Barth and Mitchell surfaces). Where the formula is a sum of powers of
/// single variables (superquadrics, the tangle cube) or is dominated by
/// transcendental functions (which RAA evaluates through IA anyway), IA is
/// as tight and cheaper. The threshold is justified by the measurements in
/// the README's benchmark table.
pub fn choose_algebra(ir: &ir::Ir) -> codegen::Domain {
    let (products, _powers) = ir.nonconstant_products();
    if products >= 2 { codegen::Domain::Affine } else { codegen::Domain::Interval }
}
