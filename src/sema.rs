//! Semantic pass: AST → [`Ir`].
//!
//! Resolves names (variables, constants, definitions, parameters), checks
//! arities, folds constants (`sqrt(5)` becomes a literal), turns integer
//! exponents into [`Op::PowI`], and shares common sub-expressions by
//! hash-consing every node, so a repeated `x^2` is computed once.

use crate::diag::{closest, Diagnostic, Span};
use crate::ir::{Func1, Func2, Func3, Ir, NodeId, Op, Var};
use crate::reference::scalar_op;
use crate::syntax::{BinOp, Expr, ExprKind, Program};
use std::collections::HashMap;

/// Largest integer exponent accepted by `^`.
pub const MAX_EXPONENT: u32 = 4096;
/// Largest number of IR nodes in one formula.
pub const MAX_NODES: usize = 50_000;

/// Errors of the semantic pass.
#[derive(Debug, Clone, PartialEq)]
#[allow(missing_docs)] // fields: the names say it
pub enum SemaError {
    /// A call of a function that does not exist.
    UnknownFunction { name: String, span: Span, suggestions: Vec<String> },
    /// A built-in function used without arguments, or a name that is not a function called with some.
    NotAFunction { name: String, span: Span },
    /// A function used as a value.
    FunctionAsValue { name: String, span: Span },
    /// Wrong number of arguments.
    Arity { name: String, expected: String, found: usize, span: Span },
    /// `a = …;` twice.
    Redefinition { name: String, previous: Span, current: Span },
    /// A definition that uses a name defined after it.
    UseBeforeDefinition { name: String, used: Span, defined: Span },
    /// Defining a reserved name (variable, constant, function).
    Reserved { name: String, span: Span },
    /// A constant sub-expression that is not a finite number.
    NotFinite { span: Span, value: f64 },
    /// An integer exponent beyond [`MAX_EXPONENT`].
    ExponentTooLarge { span: Span, exponent: f64 },
    /// More than [`MAX_NODES`] operations.
    TooLarge { nodes: usize },
}

impl SemaError {
    /// Converts to the shared diagnostic form.
    pub fn to_diagnostic(&self) -> Diagnostic {
        match self {
            SemaError::UnknownFunction { name, span, suggestions } => {
                let d = Diagnostic::error(format!("unknown function '{name}'"), *span, "not a function");
                match suggestions.as_slice() {
                    [] => d.with_note(format!("functions: {}", function_names().join(" "))),
                    s => d.with_note(format!("did you mean {}?", quote_list(s))),
                }
            }
            SemaError::NotAFunction { name, span } => {
                Diagnostic::error(format!("'{name}' is not a function"), *span, "called here")
                    .with_note("write `*` for a product: `a*(x + 1)`")
            }
            SemaError::FunctionAsValue { name, span } => {
                Diagnostic::error(format!("function '{name}' used without arguments"), *span, "expected '(' after this")
                    .with_note(format!("call it: `{name}(x)`"))
            }
            SemaError::Arity { name, expected, found, span } => Diagnostic::error(
                format!("wrong number of arguments to '{name}': expected {expected}, found {found}"),
                *span,
                format!("{found} argument{}", if *found == 1 { "" } else { "s" }),
            ),
            SemaError::Redefinition { name, previous, current } => {
                Diagnostic::error(format!("redefinition of '{name}'"), *current, "defined again here")
                    .with_label(*previous, "first defined here")
            }
            SemaError::UseBeforeDefinition { name, used, defined } => {
                Diagnostic::error(format!("'{name}' is used before its definition"), *used, "used here")
                    .with_label(*defined, "defined here")
                    .with_note("move the definition above its first use")
            }
            SemaError::Reserved { name, span } => {
                Diagnostic::error(format!("cannot define '{name}': the name is reserved"), *span, "reserved name")
                    .with_note("x y z t w pi e and the function names cannot be redefined")
            }
            SemaError::NotFinite { span, value } => Diagnostic::error(
                format!("constant expression evaluates to {}", if value.is_nan() { "NaN".to_string() } else { format!("{value}") }),
                *span,
                "not a finite 32-bit float",
            )
            .with_note("constants must be finite and within the f32 range (|c| < 3.4e38)"),
            SemaError::ExponentTooLarge { span, exponent } => Diagnostic::error(
                format!("exponent {exponent} is too large (the limit is {MAX_EXPONENT})"),
                *span,
                "exponent too large",
            ),
            SemaError::TooLarge { nodes } => Diagnostic::plain(format!(
                "formula too large: {nodes} operations (the limit is {MAX_NODES})"
            )),
        }
    }
}

