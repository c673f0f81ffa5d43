//! Parser and semantic-pass behaviour: precedence and associativity, number
//! syntax, comments, definitions, names, constant folding, common
//! sub-expression sharing, integer powers, degrees, variables and parameters.

use crate::Formula;
use crate::ir::{Func1, Func2, Ir, Op, Var};
use crate::syntax::{self, BinOp, Expr, ExprKind};

/// The body of a parsed formula as an s-expression.
fn sx(src: &str) -> String {
    let p = syntax::parse(src).unwrap_or_else(|e| panic!("{src:?}: {}", e.to_diagnostic().message));
    show(p.body())
}

fn show(e: &Expr) -> String {
    match &e.kind {
        ExprKind::Number(v) => format!("{v}"),
        ExprKind::Name(n) => n.clone(),
        ExprKind::Neg(a) => format!("(neg {})", show(a)),
        ExprKind::Binary(op, a, b) => format!("({} {} {})", op.symbol(), show(a), show(b)),
        ExprKind::Call(c) => {
            let args: Vec<String> = c.args.iter().map(show).collect();
            format!("({} {})", c.name, args.join(" "))
        }
    }
}

fn ir(src: &str) -> Ir {
    match Formula::compile("<test>", src) {
        Ok(f) => f.ir,
        Err(e) => panic!("{e}"),
    }
}

fn root(src: &str) -> Op {
    let ir = ir(src);
    ir.nodes[ir.root as usize]
}

/// The formula's value, when it folds to a constant.
fn folded(src: &str) -> f64 {
    match root(src) {
        Op::Const(c) => c,
        op => panic!("{src:?} did not fold: {op:?}"),
    }
}

fn count(ir: &Ir, pred: impl Fn(&Op) -> bool) -> usize {
    ir.live().iter().filter(|&&n| pred(&ir.nodes[n as usize])).count()
}

// ---- precedence and associativity -------------------------------------------

#[test]
fn unary_minus_binds_looser_than_power() {
    assert_eq!(sx("-x^2"), "(neg (^ x 2))");
    assert_eq!(sx("-2^2"), "(neg (^ 2 2))");
    assert_eq!(folded("-2^2"), -4.0);
    assert_eq!(sx("(-x)^2"), "(^ (neg x) 2)");
}

#[test]
fn negative_exponent_is_allowed() {
    assert_eq!(sx("2^-1"), "(^ 2 (neg 1))");
    assert_eq!(folded("2^-1"), 0.5);
    assert_eq!(sx("x^-y^2"), "(^ x (neg (^ y 2)))");
    assert_eq!(sx("x^+2"), "(^ x 2)");
}

#[test]
fn power_is_right_associative() {
    assert_eq!(sx("x^y^z"), "(^ x (^ y z))");
    assert_eq!(folded("2^3^2"), 512.0);
}

#[test]
fn minus_and_divide_are_left_associative() {
    assert_eq!(sx("x - y - z"), "(- (- x y) z)");
    assert_eq!(sx("x / y / z"), "(/ (/ x y) z)");
    assert_eq!(sx("x - y + z"), "(+ (- x y) z)");
    assert_eq!(sx("x / y * z"), "(* (/ x y) z)");
    assert_eq!(folded("10 - 4 - 3"), 3.0);
    assert_eq!(folded("64 / 4 / 2"), 8.0);
}

#[test]
fn products_bind_tighter_than_sums() {
    assert_eq!(sx("x + y * z"), "(+ x (* y z))");
    assert_eq!(sx("(x + y) * z"), "(* (+ x y) z)");
    assert_eq!(sx("x * y ^ 2"), "(* x (^ y 2))");
    assert_eq!(sx("-x * y"), "(* (neg x) y)");
    assert_eq!(sx("x * -y"), "(* x (neg y))");
    assert_eq!(sx("x - -y"), "(- x (neg y))");
    assert_eq!(sx("--x"), "(neg (neg x))");
    assert_eq!(sx("+x"), "x");
    assert_eq!(folded("2 + 3 * 4 ^ 2"), 50.0);
}

#[test]
fn calls_and_arguments() {
    assert_eq!(sx("sin(x + y)"), "(sin (+ x y))");
    assert_eq!(sx("max(x, y, -z, 1)"), "(max x y (neg z) 1)");
    assert_eq!(sx("atan2(y, x)^2"), "(^ (atan2 y x) 2)");
    assert_eq!(sx("-sin(x)^2"), "(neg (^ (sin x) 2))");
}

