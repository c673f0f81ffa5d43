//! Property tests of the front end.
//!
//! * Arbitrary bytes (lossily decoded), arbitrary printable text and random
//!   token sequences never make `Formula::compile` panic; when token soup
//!   happens to compile, its shaders validate.
//! * Random well-formed expression trees over every operator and function
//!   always compile (or fail cleanly because a constant sub-expression is
//!   not a finite f32), and the eval shader validates with naga in every
//!   domain.
//!
//! Case counts are bounded so the file runs in a few seconds in release.

use crate::Formula;
use crate::ir::Domain;
use crate::validate::validate;
use proptest::prelude::*;

const DOMAINS: [Domain; 3] = [Domain::Scalar, Domain::Interval, Domain::Affine];

/// `cases` cases, or `PROPTEST_CASES` from the environment for a longer run.
fn config(cases: u32) -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(cases);
    ProptestConfig { cases, failure_persistence: None, ..ProptestConfig::default() }
}

/// Compiles; if that succeeds, every eval shader must validate.
#[allow(clippy::result_large_err)] // the error is the library's own type
fn compile_and_validate(src: &str) -> Result<Formula, crate::FormulaError> {
    let f = Formula::compile("<fuzz>", src)?;
    for d in DOMAINS {
        let wgsl = crate::field::compiled::eval_shader(&f.ir, d);
        if let Err(e) = validate(&wgsl) {
            panic!("formula {src:?} in {d:?}:\n{e}");
        }
    }
    Ok(f)
}

/// The diagnostic of a failure must render without panicking and point
/// inside (or just past) the source.
fn check_error(src: &str, e: &crate::FormulaError) {
    for (span, _) in &e.diagnostic.labels {
        assert!(span.start <= span.end && span.end as usize <= src.len(), "{src:?}: span {span:?}");
    }
    let text = e.diagnostic.render("<fuzz>", src, false);
    assert!(text.starts_with("error: "), "{text}");
}

// ---- garbage in -------------------------------------------------------------

const TOKENS: &[&str] = &[
    "x", "y", "z", "t", "w", "pi", "e", "a", "b", "foo", "sin", "sqrt", "log", "pow", "min", "max", "clamp", "mix",
    "atan2", "floor", "(", ")", ",", ";", "=", "+", "-", "*", "/", "^", "0", "1", "2", "2.5", ".5", "1e3", "1e", "1.2.3",
    "1e39", "4097", "#", "\n", " ", "$", "\u{b2}", "\u{1}", "((", "))",
];

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..200)) {
        let src = String::from_utf8_lossy(&bytes);
        if let Err(e) = Formula::compile("<fuzz>", &src) {
            check_error(&src, &e);
        }
    }

    #[test]
    fn arbitrary_text_never_panics(src in "[ -~\t\n]{0,120}") {
        match compile_and_validate(&src) {
            Ok(_) => {}
            Err(e) => check_error(&src, &e),
        }
    }

    #[test]
    fn token_soup_never_panics(
        tokens in prop::collection::vec(prop::sample::select(TOKENS), 0..40),
        spaced in any::<bool>(),
    ) {
        let src = tokens.join(if spaced { " " } else { "" });
        match compile_and_validate(&src) {
            Ok(_) => {}
            Err(e) => check_error(&src, &e),
        }
    }
}

// ---- well-formed formulas ---------------------------------------------------

/// Formula text plus what the generator knows about it.
#[derive(Debug, Clone)]
struct Gen {
    text: String,
    /// No variable occurs in it (so the semantic pass folds it).
    constant: bool,
    /// Safe to use as an operand of any operator without parentheses.
    atomic: bool,
}

fn leaf() -> impl Strategy<Value = Gen> {
    let var = prop::sample::select(vec!["x", "y", "z", "t", "w"])
        .prop_map(|v| Gen { text: v.into(), constant: false, atomic: true });
    let num = prop::sample::select(vec!["0", "1", "2", "3", "0.5", "3.25", ".5", "1e-3", "2.5E+1", "10", "pi", "e"])
        .prop_map(|n| Gen { text: n.into(), constant: true, atomic: true });
    prop_oneof![3 => var, 2 => num]
}

