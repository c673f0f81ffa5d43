//! Semantic pass: AST → [`Ir`].
//!
//! Resolves names (variables, constants, definitions, parameters), checks
//! arities, folds constants (`sqrt(5)` becomes a literal), turns integer
//! exponents into [`Op::PowI`], and shares common sub-expressions by
//! hash-consing every node, so a repeated `x^2` is computed once.
//! Distance-field forms (`sphere(r)`, `translate(…, shape)`, …) expand here
//! into ordinary nodes ([`crate::sdf`]); transforms rebuild their lowered
//! shape over substituted x, y, z nodes.

use crate::diag::{levenshtein, Diagnostic, Span};
use crate::ir::{Func1, Func2, Func3, Ir, NodeId, Op, Var};
use crate::reference::scalar_op;
use crate::sdf;
use crate::syntax::{BinOp, Expr, ExprKind, Program};
use std::collections::HashMap;

mod chains;
mod error;
mod terms;
pub use error::SemaError;
use error::{quote_list, quote_name};

/// Largest integer exponent accepted by `^`.
pub const MAX_EXPONENT: u32 = 4096;
/// Largest number of IR nodes in one formula.
pub const MAX_NODES: usize = 50_000;

/// Names and arities of the built-in functions.
enum Builtin {
    F1(Func1),
    F2(Func2),
    F3(Func3),
    /// min / max with two or more arguments
    Variadic(Func2),
    /// A distance-field primitive, transform or operator.
    Sdf(&'static sdf::Info),
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
        _ => sdf::lookup(name).map(Builtin::Sdf),
    }
}


/// Names other languages use for a built-in function.
const ALIASES: &[(&str, &str)] = &[
    ("ln", "log"), ("sgn", "sign"), ("fabs", "abs"), ("arctan", "atan"), ("atn", "atan"),
    ("arctan2", "atan2"), ("power", "pow"), ("lerp", "mix"),
];

/// "Did you mean" candidates for an unknown function: a known alias, else
/// the built-ins within a small edit distance (1 for names up to 5 letters,
/// so `foo` does not suggest `cos`) or related by a prefix of at least three
/// letters (`cosine` → `cos`); at most three, closest first.
fn suggest_function(name: &str) -> Vec<String> {
    if let Some((_, f)) = ALIASES.iter().find(|(a, _)| a.eq_ignore_ascii_case(name)) {
        return vec![f.to_string()];
    }
    let lower = name.to_ascii_lowercase();
    let limit = (name.len() / 3).max(1);
    let common = |a: &str, b: &str| a.bytes().zip(b.bytes()).take_while(|(x, y)| x == y).count();
    let mut scored: Vec<(usize, std::cmp::Reverse<usize>, &str)> = crate::syntax::function_names()
        .into_iter()
        .chain(sdf::names())
        .map(|f| (levenshtein(&lower, f), std::cmp::Reverse(common(&lower, f)), f))
        .filter(|&(d, std::cmp::Reverse(c), f)| d <= limit || (c >= 3 && (c == f.len() || c == lower.len())))
        .collect();
    scored.sort();
    scored.into_iter().take(3).map(|(_, _, f)| f.to_string()).collect()
}

const VARIABLES: &[(&str, Var)] = &[("x", Var::X), ("y", Var::Y), ("z", Var::Z), ("t", Var::T), ("w", Var::T)];

/// Lowers a parsed program to IR, with user functions from `--inline` WGSL (name, arity):
/// they can be called like built-ins and become [`Op::User`] nodes.
pub fn analyze_with(program: &Program, externs: &[(String, usize)]) -> Result<Ir, SemaError> {
    let mut b = Builder { externs: externs.to_vec(), ..Builder::default() };
    // Pass 1: where each definition is, so a forward use can say so.
    let mut def_at: HashMap<&str, Span> = HashMap::new();
    for d in &program.definitions {
        if VARIABLES.iter().any(|(n, _)| *n == d.name) || matches!(d.name.as_str(), "pi" | "e" | "where" | "and") || builtin(&d.name).is_some() {
            return Err(SemaError::Reserved { name: d.name.clone(), span: d.name_span });
        }
        if let Some(&prev) = def_at.get(d.name.as_str()) {
            return Err(SemaError::Redefinition { name: d.name.clone(), previous: prev, current: d.name_span });
        }
        def_at.insert(&d.name, d.name_span);
    }
    for d in &program.definitions {
        b.current = Some(d.name.clone());
        let v = b.expr(&d.value, &def_at)?;
        b.defs.insert(d.name.clone(), v);
    }
    b.current = None;
    let mut surfaces = Vec::new();
    for sf in &program.surfaces {
        let f = b.expr(&sf.expr, &def_at)?;
        let mut conditions = Vec::new();
        for c in &sf.conditions {
            let l = b.expr(&c.lhs, &def_at)?;
            let r = b.expr(&c.rhs, &def_at)?;
            conditions.push((b.push(Op::Sub(l, r), c.span)?, c.less));
        }
        surfaces.push(crate::ir::SurfaceIr { f, conditions });
    }
    let root = surfaces[0].f;
    Ok(compact(chains::chain(terms::collect(Ir { nodes: b.nodes, spans: b.spans, root, surfaces, params: b.params, externs: b.externs })?)?))
}

