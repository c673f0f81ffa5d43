//! The compiler's intermediate form: a hash-consed DAG of operations in
//! topological order (operands always precede their users). Shared nodes are
//! the common sub-expressions; the code generators walk `nodes` once and emit
//! straight-line code, one `let` per node.

use crate::diag::Span;
use std::fmt;

/// Index of a node in [`Ir::nodes`].
pub type NodeId = u32;

/// The free variables of a formula.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Var {
    /// x
    X,
    /// y
    Y,
    /// z
    Z,
    /// time (`t`, alias `w`)
    T,
}

impl Var {
    /// Its name in formulas and generated code.
    pub fn name(self) -> &'static str {
        match self {
            Var::X => "x",
            Var::Y => "y",
            Var::Z => "z",
            Var::T => "t",
        }
    }
}

/// One-argument functions.
#[allow(missing_docs)] // variants are the function names
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Func1 {
    Sqrt, Exp, Log, Sin, Cos, Tan, Atan, Sinh, Cosh, Tanh, Abs, Sign, Floor,
}

/// Two-argument functions.
#[allow(missing_docs)] // variants are the function names
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Func2 {
    /// `pow(a, b)` with a non-constant or non-integer exponent: defined for a ≥ 0.
    Pow,
    Atan2, Min, Max,
    /// a^n for an integer n in `0..=POWN_MAX_EXPONENT` known only at run
    /// time: never in an [`Ir`], only in the code of the compiled field's
    /// Horner loops (`field::compiled::term_loops::horner`), whose steps read
    /// their powers from a table; an operation so that the code and its
    /// slope come from the same emitter and derivative rules as the rest.
    PowN,
}

/// The largest exponent of [`Func2::PowN`]: the op libraries' `pown` take
/// five bits of it (or of its half, for an even one).
pub const POWN_MAX_EXPONENT: u32 = 31;

/// Three-argument functions.
#[allow(missing_docs)] // variants are the function names
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Func3 {
    Clamp, Mix,
}

macro_rules! names {
    ($t:ty { $($v:ident => $n:literal),* $(,)? }) => {
        impl $t {
            /// Every variant.
            pub const ALL: &'static [$t] = &[$(<$t>::$v),*];
            /// The name users write and the suffix of the WGSL op (`op_<name>`).
            pub fn name(self) -> &'static str { match self { $(<$t>::$v => $n),* } }
        }
    };
}
names!(Func1 { Sqrt => "sqrt", Exp => "exp", Log => "log", Sin => "sin", Cos => "cos", Tan => "tan",
    Atan => "atan", Sinh => "sinh", Cosh => "cosh", Tanh => "tanh", Abs => "abs", Sign => "sign", Floor => "floor" });
names!(Func2 { Pow => "pow", Atan2 => "atan2", Min => "min", Max => "max", PowN => "pown" });
names!(Func3 { Clamp => "clamp", Mix => "mix" });

/// An operation. Operands are [`NodeId`]s of earlier nodes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Op {
    /// A literal (already folded).
    Const(f64),
    /// x, y, z or t.
    Var(Var),
    /// User parameter number `i` (a uniform).
    Param(u32),
    /// -a
    Neg(NodeId),
    /// a + b
    Add(NodeId, NodeId),
    /// a - b
    Sub(NodeId, NodeId),
    /// a * b
    Mul(NodeId, NodeId),
    /// a / b
    Div(NodeId, NodeId),
    /// a^n for an integer n ≥ 2 (negative exponents become 1 / a^n).
    PowI(NodeId, u32),
    /// f(a)
    Call1(Func1, NodeId),
    /// f(a, b)
    Call2(Func2, NodeId, NodeId),
    /// f(a, b, c)
    Call3(Func3, NodeId, NodeId, NodeId),
    /// User function number `f` of `--inline` WGSL with its first `n`
    /// arguments (at most 4).
    User(u16, [NodeId; 4], u8),
}