fn paren(g: &Gen) -> String {
    if g.atomic { g.text.clone() } else { format!("({})", g.text) }
}

fn call(name: &str, args: &[Gen]) -> Gen {
    let text: Vec<&str> = args.iter().map(|a| a.text.as_str()).collect();
    Gen { text: format!("{name}({})", text.join(", ")), constant: args.iter().all(|a| a.constant), atomic: true }
}

const FUNC1: &[&str] =
    &["sqrt", "exp", "log", "sin", "cos", "tan", "atan", "sinh", "cosh", "tanh", "abs", "sign", "floor"];
const EXPONENTS: &[&str] = &["2", "3", "4", "5", "6", "7", "8", "12", "-1", "-2", "-3", "0", "1", "0.5", "1.5", "2.5", "0.25"];

fn expr() -> impl Strategy<Value = Gen> {
    leaf().prop_recursive(5, 48, 4, |inner| {
        let binary = (inner.clone(), prop::sample::select(vec!["+", "-", "*", "/"]), inner.clone(), any::<(bool, bool)>())
            .prop_map(|(a, op, b, (pa, pb))| {
                // Parentheses are optional: without them the text still
                // parses (differently), which exercises precedence.
                let l = if pa { paren(&a) } else { a.text.clone() };
                let r = if pb { paren(&b) } else { b.text.clone() };
                Gen { text: format!("{l} {op} {r}"), constant: a.constant && b.constant, atomic: false }
            });
        let neg = inner.clone().prop_map(|a| Gen { text: format!("-{}", paren(&a)), constant: a.constant, atomic: false });
        let power = (inner.clone(), prop::sample::select(EXPONENTS)).prop_map(|(a, n)| Gen {
            text: format!("{}^{n}", paren(&a)),
            constant: a.constant,
            atomic: false,
        });
        let f1 = (prop::sample::select(FUNC1), inner.clone()).prop_map(|(f, a)| call(f, &[a]));
        let pow = (inner.clone(), inner.clone(), prop::sample::select(EXPONENTS)).prop_map(|(a, b, n)| {
            // A constant exponent must stay small (integer exponents are
            // limited), so a constant b is replaced by a literal.
            let b = if b.constant { Gen { text: n.into(), constant: true, atomic: true } } else { b };
            call("pow", &[a, b])
        });
        let atan2 = (inner.clone(), inner.clone()).prop_map(|(a, b)| call("atan2", &[a, b]));
        let minmax = (prop::sample::select(vec!["min", "max"]), prop::collection::vec(inner.clone(), 2..=4))
            .prop_map(|(f, args)| call(f, &args));
        let f3 = (prop::sample::select(vec!["clamp", "mix"]), inner.clone(), inner.clone(), inner)
            .prop_map(|(f, a, b, c)| call(f, &[a, b, c]));
        prop_oneof![4 => binary, 1 => neg, 2 => power, 3 => f1, 1 => pow, 1 => atan2, 1 => minmax, 1 => f3]
    })
}

/// Optionally names a sub-formula in a definition, and adds a parameter.
fn program() -> impl Strategy<Value = String> {
    (expr(), prop::option::of(expr()), any::<bool>()).prop_map(|(body, def, param)| {
        let mut s = String::new();
        let mut body = body.text;
        if let Some(d) = def {
            s.push_str(&format!("k = {};\n", d.text));
            body = format!("k * ({body})");
        }
        if param {
            body = format!("({body}) - radius");
        }
        s.push_str(&body);
        s
    })
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn well_formed_formulas_compile_and_validate(src in program()) {
        match compile_and_validate(&src) {
            Ok(f) => {
                prop_assert!(f.ir.live().len() <= f.ir.nodes.len());
                // The normalised form is itself a formula that compiles to
                // the same number of operations.
                let again = Formula::compile("<normalized>", &f.normalized());
                let again = again.unwrap_or_else(|e| panic!("normalized form of {src:?}: {e}"));
                prop_assert_eq!(again.ir.live().len(), f.ir.live().len(), "{} vs {}", src, f.normalized());
            }
            Err(e) => {
                let msg = &e.diagnostic.message;
                prop_assert!(msg.starts_with("constant expression evaluates to"), "{:?}: {}", src, e);
            }
        }
    }
}