/// Drops the nodes the root does not use (unused definitions, constants
/// folded away) and the parameters only they used, renumbering both, so
/// `params` lists exactly the parameters that need a value.
fn compact(ir: Ir) -> Ir {
    let live = ir.live();
    let mut new_id = vec![NodeId::MAX; ir.nodes.len()];
    let mut param_id: Vec<Option<u32>> = vec![None; ir.params.len()];
    let mut params = Vec::new();
    let mut nodes = Vec::with_capacity(live.len());
    let mut spans = Vec::with_capacity(live.len());
    for &old in &live {
        let op = match ir.nodes[old as usize] {
            Op::Param(p) => Op::Param(*param_id[p as usize].get_or_insert_with(|| {
                params.push(ir.params[p as usize].clone());
                (params.len() - 1) as u32
            })),
            op => op.with_operands(|n| new_id[n as usize]),
        };
        new_id[old as usize] = nodes.len() as NodeId;
        nodes.push(op);
        spans.push(ir.spans[old as usize]);
    }
    let surfaces = ir
        .surfaces
        .iter()
        .map(|sf| crate::ir::SurfaceIr {
            f: new_id[sf.f as usize],
            conditions: sf.conditions.iter().map(|&(g, less)| (new_id[g as usize], less)).collect(),
        })
        .collect();
    Ir { root: new_id[ir.root as usize], surfaces, nodes, spans, params, externs: ir.externs }
}

#[derive(Default)]
struct Builder {
    nodes: Vec<Op>,
    spans: Vec<Span>,
    dedup: HashMap<Key, NodeId>,
    defs: HashMap<String, NodeId>,
    params: Vec<(String, Span)>,
    /// The definition being lowered.
    current: Option<String>,
    /// User functions (`--inline`): name, arity.
    externs: Vec<(String, usize)>,
}