fn quote_list(s: &[String]) -> String {
    let q: Vec<String> = s.iter().map(|s| format!("'{s}'")).collect();
    match q.len() {
        1 => q[0].clone(),
        _ => format!("{} or {}", q[..q.len() - 1].join(", "), q[q.len() - 1]),
    }
}

/// Names and arities of the built-in functions.
enum Builtin {
    F1(Func1),
    F2(Func2),
    F3(Func3),
    /// min / max with two or more arguments
    Variadic(Func2),
}

fn builtin(name: &str) -> Option<Builtin> {
    if let Some(&f) = Func1::ALL.iter().find(|f| f.name() == name) {
        return Some(Builtin::F1(f));
    }
    match name {
        "pow" => Some(Builtin::F2(Func2::Pow)),
        "atan2" => Some(Builtin::F2(Func2::Atan2)),
        "min" => Some(Builtin::Variadic(Func2::Min)),
        "max" => Some(Builtin::Variadic(Func2::Max)),
        "clamp" => Some(Builtin::F3(Func3::Clamp)),
        "mix" => Some(Builtin::F3(Func3::Mix)),
        _ => None,
    }
}

/// All function names, for suggestions and help.
pub fn function_names() -> Vec<&'static str> {
    let mut v: Vec<&str> = Func1::ALL.iter().map(|f| f.name()).collect();
    v.extend(["pow", "atan2", "min", "max", "clamp", "mix"]);
    v
}

const VARIABLES: &[(&str, Var)] = &[("x", Var::X), ("y", Var::Y), ("z", Var::Z), ("t", Var::T), ("w", Var::T)];

/// Lowers a parsed program to IR.
pub fn analyze(program: &Program) -> Result<Ir, SemaError> {
    let mut b = Builder::default();
    // Pass 1: where each definition is, so a forward use can say so.
    let mut def_at: HashMap<&str, Span> = HashMap::new();
    for d in &program.definitions {
        if VARIABLES.iter().any(|(n, _)| *n == d.name) || matches!(d.name.as_str(), "pi" | "e") || builtin(&d.name).is_some() {
            return Err(SemaError::Reserved { name: d.name.clone(), span: d.name_span });
        }
        if let Some(&prev) = def_at.get(d.name.as_str()) {
            return Err(SemaError::Redefinition { name: d.name.clone(), previous: prev, current: d.name_span });
        }
        def_at.insert(&d.name, d.name_span);
    }
    for d in &program.definitions {
        let v = b.expr(&d.value, &def_at)?;
        b.defs.insert(d.name.clone(), v);
    }
    let root = b.expr(&program.body, &def_at)?;
    Ok(Ir { nodes: b.nodes, spans: b.spans, root, params: b.params })
}

#[derive(Default)]
struct Builder {
    nodes: Vec<Op>,
    spans: Vec<Span>,
    dedup: HashMap<Key, NodeId>,
    defs: HashMap<String, NodeId>,
    params: Vec<(String, Span)>,
}

/// Hashable form of [`Op`] (constants by their bits).
#[derive(PartialEq, Eq, Hash)]
struct Key(u8, u64, u64, u64, u64);

fn key(op: &Op) -> Key {
    let o = op.operands();
    let g = |i: usize| o.get(i).copied().unwrap_or(u32::MAX) as u64;
    let (tag, extra) = match *op {
        Op::Const(c) => (0, c.to_bits()),
        Op::Var(v) => (1, v as u64),
        Op::Param(p) => (2, p as u64),
        Op::Neg(_) => (3, 0),
        Op::Add(..) => (4, 0),
        Op::Sub(..) => (5, 0),
        Op::Mul(..) => (6, 0),
        Op::Div(..) => (7, 0),
        Op::PowI(_, n) => (8, n as u64),
        Op::Call1(f, _) => (9, f as u64),
        Op::Call2(f, ..) => (10, f as u64),
        Op::Call3(f, ..) => (11, f as u64),
    };
    Key(tag, extra, g(0), g(1), g(2))
}

impl Builder {
    fn konst(&self, n: NodeId) -> Option<f64> {
        match self.nodes[n as usize] {
            Op::Const(c) => Some(c),
            _ => None,
        }
    }

