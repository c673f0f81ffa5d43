//! The derivative rules' terms as WGSL expressions in the slopes' domain
//! (`super::rule` over [`Wgsl`]), for the compiled field's generated code.

use super::{Terms, D};
use crate::field::compiled::emit::emit_odd_power;
use crate::ir::{Domain, Ir, NodeId, Op};
use std::fmt::Write;

/// The `op_*`-library name (after the domain prefix) of a term's operation.
fn wgsl_name(op: D) -> &'static str {
    match op {
        D::Neg => "neg",
        D::Sqr => "sqr",
        D::Sin => "sin",
        D::Cos => "cos",
        D::Log => "log",
        D::Sinh => "sinh",
        D::Cosh => "cosh",
        D::Sign => "sign",
        D::Add => "add",
        D::Sub => "sub",
        D::Mul => "mul",
        D::Div => "div",
        D::Max => "max",
        D::Dsign => "dsign",
        D::Dfloor => "dfloor",
    }
}

/// A term of the generated code: a WGSL expression, either a plain f32
/// (`Point`: the ray direction, constants, and what is computed from them
/// alone; points in every domain, rounded as the domain's own product of
/// two points would be) or a value of the domain (`Form`).
/// A cell's derivative enclosure starts from the ray direction, a point, so
/// the first terms of every chain (2·x·dx of x², say) are a domain value
/// times an f32: `{p}_scale`, a few instructions where a product of two
/// intervals is about twenty (lavapipe runs every one of them on every cell).
#[derive(Debug, Clone)]
pub(super) enum Term {
    Point(String),
    Form(String),
}

impl Term {
    pub(super) fn text(&self) -> &str {
        match self {
            Term::Point(s) | Term::Form(s) => s,
        }
    }
    /// The same kind of term under another name (its `let` binding).
    pub(super) fn renamed(&self, name: String) -> Term {
        match self {
            Term::Point(_) => Term::Point(name),
            Term::Form(_) => Term::Form(name),
        }
    }
    /// The term as a value of the domain with prefix `p`.
    pub(super) fn lift(&self, p: &str) -> String {
        match self {
            Term::Point(s) => format!("{p}_const({s})"),
            Term::Form(s) => s.clone(),
        }
    }
}

/// The generated code's terms: WGSL expressions in the slopes' domain (prefix `p`), with
/// bound subterms written to `out` as `let` statements.
pub(super) struct Wgsl<'a> {
    pub(super) out: &'a mut String,
    pub(super) p: &'static str,
    pub(super) domain: Domain,
    pub(super) ir: &'a Ir,
    /// The values' domain prefix when the slopes are in another domain
    /// (values then enter slope terms as their ranges).
    pub(super) ranged: Option<&'static str>,
    /// The nodes that are never negative ([`crate::analysis::nonneg`]).
    pub(super) nn: &'a [bool],
}