/// Hashable form of [`Op`] (constants by their bits).
#[derive(PartialEq, Eq, Hash)]
struct Key(u8, u64, u64, u64, u64, u64);

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
        Op::User(u, _, n) => (12, ((u as u64) << 8) | n as u64),
    };
    Key(tag, extra, g(0), g(1), g(2), g(3))
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
        // User functions (inline WGSL) cannot run on the CPU: never folded.
        let op = if !ops.is_empty() && !matches!(op, Op::User(..)) && ops.iter().all(|&o| self.konst(o).is_some()) {
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

    /// Lowers an expression. Iterative (an explicit work stack, operands
    /// left to right, calls checked before their arguments) so that a long
    /// chain like `x + x + … + x`, which the parser builds without recursion,
    /// cannot overflow the stack here either.
    fn expr(&mut self, root: &Expr, def_at: &HashMap<&str, Span>) -> Result<NodeId, SemaError> {
        enum Work<'e> {
            Enter(&'e Expr),
            Exit(&'e Expr),
        }
        let mut work = vec![Work::Enter(root)];
        let mut values: Vec<NodeId> = Vec::new();
        while let Some(item) = work.pop() {
            match item {
                Work::Enter(e) => match &e.kind {
                    ExprKind::Number(v) if !(*v as f32).is_finite() => {
                        return Err(SemaError::NumberOutOfRange { span: e.span, value: *v });
                    }
                    ExprKind::Number(v) => values.push(self.push(Op::Const(*v), e.span)?),
                    ExprKind::Name(name) => values.push(self.name(name, e.span, def_at)?),
                    ExprKind::Neg(a) => {
                        work.push(Work::Exit(e));
                        work.push(Work::Enter(a));
                    }
                    ExprKind::Binary(_, a, b) => {
                        work.push(Work::Exit(e));
                        work.push(Work::Enter(b));
                        work.push(Work::Enter(a));
                    }
                    ExprKind::Call(c) => {
                        self.check_call(&c.name, c.name_span, c.args.len(), e.span)?;
                        work.push(Work::Exit(e));
                        work.extend(c.args.iter().rev().map(Work::Enter));
                    }
                },
                Work::Exit(e) => {
                    let id = match &e.kind {
                        ExprKind::Neg(_) => {
                            let a = values.pop().expect("operand lowered");
                            self.push(Op::Neg(a), e.span)?
                        }
                        ExprKind::Binary(op, _, bx) => {
                            let b = values.pop().expect("operand lowered");
                            let a = values.pop().expect("operand lowered");
                            match op {
                                BinOp::Add => self.push(Op::Add(a, b), e.span)?,
                                BinOp::Sub => self.push(Op::Sub(a, b), e.span)?,
                                BinOp::Mul => self.push(Op::Mul(a, b), e.span)?,
                                BinOp::Div => self.push(Op::Div(a, b), e.span)?,
                                BinOp::Pow => self.pow_nodes(a, b, bx.span, e.span)?,
                            }
                        }
                        ExprKind::Call(c) => {
                            let v = values.split_off(values.len() - c.args.len());
                            self.finish_call(&c.name, &v, &c.args, e.span)?
                        }
                        ExprKind::Number(_) | ExprKind::Name(_) => unreachable!("leaves have no exit step"),
                    };
                    values.push(id);
                }
            }
        }
        debug_assert_eq!(values.len(), 1);
        Ok(values[0])
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
            if self.current.as_deref() == Some(name) {
                return Err(SemaError::SelfReference { name: name.to_string(), used: span, defined });
            }
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
            _ if n.is_multiple_of(2) => {
                let sq = self.push(Op::PowI(a, 2), span)?;
                self.powi(sq, n / 2, span)
            }
            _ => self.push(Op::PowI(a, n), span),
        }
    }

    /// Checks that `name(…)` with `nargs` arguments is a valid call (before
    /// its arguments are lowered, so the first error in reading order wins).
    fn check_call(&self, name: &str, name_span: Span, nargs: usize, span: Span) -> Result<(), SemaError> {
        if builtin(name).is_none() {
            if let Some(k) = self.externs.iter().position(|(n, _)| n == name) {
                let arity = self.externs[k].1;
                if nargs != arity {
                    return Err(SemaError::Arity { name: name.to_string(), expected: arity.to_string(), found: nargs, span });
                }
                return Ok(());
            }
        }
        let Some(f) = builtin(name) else {
            if VARIABLES.iter().any(|(n, _)| *n == name) || self.defs.contains_key(name) || matches!(name, "pi" | "e") {
                return Err(SemaError::NotAFunction { name: name.to_string(), span: name_span });
            }
            let mut suggestions = suggest_function(name);
            // Inline WGSL functions are candidates too.
            for (f, _) in &self.externs {
                if crate::diag::levenshtein(&name.to_ascii_lowercase(), f) <= (name.len() / 3).max(1) && suggestions.len() < 3 {
                    suggestions.push(f.clone());
                }
            }
            return Err(SemaError::UnknownFunction { name: name.to_string(), span: name_span, suggestions });
        };
        let (expected, ok) = match f {
            Builtin::F1(_) => ("1".to_string(), nargs == 1),
            Builtin::F2(_) => ("2".to_string(), nargs == 2),
            Builtin::F3(_) => ("3".to_string(), nargs == 3),
            Builtin::Variadic(_) => ("2 or more".to_string(), nargs >= 2),
            Builtin::Sdf(info) => match info.arity {
                sdf::Arity::Exactly(n) => (n.to_string(), nargs == n),
                sdf::Arity::AtLeast(n) => (format!("{n} or more"), nargs >= n),
                sdf::Arity::Between(lo, hi) => (format!("{lo} or {hi}"), (lo..=hi).contains(&nargs)),
                sdf::Arity::Pairs(lo, hi) => (
                    format!("an even number from {} to {} ({lo} to {hi} vertices)", 2 * lo, 2 * hi),
                    nargs % 2 == 0 && (2 * lo..=2 * hi).contains(&nargs),
                ),
            },
        };
        if !ok {
            return Err(SemaError::Arity { name: name.to_string(), expected, found: nargs, span });
        }
        Ok(())
    }

    /// Builds a checked call from its lowered arguments `v`.
    fn finish_call(&mut self, name: &str, v: &[NodeId], args: &[Expr], span: Span) -> Result<NodeId, SemaError> {
        if builtin(name).is_none() {
            if let Some(k) = self.externs.iter().position(|(n, _)| n == name) {
                let mut a = [0; 4];
                a[..v.len()].copy_from_slice(v);
                return self.push(Op::User(k as u16, a, v.len() as u8), span);
            }
        }
        match builtin(name).expect("checked by check_call") {
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
            Builtin::Sdf(info) => {
                let mut sink = SdfSink { b: self, span, name: info.name, args };
                sdf::lower(&mut sink, info.form, v)
            }
        }
    }

    /// `root` rebuilt with x, y, z replaced by `xyz` (a transform's
    /// coordinate substitution). Only the nodes `root` depends on are
    /// visited, in id order (which is topological); the rebuilt nodes fold
    /// and share through [`Builder::push`] like any other, and the old
    /// subgraph, if nothing else uses it, is dropped by [`compact`].
    fn substitute(&mut self, root: NodeId, xyz: [NodeId; 3]) -> Result<NodeId, SemaError> {
        let mut seen: HashMap<NodeId, NodeId> = HashMap::new();
        let mut stack = vec![root];
        let mut order = Vec::new();
        while let Some(n) = stack.pop() {
            if seen.insert(n, n).is_none() {
                order.push(n);
                stack.extend(self.nodes[n as usize].operands());
            }
        }
        order.sort_unstable();
        for n in order {
            let op = match self.nodes[n as usize] {
                Op::Var(Var::X) => { seen.insert(n, xyz[0]); continue; }
                Op::Var(Var::Y) => { seen.insert(n, xyz[1]); continue; }
                Op::Var(Var::Z) => { seen.insert(n, xyz[2]); continue; }
                Op::Var(Var::T) | Op::Const(_) | Op::Param(_) => continue,
                op => op.with_operands(|k| seen[&k]),
            };
            let span = self.spans[n as usize];
            let id = self.push(op, span)?;
            seen.insert(n, id);
        }
        Ok(seen[&root])
    }
}