    /// Adds (or finds) a node, folding it when every operand is constant.
    fn push(&mut self, op: Op, span: Span) -> Result<NodeId, SemaError> {
        let ops = op.operands();
        let op = if !ops.is_empty() && ops.iter().all(|&o| self.konst(o).is_some()) {
            let args: Vec<f64> = ops.iter().map(|&o| self.konst(o).unwrap_or(0.0)).collect();
            let v = scalar_op(&op, &args);
            if !v.is_finite() || !(v as f32).is_finite() {
                return Err(SemaError::NotFinite { span, value: v });
            }
            Op::Const(v)
        } else {
            op
        };
        // Normalise commutative operands so `a*b` and `b*a` share a node.
        let op = match op {
            Op::Add(a, b) if a > b => Op::Add(b, a),
            Op::Mul(a, b) if a > b => Op::Mul(b, a),
            Op::Call2(f @ (Func2::Min | Func2::Max), a, b) if a > b => Op::Call2(f, b, a),
            o => o,
        };
        let k = key(&op);
        if let Some(&id) = self.dedup.get(&k) {
            return Ok(id);
        }
        if self.nodes.len() >= MAX_NODES {
            return Err(SemaError::TooLarge { nodes: self.nodes.len() + 1 });
        }
        let id = self.nodes.len() as NodeId;
        self.nodes.push(op);
        self.spans.push(span);
        self.dedup.insert(k, id);
        Ok(id)
    }

    fn expr(&mut self, e: &Expr, def_at: &HashMap<&str, Span>) -> Result<NodeId, SemaError> {
        match &e.kind {
            ExprKind::Number(v) if !(*v as f32).is_finite() => Err(SemaError::NotFinite { span: e.span, value: *v }),
            ExprKind::Number(v) => self.push(Op::Const(*v), e.span),
            ExprKind::Name(name) => self.name(name, e.span, def_at),
            ExprKind::Neg(a) => {
                let a = self.expr(a, def_at)?;
                self.push(Op::Neg(a), e.span)
            }
            ExprKind::Binary(op, a, bx) => {
                let a = self.expr(a, def_at)?;
                if *op == BinOp::Pow {
                    return self.power(a, bx, e.span, def_at);
                }
                let b = self.expr(bx, def_at)?;
                let op = match op {
                    BinOp::Add => Op::Add(a, b),
                    BinOp::Sub => Op::Sub(a, b),
                    BinOp::Mul => Op::Mul(a, b),
                    BinOp::Div => Op::Div(a, b),
                    BinOp::Pow => unreachable!("handled above"),
                };
                self.push(op, e.span)
            }
            ExprKind::Call { name, name_span, args } => self.call(name, *name_span, args, e.span, def_at),
        }
    }

    fn name(&mut self, name: &str, span: Span, def_at: &HashMap<&str, Span>) -> Result<NodeId, SemaError> {
        if let Some((_, v)) = VARIABLES.iter().find(|(n, _)| *n == name) {
            return self.push(Op::Var(*v), span);
        }
        match name {
            "pi" => return self.push(Op::Const(std::f64::consts::PI), span),
            "e" => return self.push(Op::Const(std::f64::consts::E), span),
            _ => {}
        }
        if let Some(&id) = self.defs.get(name) {
            return Ok(id);
        }
        if let Some(&defined) = def_at.get(name) {
            return Err(SemaError::UseBeforeDefinition { name: name.to_string(), used: span, defined });
        }
        if builtin(name).is_some() {
            return Err(SemaError::FunctionAsValue { name: name.to_string(), span });
        }
        let idx = match self.params.iter().position(|(n, _)| n == name) {
            Some(i) => i,
            None => {
                self.params.push((name.to_string(), span));
                self.params.len() - 1
            }
        };
        self.push(Op::Param(idx as u32), span)
    }

    /// `a ^ b`: integer constant exponents become [`Op::PowI`] (negative ones
    /// `1 / a^n`), anything else `pow(a, b)` defined for a ≥ 0.
    fn power(&mut self, a: NodeId, bx: &Expr, span: Span, def_at: &HashMap<&str, Span>) -> Result<NodeId, SemaError> {
        let b = self.expr(bx, def_at)?;
        self.pow_nodes(a, b, bx.span, span)
    }