impl Terms for Wgsl<'_> {
    type T = Term;
    fn value(&mut self, n: NodeId) -> Term {
        match self.ranged {
            Some(vp) => Term::Form(format!("{vp}_range(v{n})")),
            None => Term::Form(format!("v{n}")),
        }
    }
    fn konst(&mut self, c: f32) -> Term {
        Term::Point(format!("{c:?}"))
    }
    fn direction(&mut self, axis: u32) -> Term {
        Term::Point(["dx", "dy", "dz"][axis as usize].into())
    }
    fn un(&mut self, op: D, a: Term) -> Term {
        match (op, &a) {
            (D::Neg, Term::Point(x)) => Term::Point(format!("(-({x}))")),
            (D::Sqr, Term::Point(x)) => Term::Point(format!("({x} * {x})")),
            _ => Term::Form(format!("{}_{}({})", self.p, wgsl_name(op), a.lift(self.p))),
        }
    }
    fn bin(&mut self, op: D, a: Term, b: Term) -> Term {
        let p = self.p;
        match (op, &a, &b) {
            (D::Add | D::Sub | D::Mul, Term::Point(x), Term::Point(y)) => {
                let sym = match op {
                    D::Add => "+",
                    D::Sub => "-",
                    _ => "*",
                };
                Term::Point(format!("({x} {sym} {y})"))
            }
            (D::Mul, Term::Point(x), Term::Form(v)) | (D::Mul, Term::Form(v), Term::Point(x)) => Term::Form(format!("{p}_scale({v}, {x})")),
            _ => Term::Form(format!("{p}_{}({}, {})", wgsl_name(op), a.lift(p), b.lift(p))),
        }
    }
    fn dminmax(&mut self, max: bool, [a, b, da, db]: [Term; 4]) -> Term {
        let p = self.p;
        Term::Form(format!("{p}_{}({}, {}, {}, {})", if max { "dmax" } else { "dmin" }, a.lift(p), b.lift(p), da.lift(p), db.lift(p)))
    }
    fn odd_power(&mut self, id: NodeId, q: Term, m: u32) -> Term {
        let q = q.lift(self.p);
        Term::Form(emit_odd_power(self.out, self.p, &format!("dw{id}"), &q, m))
    }
    fn bind(&mut self, id: NodeId, tag: &str, x: Term) -> Term {
        let _ = writeln!(self.out, "    let {tag}{id} = {};", x.text());
        x.renamed(format!("{tag}{id}"))
    }
    fn whole(&mut self) -> Term {
        Term::Form(format!("{}_whole()", self.p))
    }
    fn pown_slope(&mut self, a: Term, n: Term) -> Term {
        let p = self.p;
        Term::Form(format!("{p}_dpown({}, {})", a.lift(p), n.lift(p)))
    }
    /// In interval slopes, a slope times a value that is never negative
    /// takes two products (`ia_mul_by_nonneg`).
    fn times(&mut self, d: Term, c: NodeId) -> Term {
        let vc = self.value(c);
        match d {
            Term::Form(_) if self.p == "ia" && self.nn.get(c as usize) == Some(&true) => Term::Form(format!("ia_mul_by_nonneg({}, {})", d.lift("ia"), vc.lift("ia"))),
            _ => self.bin(D::Mul, d, vc),
        }
    }
    /// In interval slopes, the square's slope of a never-negative a takes
    /// `ia_mul_by_nonneg`'s two products (the distance forms' max(q, 0)²).
    fn twice_times(&mut self, d: Term, a: NodeId) -> Term {
        let (two, va) = (self.konst(2.0), self.value(a));
        let m = self.bin(D::Mul, two, va);
        match d {
            Term::Form(_) if self.p == "ia" && self.nn.get(a as usize) == Some(&true) => Term::Form(format!("ia_mul_by_nonneg({}, {})", d.lift("ia"), m.lift("ia"))),
            _ => self.bin(D::Mul, m, d),
        }
    }
    /// In interval slopes, `ia_div_by_nonneg`: no general product on the
    /// side that is not taken (lavapipe compiles both sides of a select).
    fn over_nonneg(&mut self, d: Term, m: Term) -> Term {
        match (&d, &m) {
            (Term::Form(_), Term::Form(_)) if self.p == "ia" => Term::Form(format!("ia_div_by_nonneg({}, {})", d.lift("ia"), m.lift("ia"))),
            _ => self.bin(D::Div, d, m),
        }
    }
    /// In interval slopes, `ia_dabs`: a's slope or its negative where a
    /// keeps its sign, their hull where it does not. The product
    /// sign(a)·a' gives that too (and the hull of 0 and a' where a's range
    /// ends at 0), but `ia_mul`'s general case cost icos.csg's ten |n·p|
    /// about a tenth of its frame.
    fn dabs(&mut self, a: Term, da: Term) -> Term {
        if self.p != "ia" {
            let s = self.un(D::Sign, a);
            return self.bin(D::Mul, s, da);
        }
        Term::Form(format!("ia_dabs({}, {})", a.lift("ia"), da.lift("ia")))
    }
    fn divide(&mut self, a: Term, c: NodeId) -> Term {
        let by_literal = match self.ir.nodes.get(c as usize) {
            Some(&Op::Const(k)) => crate::codegen::divide_by_literal(self.domain, &a.lift(self.p), k),
            _ => None,
        };
        by_literal.map_or_else(|| self.bin(D::Div, a, Term::Form(format!("v{c}"))), Term::Form)
    }
}