#[test]
fn spans_cover_the_source() {
    let src = "a = 2;  (x + y) * sin(z)";
    let p = syntax::parse(src).unwrap();
    assert_eq!(p.definitions[0].name, "a");
    assert_eq!(&src[p.definitions[0].name_span.range()], "a");
    assert_eq!(&src[p.body().span.range()], "(x + y) * sin(z)");
    let ExprKind::Binary(BinOp::Mul, a, b) = &p.body().kind else { panic!("{:?}", p.body()) };
    assert_eq!(&src[a.span.range()], "(x + y)");
    assert_eq!(&src[b.span.range()], "sin(z)");
    let ExprKind::Call(c) = &b.kind else { panic!() };
    assert_eq!(&src[c.name_span.range()], "sin");
    let p = syntax::parse("-x^2").unwrap();
    assert_eq!((p.body().span.start, p.body().span.end), (0, 4));
}

// ---- tokens -------------------------------------------------------------

#[test]
fn number_forms() {
    for (text, value) in [
        (".5", 0.5),
        ("1e-3", 1e-3),
        ("2.5E+4", 2.5e4),
        ("2.5e4", 2.5e4),
        ("5.", 5.0),
        ("1.e2", 100.0),
        (".5e1", 5.0),
        ("007", 7.0),
        ("0", 0.0),
        ("3.4e38", 3.4e38),
        ("1e-50", 1e-50),
    ] {
        let p = syntax::parse(text).unwrap_or_else(|e| panic!("{text}: {e:?}"));
        assert_eq!(p.body().kind, ExprKind::Number(value), "{text}");
    }
    assert_eq!(sx("2*.5"), "(* 2 0.5)");
    assert_eq!(sx("x^2e1"), "(^ x 20)");
}

#[test]
fn malformed_numbers_are_errors() {
    for text in ["1e", "1e+", "1.2.3", ".", "1..2", "1e2.5", ".e3", "2e-x"] {
        let e = syntax::parse(text).expect_err(text);
        assert!(e.to_diagnostic().message.starts_with("invalid number"), "{text}: {e:?}");
    }
}

#[test]
fn comments_and_whitespace() {
    assert_eq!(sx("x # a comment\n + y"), "(+ x y)");
    assert_eq!(sx("# leading comment\nx#trailing"), "x");
    assert_eq!(sx("\tx\r\n*\r\ny  "), "(* x y)");
    assert_eq!(sx("a = 1; # one\n# two\na + x"), "(+ a x)");
    assert_eq!(sx("x # ( unbalanced in a comment )"), "x");
}

#[test]
fn identifiers() {
    assert_eq!(sx("_a1 + B_2"), "(+ _a1 B_2)");
    assert_eq!(sx("sin_x"), "sin_x");
    assert_eq!(sx("x2"), "x2");
}

// ---- names --------------------------------------------------------------

#[test]
fn definitions_are_inlined() {
    let f = Formula::compile("<test>", "r = 1.5; s = r^2; x^2 + y^2 + z^2 - s").unwrap();
    assert_eq!(f.ir.params, vec![]);
    assert_eq!(f.ir.degree(), Some(2));
    // s folds to the constant 2.25.
    assert!(f.ir.nodes.iter().any(|op| *op == Op::Const(2.25)));
    assert_eq!(f.normalized(), Formula::compile("<test>", "x^2 + y^2 + z^2 - 2.25").unwrap().normalized());
    // A definition can use variables and earlier definitions.
    let f = Formula::compile("<test>", "q = x^2 + y^2; p = q*q; p - z").unwrap();
    assert_eq!(f.ir.degree(), Some(4));
}

#[test]
fn unused_definitions_leave_nothing_behind() {
    let ir = ir("k = b*y + sin(z); x - 1");
    assert_eq!(ir.variables(), vec![Var::X]);
    assert!(ir.params.is_empty(), "{:?}", ir.params);
    assert_eq!(ir.nodes.len(), ir.live().len());
    assert_eq!(ir.root as usize, ir.nodes.len() - 1);
}

#[test]
fn w_is_an_alias_of_t() {
    let a = ir("x + w");
    let b = ir("x + t");
    assert_eq!(a.nodes, b.nodes);
    assert_eq!(a.variables(), vec![Var::X, Var::T]);
    // t and w are the same node.
    let ir = ir("t*w");
    assert_eq!(count(&ir, |op| matches!(op, Op::Var(_))), 1);
    assert!(matches!(ir.nodes[ir.root as usize], Op::PowI(_, 2) | Op::Mul(..)));
}