    fn pow_nodes(&mut self, a: NodeId, b: NodeId, exp_span: Span, span: Span) -> Result<NodeId, SemaError> {
        match self.konst(b) {
            Some(n) if n.fract() == 0.0 => {
                if n.abs() > MAX_EXPONENT as f64 {
                    return Err(SemaError::ExponentTooLarge { span: exp_span, exponent: n });
                }
                let m = n.abs() as u32;
                let p = match m {
                    0 => return self.push(Op::Const(1.0), span),
                    _ => self.powi(a, m, span)?,
                };
                if n < 0.0 {
                    let one = self.push(Op::Const(1.0), span)?;
                    self.push(Op::Div(one, p), span)
                } else {
                    Ok(p)
                }
            }
            _ => self.push(Op::Call2(Func2::Pow, a, b), span),
        }
    }

    /// a^n by repeated squaring: an even power is the square's power
    /// (x^6 = (x^2)^3), which is tight in interval arithmetic and shares
    /// x^2 between every power of x.
    fn powi(&mut self, a: NodeId, n: u32, span: Span) -> Result<NodeId, SemaError> {
        match n {
            1 => Ok(a),
            2 => self.push(Op::PowI(a, 2), span),
            _ if n % 2 == 0 => {
                let sq = self.push(Op::PowI(a, 2), span)?;
                self.powi(sq, n / 2, span)
            }
            _ => self.push(Op::PowI(a, n), span),
        }
    }

    fn call(&mut self, name: &str, name_span: Span, args: &[Expr], span: Span, def_at: &HashMap<&str, Span>) -> Result<NodeId, SemaError> {
        let Some(f) = builtin(name) else {
            if VARIABLES.iter().any(|(n, _)| *n == name) || self.defs.contains_key(name) || matches!(name, "pi" | "e") {
                return Err(SemaError::NotAFunction { name: name.to_string(), span: name_span });
            }
            let suggestions = closest(name, function_names()).into_iter().map(String::from).collect();
            return Err(SemaError::UnknownFunction { name: name.to_string(), span: name_span, suggestions });
        };
        let (expected, ok) = match f {
            Builtin::F1(_) => ("1", args.len() == 1),
            Builtin::F2(_) => ("2", args.len() == 2),
            Builtin::F3(_) => ("3", args.len() == 3),
            Builtin::Variadic(_) => ("2 or more", args.len() >= 2),
        };
        if !ok {
            return Err(SemaError::Arity { name: name.to_string(), expected: expected.to_string(), found: args.len(), span });
        }
        let mut v = Vec::with_capacity(args.len());
        for a in args {
            v.push(self.expr(a, def_at)?);
        }
        match f {
            Builtin::F1(g) => self.push(Op::Call1(g, v[0]), span),
            Builtin::F2(Func2::Pow) => self.pow_nodes(v[0], v[1], args[1].span, span),
            Builtin::F2(g) => self.push(Op::Call2(g, v[0], v[1]), span),
            Builtin::F3(g) => self.push(Op::Call3(g, v[0], v[1], v[2]), span),
            Builtin::Variadic(g) => {
                let mut acc = v[0];
                for &n in &v[1..] {
                    acc = self.push(Op::Call2(g, acc, n), span)?;
                }
                Ok(acc)
            }
        }
    }
}

/// Binds `--param name=value` pairs to the formula's parameters. Returns the
/// values in parameter order, plus warnings for values that are not used.
pub fn bind_params(ir: &Ir, given: &[(String, f64)]) -> Result<(Vec<f32>, Vec<Diagnostic>), Diagnostic> {
    let mut values = Vec::with_capacity(ir.params.len());
    for (name, span) in &ir.params {
        match given.iter().rev().find(|(n, _)| n == name) {
            Some((_, v)) => values.push(*v as f32),
            None => {
                return Err(Diagnostic::error(format!("missing value for parameter '{name}'"), *span, "free name")
                    .with_note(format!("give it on the command line: --param {name}=1.0 (or did you mean one of x y z t?)")));
            }
        }
    }
    let warnings = given
        .iter()
        .filter(|(n, _)| !ir.params.iter().any(|(p, _)| p == n))
        .map(|(n, _)| {
            let mut d = Diagnostic::plain(format!("parameter '{n}' is given with --param but the formula does not use it"));
            d.severity = crate::diag::Severity::Warning;
            d
        })
        .collect();
    Ok((values, warnings))
}