/// The semantic pass seen by [`sdf::lower`]: new nodes carry the call's
/// span, and a bad argument points at that argument.
struct SdfSink<'b, 'e> {
    b: &'b mut Builder,
    span: Span,
    name: &'static str,
    args: &'e [Expr],
}

impl sdf::Sink for SdfSink<'_, '_> {
    type Error = SemaError;
    fn push(&mut self, op: Op) -> Result<NodeId, SemaError> {
        self.b.push(op, self.span)
    }
    fn konst(&self, n: NodeId) -> Option<f64> {
        self.b.konst(n)
    }
    fn op(&self, n: NodeId) -> Op {
        self.b.nodes[n as usize]
    }
    fn substitute(&mut self, shape: NodeId, xyz: [NodeId; 3]) -> Result<NodeId, SemaError> {
        self.b.substitute(shape, xyz)
    }
    fn bad_argument(&self, index: usize, message: String) -> SemaError {
        let span = self.args.get(index).map_or(self.span, |a| a.span);
        SemaError::BadArgument { name: self.name.to_string(), message, span }
    }
}

/// Binds `--param name=value` pairs to the formula's parameters. Returns the
/// values in parameter order, plus warnings for values that are not used.
/// A parameter given twice takes its last value.
pub fn bind_params(ir: &Ir, given: &[(String, f64)]) -> Result<(Vec<f32>, Vec<Diagnostic>), Diagnostic> {
    let mut values = Vec::with_capacity(ir.params.len());
    for (name, span) in &ir.params {
        match given.iter().rev().find(|(n, _)| n == name) {
            Some(&(_, v)) if v.is_finite() && (v as f32).is_finite() => values.push(v as f32),
            Some(&(_, v)) => {
                return Err(Diagnostic::error(
                    format!("value {} of parameter {} is not a finite 32-bit float", crate::diag::show_number(v), quote_name(name)),
                    *span,
                    "parameter used here",
                )
                .with_note("parameter values must be finite and within the f32 range (|v| < 3.4e38)"));
            }
            None => {
                let mut d = Diagnostic::error(format!("missing value for parameter {}", quote_name(name)), *span, "free name, so a parameter");
                if name.len() <= crate::diag::QUOTED_CHARS {
                    d = d.with_note(format!("give it a value on the command line: --param {name}=1.0"));
                }
                let lower = name.to_ascii_lowercase();
                if lower != *name && (VARIABLES.iter().any(|(v, _)| *v == lower) || matches!(lower.as_str(), "pi" | "e")) {
                    d = d.with_note(format!("did you mean '{lower}'? names are case-sensitive"));
                }
                return Err(d);
            }
        }
    }
    let names: Vec<&str> = ir.params.iter().map(|(p, _)| p.as_str()).collect();
    let mut warnings: Vec<Diagnostic> = Vec::new();
    let mut warned: Vec<&str> = Vec::new();
    for (n, _) in given {
        if names.contains(&n.as_str()) || warned.contains(&n.as_str()) {
            continue;
        }
        warned.push(n);
        let mut d = Diagnostic::plain(format!("parameter {} is given with --param but the formula does not use it", quote_name(n)));
        d.severity = crate::diag::Severity::Warning;
        let near: Vec<String> = names
            .iter()
            .filter(|p| {
                let d = levenshtein(n, p);
                d <= 1.max(n.len() / 3) && d < n.len().max(p.len())
            })
            .map(|p| p.to_string())
            .collect();
        d = if !near.is_empty() {
            d.with_note(format!("did you mean {}?", quote_list(&near)))
        } else if names.is_empty() {
            d.with_note("the formula has no parameters")
        } else {
            d.with_note(format!("the formula's parameters: {}", names.join(" ")))
        };
        warnings.push(d);
    }
    Ok((values, warnings))
}