impl Op {
    /// The operands, in order.
    pub fn operands(&self) -> Vec<NodeId> {
        match *self {
            Op::Const(_) | Op::Var(_) | Op::Param(_) => vec![],
            Op::Neg(a) | Op::PowI(a, _) | Op::Call1(_, a) => vec![a],
            Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) | Op::Call2(_, a, b) => vec![a, b],
            Op::Call3(_, a, b, c) => vec![a, b, c],
            Op::User(_, args, n) => args[..n as usize].to_vec(),
        }
    }
    /// The same operation on operands mapped by `m` (a rebuilt graph's new
    /// ids); a user function's unused argument slots are 0.
    pub fn with_operands(self, mut m: impl FnMut(NodeId) -> NodeId) -> Op {
        match self {
            Op::Const(_) | Op::Var(_) | Op::Param(_) => self,
            Op::Neg(a) => Op::Neg(m(a)),
            Op::Add(a, b) => Op::Add(m(a), m(b)),
            Op::Sub(a, b) => Op::Sub(m(a), m(b)),
            Op::Mul(a, b) => Op::Mul(m(a), m(b)),
            Op::Div(a, b) => Op::Div(m(a), m(b)),
            Op::PowI(a, n) => Op::PowI(m(a), n),
            Op::Call1(f, a) => Op::Call1(f, m(a)),
            Op::Call2(f, a, b) => Op::Call2(f, m(a), m(b)),
            Op::Call3(f, a, b, c) => Op::Call3(f, m(a), m(b), m(c)),
            Op::User(u, args, n) => {
                let mut mapped = [0; 4];
                for (to, &from) in mapped.iter_mut().zip(&args[..n as usize]) {
                    *to = m(from);
                }
                Op::User(u, mapped, n)
            }
        }
    }
    /// True for operations whose result can be empty (argument entirely
    /// outside the domain): sqrt, log, pow with a real exponent.
    pub fn restricts_domain(&self) -> bool {
        matches!(self, Op::Call1(Func1::Sqrt | Func1::Log, _) | Op::Call2(Func2::Pow, _, _))
    }
}

/// A compiled formula.
#[derive(Debug, Clone)]
pub struct Ir {
    /// Nodes in topological order.
    pub nodes: Vec<Op>,
    /// Source span of each node (for diagnostics and comments).
    pub spans: Vec<Span>,
    /// The implicit function (the first surface's).
    pub root: NodeId,
    /// Every surface drawn: the first is `root`; with `where` clauses each
    /// carries the level-set conditions that restrict it.
    pub surfaces: Vec<SurfaceIr>,
    /// Parameter names, indexed by `Op::Param`, with the first use.
    pub params: Vec<(String, Span)>,
    /// User functions (`--inline` WGSL), indexed by `Op::User`: name, arity.
    pub externs: Vec<(String, usize)>,
}

impl Ir {
    /// The largest degree [`Ir::degree`] reports: a formula of this degree
    /// or more reports exactly this.
    pub const DEGREE_MAX: u32 = u32::MAX;

    /// True when the formula has several surfaces or level-set conditions.
    pub fn is_csg(&self) -> bool {
        self.surfaces.len() > 1 || self.surfaces.iter().any(|s| !s.conditions.is_empty())
    }

    /// Variables the formula depends on, sorted.
    pub fn variables(&self) -> Vec<Var> {
        let mut v: Vec<Var> = self.live().iter().filter_map(|&n| match self.nodes[n as usize] {
            Op::Var(v) => Some(v),
            _ => None,
        }).collect();
        v.sort();
        v.dedup();
        v
    }

