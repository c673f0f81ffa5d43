//! Exact rendered text of every front-end diagnostic (lexer, parser,
//! semantic pass, parameter binding), through the library and through the
//! `isotrace check` binary.
//!
//! Each expectation is the whole string `Diagnostic::render` produces without
//! colour, one source line per `concat!` piece so trailing spaces are visible.

use std::process::Command;

// ---- through the binary ---------------------------------------------------

/// Runs `isotrace check FORMULA` and returns (exit code, stdout, stderr).
fn run_check(formula: &str) -> (Option<i32>, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_isotrace")).arg("check").arg(formula).output().expect("run isotrace");
    (out.status.code(), String::from_utf8_lossy(&out.stdout).into_owned(), String::from_utf8_lossy(&out.stderr).into_owned())
}

#[track_caller]
fn check_binary(formula: &str, expected_stderr: &str) {
    let (code, stdout, stderr) = run_check(formula);
    assert_eq!(code, Some(1), "exit code for {formula:?}; stderr:\n{stderr}");
    assert_eq!(stdout, "", "nothing on stdout for {formula:?}");
    assert_eq!(stderr, expected_stderr, "\nstderr for {formula:?}:\n{stderr}");
}

#[test]
fn binary_unexpected_token() {
    check_binary(
        "x^2 + * y",
        concat!(
            "error: expected an expression, found '*'\n",
            "  ┌─ <formula>:1:7\n",
            "  │\n",
            "1 │ x^2 + * y\n",
            "  │       ^ expected an expression\n",
            "\n",
        ),
    );
}

#[test]
fn binary_unclosed_parenthesis() {
    check_binary(
        "(x + y",
        concat!(
            "error: unbalanced parenthesis: expected ')', found end of formula\n",
            "  ┌─ <formula>:1:7\n",
            "  │\n",
            "1 │ (x + y\n",
            "  │ -     ^ expected ')'\n",
            "  │ │     \n",
            "  │ this '(' is never closed\n",
            "\n",
        ),
    );
}

#[test]
fn binary_unknown_function() {
    check_binary(
        "sinn(x) + y",
        concat!(
            "error: unknown function 'sinn'\n",
            "  ┌─ <formula>:1:1\n",
            "  │\n",
            "1 │ sinn(x) + y\n",
            "  │ ^^^^ not a function\n",
            "  │\n",
            "  = did you mean 'sin', 'sinh' or 'sign'?\n",
            "\n",
        ),
    );
}

#[test]
fn binary_not_finite() {
    check_binary(
        "x + log(0)",
        concat!(
            "error: constant expression evaluates to -infinity\n",
            "  ┌─ <formula>:1:5\n",
            "  │\n",
            "1 │ x + log(0)\n",
            "  │     ^^^^^^ not a finite number\n",
            "  │\n",
            "  = constants must be finite and within the f32 range (|c| < 3.4e38)\n",
            "\n",
        ),
    );
}

#[test]
fn binary_use_before_definition() {
    check_binary(
        "a = b; b = 1; a*x",
        concat!(
            "error: 'b' is used before its definition\n",
            "  ┌─ <formula>:1:5\n",
            "  │\n",
            "1 │ a = b; b = 1; a*x\n",
            "  │     ^  - defined here\n",
            "  │     │   \n",
            "  │     used here\n",
            "  │\n",
            "  = move the definition above its first use\n",
            "\n",
        ),
    );
}

#[test]
fn binary_accepts_a_good_formula() {
    let (code, stdout, stderr) = run_check("x^2 + y^2 + z^2 - 1");
    assert_eq!(code, Some(0), "stderr:\n{stderr}");
    assert!(!stdout.is_empty());
    assert_eq!(stderr, "");
}