#[test]
fn pi_and_e() {
    assert_eq!(folded("pi"), std::f64::consts::PI);
    assert_eq!(folded("e"), std::f64::consts::E);
    assert_eq!(folded("2*pi"), 2.0 * std::f64::consts::PI);
    assert_eq!(folded("log(e)"), 1.0);
    assert!(ir("e*x").params.is_empty());
}

#[test]
fn free_names_are_parameters() {
    let ir = ir("a*x^2 + b*y + a - c_1");
    let names: Vec<&str> = ir.params.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["a", "b", "c_1"]);
    assert_eq!(count(&ir, |op| matches!(op, Op::Param(0))), 1, "a is one node");
    // Names are case-sensitive: X is a parameter, not x.
    let ir2 = crate::Formula::compile("<t>", "X + x").unwrap().ir;
    assert_eq!(ir2.params.len(), 1);
    assert_eq!(ir2.variables(), vec![Var::X]);
}

#[test]
fn variables_are_sorted_and_live_only() {
    assert_eq!(ir("z + x*y").variables(), vec![Var::X, Var::Y, Var::Z]);
    assert_eq!(ir("sin(t) + z").variables(), vec![Var::Z, Var::T]);
    assert_eq!(ir("sin(x) - sin(x) + 1").variables(), vec![Var::X]);
    // Like terms are collected first: x cancels.
    assert_eq!(ir("x - x + 1").variables(), vec![]);
    assert_eq!(ir("7").variables(), vec![]);
}

// ---- folding, sharing, powers -----------------------------------------------

#[test]
fn constants_fold() {
    let ir = ir("sqrt(5)*x");
    assert!(ir.nodes.iter().any(|op| *op == Op::Const(5f64.sqrt())));
    assert_eq!(count(&ir, |op| matches!(op, Op::Call1(..))), 0);
    assert_eq!(folded("sqrt(5)"), 5f64.sqrt());
    assert_eq!(folded("min(3, 1, 2)"), 1.0);
    assert_eq!(folded("max(3, 1, 2)"), 3.0);
    assert_eq!(folded("clamp(5, 0, 1)"), 1.0);
    assert_eq!(folded("mix(2, 4, 0.25)"), 2.5);
    assert_eq!(folded("atan2(1, 1)"), std::f64::consts::FRAC_PI_4);
    assert_eq!(folded("pow(2, 0.5)"), 2f64.sqrt());
    assert_eq!(folded("abs(-3) + sign(-2) + floor(2.5)"), 4.0);
    assert_eq!(folded("-(1 + 2)"), -3.0);
    assert_eq!(folded("x^0"), 1.0);
    // Constant parts of a larger formula fold; the rest does not.
    let ir = self::ir("x + 2*3");
    assert!(matches!(ir.nodes[ir.root as usize], Op::Add(..)));
    assert!(ir.nodes.contains(&Op::Const(6.0)));
    assert_eq!(ir.nodes.len(), 3);
}

#[test]
fn common_subexpressions_are_shared() {
    let ir = ir("x^2 + y^2 + x^2*z - sqrt(x^2 + y^2)");
    assert_eq!(count(&ir, |op| matches!(op, Op::PowI(_, 2))), 2, "x^2 and y^2 once each");
    // (x^2 + y^2) is shared with the sqrt argument: 2 additions, not 3.
    assert_eq!(count(&ir, |op| matches!(op, Op::Add(..))), 2, "x^2 + y^2 once");
    let ir = self::ir("sin(x) * sin(x) + sin(x)");
    assert_eq!(count(&ir, |op| matches!(op, Op::Call1(Func1::Sin, _))), 1);
    // Commutative operands are normalised.
    let ir = self::ir("sin(x*y) + sin(y*x)");
    assert_eq!(count(&ir, |op| matches!(op, Op::Mul(..))), 1);
    let ir = self::ir("min(x, y) - min(y, x)");
    assert_eq!(count(&ir, |op| matches!(op, Op::Call2(Func2::Min, ..))), 1);
    // Through definitions too.
    let ir = self::ir("r2 = x^2 + y^2; r2*r2 - (x^2 + y^2)");
    assert_eq!(count(&ir, |op| matches!(op, Op::Add(..))), 1);
}