    /// Nodes reachable from the surfaces and their conditions, in
    /// topological order.
    pub fn live(&self) -> Vec<NodeId> {
        let mut mark = vec![false; self.nodes.len()];
        mark[self.root as usize] = true;
        for s in &self.surfaces {
            mark[s.f as usize] = true;
            for &(g, _) in &s.conditions {
                mark[g as usize] = true;
            }
        }
        for i in (0..self.nodes.len()).rev() {
            if mark[i] {
                for o in self.nodes[i].operands() {
                    mark[o as usize] = true;
                }
            }
        }
        (0..self.nodes.len() as u32).filter(|&i| mark[i as usize]).collect()
    }

    /// Total degree in x, y, z when the formula is a polynomial (t and
    /// parameters count as coefficients), else `None`. Saturates at
    /// [`Ir::DEGREE_MAX`] (nested powers reach 2^32 within the exponent
    /// limit; a wrapped count would read as a small degree).
    pub fn degree(&self) -> Option<u32> {
        let mut deg: Vec<Option<u32>> = Vec::with_capacity(self.nodes.len());
        for op in &self.nodes {
            let d = |n: NodeId| deg[n as usize];
            let v = match *op {
                Op::Const(_) | Op::Param(_) | Op::Var(Var::T) => Some(0),
                Op::Var(_) => Some(1),
                Op::Neg(a) => d(a),
                Op::Add(a, b) | Op::Sub(a, b) => d(a).zip(d(b)).map(|(a, b)| a.max(b)),
                Op::Mul(a, b) => d(a).zip(d(b)).map(|(a, b)| a.saturating_add(b)),
                Op::Div(a, b) => if d(b) == Some(0) { d(a) } else { None },
                Op::PowI(a, n) => d(a).map(|a| a.saturating_mul(n)),
                Op::User(..) => None,
                Op::Call1(..) | Op::Call2(..) | Op::Call3(..) => {
                    if op.operands().iter().all(|&o| d(o) == Some(0)) { Some(0) } else { None }
                }
            };
            deg.push(v);
        }
        deg[self.root as usize]
    }

    /// The features `--algebra auto` looks at: the number of min / max /
    /// abs / clamp operations, and the largest effective integer exponent
    /// (x^200 normalised to repeated squares still counts as 200).
    pub fn shape(&self) -> (u32, u32) {
        let mut power = vec![1u32; self.nodes.len()];
        let (mut minmax, mut max_power) = (0, 1);
        for &i in &self.live() {
            match self.nodes[i as usize] {
                Op::PowI(a, n) => {
                    power[i as usize] = power[a as usize].saturating_mul(n);
                    max_power = max_power.max(power[i as usize]);
                }
                Op::Call2(Func2::Min | Func2::Max, ..) | Op::Call1(Func1::Abs, _) | Op::Call3(Func3::Clamp, ..) => minmax += 1,
                _ => {}
            }
        }
        (minmax, max_power)
    }

    /// Number of products of two non-constant operands (including squarings
    /// in integer powers), the quantity `--algebra auto` looks at.
    pub fn nonconstant_products(&self) -> (u32, u32) {
        let mut konst = vec![false; self.nodes.len()];
        let (mut products, mut powers) = (0, 0);
        for &i in &self.live() {
            let op = self.nodes[i as usize];
            konst[i as usize] = match op {
                Op::Const(_) | Op::Param(_) | Op::Var(Var::T) => true,
                Op::Var(_) => false,
                _ => op.operands().iter().all(|&o| konst[o as usize]),
            };
            match op {
                Op::Mul(a, b) if !konst[a as usize] && !konst[b as usize] => products += 1,
                Op::PowI(a, _) if !konst[a as usize] => powers += 1,
                _ => {}
            }
        }
        (products, powers)
    }
}

/// One surface: f = 0 where every condition g holds (`g < 0` when
/// `less`, else `g > 0`; g is lhs − rhs of the written condition).
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceIr {
    /// The function.
    pub f: NodeId,
    /// `(g, less)` pairs.
    pub conditions: Vec<(NodeId, bool)>,
}

impl SurfaceIr {
    /// A surface without conditions.
    pub fn plain(f: NodeId) -> SurfaceIr {
        SurfaceIr { f, conditions: vec![] }
    }
}

/// Prints the formula with explicit parentheses (shared nodes expanded).
/// Expansion can grow exponentially with chained definitions; use
/// [`display_limited`] for anything shown to a user.
pub struct Display<'a>(pub &'a Ir, pub NodeId);

/// The formula as [`Display`] prints it, cut after about `limit` bytes
/// (with `...`). The cut also bounds the time and the recursion depth.
pub fn display_limited(ir: &Ir, root: NodeId, limit: usize) -> String {
    struct Budget(String, usize);
    impl fmt::Write for Budget {
        fn write_str(&mut self, s: &str) -> fmt::Result {
            if self.0.len() + s.len() > self.1 {
                return Err(fmt::Error);
            }
            self.0.push_str(s);
            Ok(())
        }
    }
    let mut b = Budget(String::new(), limit);
    if fmt::write(&mut b, format_args!("{}", Display(ir, root))).is_err() {
        b.0.push_str("...");
    }
    b.0
}

impl fmt::Display for Display<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let ir = self.0;
        let sub = |n: NodeId| Display(ir, n);
        match ir.nodes[self.1 as usize] {
            Op::Const(c) => {
                if c < 0.0 { write!(f, "({c})") } else { write!(f, "{c}") }
            }
            Op::Var(v) => f.write_str(v.name()),
            Op::Param(p) => f.write_str(&ir.params[p as usize].0),
            Op::Neg(a) => write!(f, "(-{})", sub(a)),
            Op::Add(a, b) => write!(f, "({} + {})", sub(a), sub(b)),
            Op::Sub(a, b) => write!(f, "({} - {})", sub(a), sub(b)),
            Op::Mul(a, b) => write!(f, "({} * {})", sub(a), sub(b)),
            Op::Div(a, b) => write!(f, "({} / {})", sub(a), sub(b)),
            Op::PowI(a, n) => match ir.nodes[a as usize] {
                Op::PowI(..) => write!(f, "({})^{n}", sub(a)),
                _ => write!(f, "{}^{n}", sub(a)),
            },
            Op::Call1(g, a) => write!(f, "{}({})", g.name(), sub(a)),
            Op::Call2(g, a, b) => write!(f, "{}({}, {})", g.name(), sub(a), sub(b)),
            Op::Call3(g, a, b, c) => write!(f, "{}({}, {}, {})", g.name(), sub(a), sub(b), sub(c)),
            Op::User(u, args, n) => {
                write!(f, "{}(", ir.externs[u as usize].0)?;
                for (k, a) in args[..n as usize].iter().enumerate() {
                    write!(f, "{}{}", if k > 0 { ", " } else { "" }, sub(*a))?;
                }
                f.write_str(")")
            }
        }
    }
}

/// A number domain: how a value is represented on the device (a point, an
/// interval, a reduced affine form), each with its op library of the same
/// names behind its prefix (`crate::codegen::library`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Domain {
    /// Plain f32 (`s_*`).
    Scalar,
    /// Interval arithmetic, `vec2<f32>` (`ia_*`).
    Interval,
    /// Reduced affine arithmetic (AF1, n = 1), `vec3<f32>` (`ra_*`).
    Affine,
}

impl Domain {
    /// Prefix of the library's operations.
    pub fn prefix(self) -> &'static str {
        match self {
            Domain::Scalar => "s",
            Domain::Interval => "ia",
            Domain::Affine => "ra",
        }
    }
    /// The WGSL type of a value.
    pub fn ty(self) -> &'static str {
        match self {
            Domain::Scalar => "f32",
            Domain::Interval => "vec2<f32>",
            Domain::Affine => "vec3<f32>",
        }
    }
    /// Name of the generated evaluator function.
    pub fn eval_fn(self) -> String {
        format!("eval_{}", self.prefix())
    }
}