#[test]
fn integer_powers() {
    assert!(matches!(root("x^3"), Op::PowI(_, 3)));
    assert!(matches!(root("x^2.0"), Op::PowI(_, 2)));
    assert!(matches!(root("pow(x, 3)"), Op::PowI(_, 3)));
    assert!(matches!(root("x^1"), Op::Var(Var::X)));
    assert!(matches!(root("x^0.5"), Op::Call2(Func2::Pow, ..)));
    assert!(matches!(root("x^y"), Op::Call2(Func2::Pow, ..)));
    // Negative: 1 / x^n.
    let ir = ir("x^-2");
    let Op::Div(one, p) = ir.nodes[ir.root as usize] else { panic!("{:?}", ir.nodes) };
    assert_eq!(ir.nodes[one as usize], Op::Const(1.0));
    assert!(matches!(ir.nodes[p as usize], Op::PowI(_, 2)));
    // Even powers square first, so x^6 reuses x^2.
    let ir = self::ir("x^6 + x^2");
    assert_eq!(count(&ir, |op| matches!(op, Op::PowI(..))), 2);
    let ir = self::ir("x^200");
    assert_eq!(count(&ir, |op| matches!(op, Op::PowI(..))), 4, "((x^2)^2)^2 then ^25: {:?}", ir.nodes);
    assert!(matches!(root("x^4096"), Op::PowI(..)));
}

#[test]
fn variadic_min_max_chain() {
    let ir = ir("max(x, y, z, t)");
    assert_eq!(count(&ir, |op| matches!(op, Op::Call2(Func2::Max, ..))), 3);
}

// ---- degree ---------------------------------------------------------------

const PHI: &str = "1.618033988749895";

#[test]
fn degrees() {
    let barth = format!(
        "4*({PHI}^2*x^2 - y^2)*({PHI}^2*y^2 - z^2)*({PHI}^2*z^2 - x^2) - (1 + 2*{PHI})*(x^2 + y^2 + z^2 - 1)^2"
    );
    assert_eq!(ir(&barth).degree(), Some(6));
    assert_eq!(ir("x^200 + y^200 + z^200 - 1").degree(), Some(200));
    assert_eq!(ir("x^2 + y^2 + z^2 - 1").degree(), Some(2));
    assert_eq!(ir("x^2*y^2 + y^2*z^2 + z^2*x^2 - x*y*z").degree(), Some(4));
    assert_eq!(ir("((x^2 + y^2)^3 - 4*x^2*y^2)^2 + z^2 - 0.0005").degree(), Some(12));
    assert_eq!(ir("sin(x) + y").degree(), None);
    assert_eq!(ir("sqrt(x^2 + y^2) - 1").degree(), None);
    assert_eq!(ir("1/x").degree(), None);
    assert_eq!(ir("x^-2").degree(), None);
    assert_eq!(ir("x^2/2 + y").degree(), Some(2));
    // t, parameters and constant functions are coefficients.
    assert_eq!(ir("a*x^3 + sin(t)*y").degree(), Some(3));
    assert_eq!(ir("sqrt(2)*x*y*z").degree(), Some(3));
    assert_eq!(ir("5").degree(), Some(0));
}

#[test]
fn where_clauses_and_several_surfaces() {
    let f = crate::Formula::compile("<t>", "a = 2; x^2 + y^2 + z^2 - 1 where z > 0 and x < a; z where x^2 + y^2 < 1;").unwrap();
    assert_eq!(f.ir.surfaces.len(), 2);
    assert_eq!(f.ir.surfaces[0].conditions.len(), 2);
    assert!(!f.ir.surfaces[0].conditions[0].1 && f.ir.surfaces[0].conditions[1].1);
    assert!(f.ir.is_csg());
    assert!(!crate::Formula::compile("<t>", "x - 1").unwrap().ir.is_csg());
    // `;` only follows a surface with a where clause.
    let e = crate::Formula::compile("<t>", "x; y where z < 0").unwrap_err();
    assert_eq!(e.diagnostic.message, "expected end of formula, found ';'");
    let e = crate::Formula::compile("<t>", "x where y").unwrap_err();
    assert_eq!(e.diagnostic.message, "expected '<' or '>', found end of formula");
    let e = crate::Formula::compile("<t>", "where = 1; x").unwrap_err();
    assert_eq!(e.diagnostic.message, "cannot define 'where': the name is reserved");
}
