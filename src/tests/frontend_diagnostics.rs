//! Exact rendered text of every front-end diagnostic (lexer, parser,
//! semantic pass, parameter binding), through the library and through the
//! `isotrace check` binary.
//!
//! Each expectation is the whole string `Diagnostic::render` produces without
//! colour, one source line per `concat!` piece so trailing spaces are visible.

use crate::Formula;
use crate::diag::Diagnostic;
use crate::sema::bind_params;
use crate::syntax::parser::{MAX_DEPTH, MAX_SOURCE_BYTES};

/// Compiles `src`, expects an error, and compares its rendering.
#[track_caller]
fn check(src: &str, expected: &str) {
    let err = match Formula::compile("<formula>", src) {
        Ok(_) => panic!("formula {src:?} compiled but an error was expected"),
        Err(e) => e,
    };
    let got = err.diagnostic.render("<formula>", src, false);
    assert_eq!(got, expected, "\nformula {src:?} rendered:\n{got}");
}

/// The error a formula gives, or a panic.
fn error_of(src: &str) -> Diagnostic {
    match Formula::compile("<formula>", src) {
        Ok(_) => panic!("formula of {} bytes compiled but an error was expected", src.len()),
        Err(e) => e.diagnostic,
    }
}

/// Runs `f` on a thread with a 256 KiB stack (a stack overflow aborts the
/// whole test binary, so passing proves there is none).
fn on_small_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new().stack_size(256 * 1024).spawn(f).expect("spawn").join().expect("no panic")
}

// ---- one test per diagnostic -------------------------------------------

#[test]
fn unexpected_token() {
    check("x^2 + * y", concat!(
        "error: expected an expression, found '*'\n",
        "  ┌─ <formula>:1:7\n",
        "  │\n",
        "1 │ x^2 + * y\n",
        "  │       ^ expected an expression\n",
        "\n",
    ));
}

#[test]
fn unexpected_token_on_a_later_line() {
    check("a = 1;\nb = 2;\na +* b", concat!(
        "error: expected an expression, found '*'\n",
        "  ┌─ <formula>:3:4\n",
        "  │\n",
        "3 │ a +* b\n",
        "  │    ^ expected an expression\n",
        "\n",
    ));
}

#[test]
fn unexpected_end() {
    check("x +", concat!(
        "error: expected an expression, found end of formula\n",
        "  ┌─ <formula>:1:4\n",
        "  │\n",
        "1 │ x +\n",
        "  │    ^ expected an expression\n",
        "  │\n",
        "  = the formula ends after an operator\n",
        "\n",
    ));
}

#[test]
fn unexpected_end_after_caret() {
    check("x^", concat!(
        "error: expected an expression, found end of formula\n",
        "  ┌─ <formula>:1:3\n",
        "  │\n",
        "1 │ x^\n",
        "  │   ^ expected an expression\n",
        "  │\n",
        "  = the formula ends after an operator\n",
        "\n",
    ));
}

#[test]
fn unclosed_parenthesis() {
    check("(x + y", concat!(
        "error: unbalanced parenthesis: expected ')', found end of formula\n",
        "  ┌─ <formula>:1:7\n",
        "  │\n",
        "1 │ (x + y\n",
        "  │ -     ^ expected ')'\n",
        "  │ │     \n",
        "  │ this '(' is never closed\n",
        "\n",
    ));
}

#[test]
fn unclosed_parenthesis_before_semicolon() {
    check("a = (x + 1; a", concat!(
        "error: unbalanced parenthesis: expected ')', found ';'\n",
        "  ┌─ <formula>:1:11\n",
        "  │\n",
        "1 │ a = (x + 1; a\n",
        "  │     -     ^ expected ')'\n",
        "  │     │      \n",
        "  │     this '(' is never closed\n",
        "\n",
    ));
}

#[test]
fn unclosed_call() {
    check("sin(x", concat!(
        "error: unbalanced parenthesis: expected ')', found end of formula\n",
        "  ┌─ <formula>:1:6\n",
        "  │\n",
        "1 │ sin(x\n",
        "  │    - ^ expected ')'\n",
        "  │    │ \n",
        "  │    this '(' is never closed\n",
        "\n",
    ));
}

#[test]
fn unmatched_close_parenthesis() {
    check("x + y)", concat!(
        "error: unbalanced parenthesis: ')' without a matching '('\n",
        "  ┌─ <formula>:1:6\n",
        "  │\n",
        "1 │ x + y)\n",
        "  │      ^ no '(' before this\n",
        "\n",
    ));
}

#[test]
fn unmatched_close_parenthesis_at_start() {
    check(")", concat!(
        "error: unbalanced parenthesis: ')' without a matching '('\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ )\n",
        "  │ ^ no '(' before this\n",
        "\n",
    ));
}

#[test]
fn empty_group() {
    check("()", concat!(
        "error: expected an expression, found ')'\n",
        "  ┌─ <formula>:1:2\n",
        "  │\n",
        "1 │ ()\n",
        "  │  ^ expected an expression\n",
        "\n",
    ));
}

#[test]
fn unknown_function_did_you_mean() {
    check("sinn(x)", concat!(
        "error: unknown function 'sinn'\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ sinn(x)\n",
        "  │ ^^^^ not a function\n",
        "  │\n",
        "  = did you mean 'sin', 'sinh' or 'sign'?\n",
        "\n",
    ));
}

#[test]
fn unknown_function_alias() {
    check("ln(x)", concat!(
        "error: unknown function 'ln'\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ ln(x)\n",
        "  │ ^^ not a function\n",
        "  │\n",
        "  = did you mean 'log'?\n",
        "\n",
    ));
}

#[test]
fn unknown_function_prefix() {
    check("cosine(x)", concat!(
        "error: unknown function 'cosine'\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ cosine(x)\n",
        "  │ ^^^^^^ not a function\n",
        "  │\n",
        "  = did you mean 'cone' or 'cos'?\n",
        "\n",
    ));
}

#[test]
fn unknown_function_no_suggestion() {
    check("foo(x)", concat!(
        "error: unknown function 'foo'\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ foo(x)\n",
        "  │ ^^^ not a function\n",
        "  │\n",
        "  = functions: sqrt exp log sin cos tan atan sinh cosh tanh abs sign floor pow atan2 min max clamp mix\n",
        "  = for a product write `foo*(...)`\n",
        "\n",
    ));
}

#[test]
fn variable_called_as_function() {
    check("x(2)", concat!(
        "error: 'x' is not a function\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ x(2)\n",
        "  │ ^ called here\n",
        "  │\n",
        "  = for a product write `x*(...)`\n",
        "\n",
    ));
}

#[test]
fn definition_called_as_function() {
    check("a = 1; a(x)", concat!(
        "error: 'a' is not a function\n",
        "  ┌─ <formula>:1:8\n",
        "  │\n",
        "1 │ a = 1; a(x)\n",
        "  │        ^ called here\n",
        "  │\n",
        "  = for a product write `a*(...)`\n",
        "\n",
    ));
}

#[test]
fn constant_called_as_function() {
    check("pi(2)", concat!(
        "error: 'pi' is not a function\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ pi(2)\n",
        "  │ ^^ called here\n",
        "  │\n",
        "  = for a product write `pi*(...)`\n",
        "\n",
    ));
}

#[test]
fn arity_sin() {
    check("sin(x,y)", concat!(
        "error: wrong number of arguments to 'sin': expected 1, found 2\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ sin(x,y)\n",
        "  │ ^^^^^^^^ 2 arguments\n",
        "\n",
    ));
}

#[test]
fn arity_min() {
    check("min(x)", concat!(
        "error: wrong number of arguments to 'min': expected 2 or more, found 1\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ min(x)\n",
        "  │ ^^^^^^ 1 argument\n",
        "\n",
    ));
}

#[test]
fn arity_clamp() {
    check("clamp(x,y)", concat!(
        "error: wrong number of arguments to 'clamp': expected 3, found 2\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ clamp(x,y)\n",
        "  │ ^^^^^^^^^^ 2 arguments\n",
        "\n",
    ));
}

#[test]
fn arity_pow() {
    check("pow(x)", concat!(
        "error: wrong number of arguments to 'pow': expected 2, found 1\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ pow(x)\n",
        "  │ ^^^^^^ 1 argument\n",
        "\n",
    ));
}

#[test]
fn redefinition() {
    check("a = 1; a = 2; a", concat!(
        "error: redefinition of 'a'\n",
        "  ┌─ <formula>:1:8\n",
        "  │\n",
        "1 │ a = 1; a = 2; a\n",
        "  │ -      ^ defined again here\n",
        "  │ │       \n",
        "  │ first defined here\n",
        "\n",
    ));
}

#[test]
fn use_before_definition() {
    check("a = b; b = 1; a", concat!(
        "error: 'b' is used before its definition\n",
        "  ┌─ <formula>:1:5\n",
        "  │\n",
        "1 │ a = b; b = 1; a\n",
        "  │     ^  - defined here\n",
        "  │     │   \n",
        "  │     used here\n",
        "  │\n",
        "  = move the definition above its first use\n",
        "\n",
    ));
}

#[test]
fn self_reference() {
    check("a = a + 1; a", concat!(
        "error: 'a' is used in its own definition\n",
        "  ┌─ <formula>:1:5\n",
        "  │\n",
        "1 │ a = a + 1; a\n",
        "  │ -   ^ used here\n",
        "  │ │    \n",
        "  │ defined here\n",
        "  │\n",
        "  = a definition can only use names defined above it\n",
        "\n",
    ));
}

#[test]
fn reserved_variable() {
    check("x = 1; x", concat!(
        "error: cannot define 'x': the name is reserved\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ x = 1; x\n",
        "  │ ^ reserved name\n",
        "  │\n",
        "  = x y z t w pi e and the function names cannot be redefined\n",
        "\n",
    ));
}

#[test]
fn reserved_alias() {
    check("w = 1; x", concat!(
        "error: cannot define 'w': the name is reserved\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ w = 1; x\n",
        "  │ ^ reserved name\n",
        "  │\n",
        "  = x y z t w pi e and the function names cannot be redefined\n",
        "\n",
    ));
}

#[test]
fn reserved_function() {
    check("sin = 1; sin(x)", concat!(
        "error: cannot define 'sin': the name is reserved\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ sin = 1; sin(x)\n",
        "  │ ^^^ reserved name\n",
        "  │\n",
        "  = x y z t w pi e and the function names cannot be redefined\n",
        "\n",
    ));
}

#[test]
fn reserved_constant() {
    check("pi = 3; pi*x", concat!(
        "error: cannot define 'pi': the name is reserved\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ pi = 3; pi*x\n",
        "  │ ^^ reserved name\n",
        "  │\n",
        "  = x y z t w pi e and the function names cannot be redefined\n",
        "\n",
    ));
}

#[test]
fn invalid_number_exponent() {
    check("1e", concat!(
        "error: invalid number '1e'\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ 1e\n",
        "  │ ^^ not a number\n",
        "  │\n",
        "  = numbers look like 2, 0.5, .5, 1e-3 or 2.5E+4\n",
        "\n",
    ));
}

#[test]
fn invalid_number_exponent_sign() {
    check("2e+ x", concat!(
        "error: invalid number '2e+'\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ 2e+ x\n",
        "  │ ^^^ not a number\n",
        "  │\n",
        "  = numbers look like 2, 0.5, .5, 1e-3 or 2.5E+4\n",
        "\n",
    ));
}

#[test]
fn invalid_number_two_dots() {
    check("1.2.3", concat!(
        "error: invalid number '1.2.3'\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ 1.2.3\n",
        "  │ ^^^^^ not a number\n",
        "  │\n",
        "  = numbers look like 2, 0.5, .5, 1e-3 or 2.5E+4\n",
        "\n",
    ));
}

#[test]
fn invalid_number_dot() {
    check("x + .", concat!(
        "error: invalid number '.'\n",
        "  ┌─ <formula>:1:5\n",
        "  │\n",
        "1 │ x + .\n",
        "  │     ^ not a number\n",
        "  │\n",
        "  = numbers look like 2, 0.5, .5, 1e-3 or 2.5E+4\n",
        "\n",
    ));
}

#[test]
fn empty_string() {
    check("", concat!(
        "error: empty formula\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ \n",
        "  │ ^ expected an expression\n",
        "  │\n",
        "  = a formula is an expression in x, y, z such as `x^2 + y^2 + z^2 - 1`\n",
        "\n",
    ));
}

#[test]
fn empty_whitespace() {
    check("  \n\t ", concat!(
        "error: empty formula\n",
        "  ┌─ <formula>:2:3\n",
        "  │\n",
        "2 │      \n",
        "  │      ^ expected an expression\n",
        "  │\n",
        "  = a formula is an expression in x, y, z such as `x^2 + y^2 + z^2 - 1`\n",
        "\n",
    ));
}

#[test]
fn empty_comment() {
    check("# only a comment", concat!(
        "error: empty formula\n",
        "  ┌─ <formula>:1:17\n",
        "  │\n",
        "1 │ # only a comment\n",
        "  │                 ^ expected an expression\n",
        "  │\n",
        "  = a formula is an expression in x, y, z such as `x^2 + y^2 + z^2 - 1`\n",
        "\n",
    ));
}

#[test]
fn definitions_only() {
    check("a = 1;", concat!(
        "error: expected an expression after the definitions, found end of formula\n",
        "  ┌─ <formula>:1:7\n",
        "  │\n",
        "1 │ a = 1;\n",
        "  │       ^ expected an expression after the definitions\n",
        "  │\n",
        "  = the last part of a formula is the function to draw, without `name =` and `;`\n",
        "\n",
    ));
}

#[test]
fn definition_without_semicolon() {
    check("a = 1", concat!(
        "error: expected ';' after the definition, found end of formula\n",
        "  ┌─ <formula>:1:6\n",
        "  │\n",
        "1 │ a = 1\n",
        "  │      ^ expected ';' after the definition\n",
        "  │\n",
        "  = `a = ...;` defines a name; the formula to draw follows it\n",
        "\n",
    ));
}

#[test]
fn equation_height_field() {
    check("z = x^2 + y^2", concat!(
        "error: expected ';' after the definition, found end of formula\n",
        "  ┌─ <formula>:1:14\n",
        "  │\n",
        "1 │ z = x^2 + y^2\n",
        "  │              ^ expected ';' after the definition\n",
        "  │\n",
        "  = the surface is where the formula is 0: write `z - (...)` to draw `z = ...`\n",
        "\n",
    ));
}

#[test]
fn equation() {
    check("x^2 + y^2 + z^2 = 1", concat!(
        "error: expected an operator or end of formula, found '='\n",
        "  ┌─ <formula>:1:17\n",
        "  │\n",
        "1 │ x^2 + y^2 + z^2 = 1\n",
        "  │                 ^ expected an operator or end of formula\n",
        "  │\n",
        "  = the surface is where the formula is 0: write `lhs - (rhs)` instead of an equation `lhs = rhs`\n",
        "\n",
    ));
}

#[test]
fn trailing_semicolon() {
    check("x;", concat!(
        "error: expected end of formula, found ';'\n",
        "  ┌─ <formula>:1:2\n",
        "  │\n",
        "1 │ x;\n",
        "  │  ^ expected end of formula\n",
        "  │\n",
        "  = only definitions `name = expression;` end with ';'\n",
        "\n",
    ));
}

#[test]
fn implicit_product() {
    check("2x", concat!(
        "error: expected an operator or end of formula, found 'x'\n",
        "  ┌─ <formula>:1:2\n",
        "  │\n",
        "1 │ 2x\n",
        "  │  ^ expected an operator or end of formula\n",
        "  │\n",
        "  = write `*` for a product: `2*x`, not `2x`\n",
        "\n",
    ));
}

#[test]
fn implicit_product_in_group() {
    check("(2x + 1)", concat!(
        "error: expected ')' or an operator, found 'x'\n",
        "  ┌─ <formula>:1:3\n",
        "  │\n",
        "1 │ (2x + 1)\n",
        "  │   ^ expected ')' or an operator\n",
        "  │\n",
        "  = write `*` for a product: `2*x`, not `2x`\n",
        "\n",
    ));
}

#[test]
fn function_without_parentheses() {
    check("sin x", concat!(
        "error: expected an operator or end of formula, found 'x'\n",
        "  ┌─ <formula>:1:5\n",
        "  │\n",
        "1 │ sin x\n",
        "  │     ^ expected an operator or end of formula\n",
        "  │\n",
        "  = arguments go in parentheses: `sin(x)`\n",
        "\n",
    ));
}

#[test]
fn double_star() {
    check("x**2", concat!(
        "error: expected an expression, found '*'\n",
        "  ┌─ <formula>:1:3\n",
        "  │\n",
        "1 │ x**2\n",
        "  │   ^ expected an expression\n",
        "  │\n",
        "  = write `^` for a power: `x^2`, not `x**2`\n",
        "\n",
    ));
}

#[test]
fn unexpected_character() {
    check("x $ y", concat!(
        "error: unexpected character '$'\n",
        "  ┌─ <formula>:1:3\n",
        "  │\n",
        "1 │ x $ y\n",
        "  │   ^ no token starts with this\n",
        "\n",
    ));
}

#[test]
fn absolute_value_bars() {
    check("|x|", concat!(
        "error: unexpected character '|'\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ |x|\n",
        "  │ ^ no token starts with this\n",
        "  │\n",
        "  = write `abs(x)` for |x|\n",
        "\n",
    ));
}

#[test]
fn square_brackets() {
    check("[x]", concat!(
        "error: unexpected character '['\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ [x]\n",
        "  │ ^ no token starts with this\n",
        "  │\n",
        "  = group with `(` and `)`\n",
        "\n",
    ));
}

#[test]
fn comparison() {
    check("x < 1", concat!(
        "error: expected an operator or end of formula, found '<'\n",
        "  ┌─ <formula>:1:3\n",
        "  │\n",
        "1 │ x < 1\n",
        "  │   ^ expected an operator or end of formula\n",
        "  │\n",
        "  = comparisons belong in level-set conditions (`f where g < 0`); the surface itself is where the formula is 0: write `lhs - (rhs)`\n",
        "\n",
    ));
}

#[test]
fn non_ascii() {
    check("x² + y", concat!(
        "error: non-ASCII character '²' (U+00B2) in formula\n",
        "  ┌─ <formula>:1:2\n",
        "  │\n",
        "1 │ x² + y\n",
        "  │  ^ not allowed here\n",
        "  │\n",
        "  = formulas are plain ASCII: write `^2` for ²\n",
        "\n",
    ));
}

#[test]
fn non_ascii_pi() {
    check("π*x", concat!(
        "error: non-ASCII character 'π' (U+03C0) in formula\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ π*x\n",
        "  │ ^ not allowed here\n",
        "  │\n",
        "  = formulas are plain ASCII: write `pi` for π\n",
        "\n",
    ));
}

#[test]
fn non_ascii_in_comment() {
    check("x # café", concat!(
        "error: non-ASCII character 'é' (U+00E9) in formula\n",
        "  ┌─ <formula>:1:8\n",
        "  │\n",
        "1 │ x # café\n",
        "  │        ^ not allowed here\n",
        "  │\n",
        "  = formulas are plain ASCII: use `pi` for π, `*` for ×, `^2` for ²\n",
        "\n",
    ));
}

/// Control characters are shown as their Unicode control pictures (␁, ␡),
/// never raw, so the caret has a column to point at.
#[test]
fn control_character() {
    check("x\u{1} + y", concat!(
        "error: control character U+0001 in formula\n",
        "  ┌─ <formula>:1:2\n",
        "  │\n",
        "1 │ x\u{2401} + y\n",
        "  │  ^ not allowed here\n",
        "  │\n",
        "  = besides printable ASCII only spaces, tabs and line breaks may appear in a formula\n",
        "\n",
    ));
}

#[test]
fn control_character_in_comment() {
    check("x # \u{7f}", concat!(
        "error: control character U+007F in formula\n",
        "  ┌─ <formula>:1:5\n",
        "  │\n",
        "1 │ x # \u{2421}\n",
        "  │     ^ not allowed here\n",
        "  │\n",
        "  = besides printable ASCII only spaces, tabs and line breaks may appear in a formula\n",
        "\n",
    ));
}

#[test]
fn not_finite_log_of_zero() {
    check("log(0)", concat!(
        "error: constant expression evaluates to -infinity\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ log(0)\n",
        "  │ ^^^^^^ not a finite number\n",
        "  │\n",
        "  = constants must be finite and within the f32 range (|c| < 3.4e38)\n",
        "\n",
    ));
}

#[test]
fn not_finite_division_by_zero() {
    check("1/0", concat!(
        "error: constant expression evaluates to infinity\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ 1/0\n",
        "  │ ^^^ not a finite number\n",
        "  │\n",
        "  = constants must be finite and within the f32 range (|c| < 3.4e38)\n",
        "\n",
    ));
}

#[test]
fn not_finite_sqrt_of_negative() {
    check("x + sqrt(-1)", concat!(
        "error: constant expression evaluates to NaN\n",
        "  ┌─ <formula>:1:5\n",
        "  │\n",
        "1 │ x + sqrt(-1)\n",
        "  │     ^^^^^^^^ not a finite number\n",
        "  │\n",
        "  = constants must be finite and within the f32 range (|c| < 3.4e38)\n",
        "\n",
    ));
}

#[test]
fn not_finite_zero_to_negative_power() {
    check("0^-1", concat!(
        "error: constant expression evaluates to infinity\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ 0^-1\n",
        "  │ ^^^^ not a finite number\n",
        "  │\n",
        "  = constants must be finite and within the f32 range (|c| < 3.4e38)\n",
        "\n",
    ));
}

#[test]
fn not_finite_overflow() {
    check("x*10^20^2", concat!(
        "error: constant expression evaluates to infinity\n",
        "  ┌─ <formula>:1:3\n",
        "  │\n",
        "1 │ x*10^20^2\n",
        "  │   ^^^^^^^ not a finite number\n",
        "  │\n",
        "  = constants must be finite and within the f32 range (|c| < 3.4e38)\n",
        "\n",
    ));
}

#[test]
fn not_finite_beyond_f32() {
    check("x + exp(100)", concat!(
        "error: constant expression evaluates to 2.6881e43\n",
        "  ┌─ <formula>:1:5\n",
        "  │\n",
        "1 │ x + exp(100)\n",
        "  │     ^^^^^^^^ beyond the 32-bit float range\n",
        "  │\n",
        "  = constants must be finite and within the f32 range (|c| < 3.4e38)\n",
        "\n",
    ));
}

#[test]
fn number_out_of_f32_range() {
    check("1e39", concat!(
        "error: number 1e39 is too large for a 32-bit float\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ 1e39\n",
        "  │ ^^^^ out of range\n",
        "  │\n",
        "  = the largest 32-bit float is about 3.4e38\n",
        "\n",
    ));
}

#[test]
fn number_out_of_f64_range() {
    check("1e400", concat!(
        "error: number too large for a 32-bit float\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ 1e400\n",
        "  │ ^^^^^ out of range\n",
        "  │\n",
        "  = the largest 32-bit float is about 3.4e38\n",
        "\n",
    ));
}

#[test]
fn function_as_value() {
    check("sin + x", concat!(
        "error: function 'sin' used without arguments\n",
        "  ┌─ <formula>:1:1\n",
        "  │\n",
        "1 │ sin + x\n",
        "  │ ^^^ expected '(' after this\n",
        "  │\n",
        "  = call it: `sin(x)`\n",
        "\n",
    ));
}

#[test]
fn exponent_too_large() {
    check("x^5000", concat!(
        "error: exponent 5000 is too large (the limit is 4096)\n",
        "  ┌─ <formula>:1:3\n",
        "  │\n",
        "1 │ x^5000\n",
        "  │   ^^^^ exponent too large\n",
        "\n",
    ));
}

#[test]
fn negative_exponent_too_large() {
    check("x^-5000", concat!(
        "error: exponent -5000 is too large (the limit is 4096 in absolute value)\n",
        "  ┌─ <formula>:1:3\n",
        "  │\n",
        "1 │ x^-5000\n",
        "  │   ^^^^^ exponent too large\n",
        "\n",
    ));
}

#[test]
fn pow_exponent_too_large() {
    check("pow(x, 1e4)", concat!(
        "error: exponent 10000 is too large (the limit is 4096)\n",
        "  ┌─ <formula>:1:8\n",
        "  │\n",
        "1 │ pow(x, 1e4)\n",
        "  │        ^^^ exponent too large\n",
        "\n",
    ));
}

// ---- limits -------------------------------------------------------------

#[test]
fn formula_too_large() {
    let src = "x + ".repeat(20_000) + "x";
    assert!(src.len() > MAX_SOURCE_BYTES);
    check(&src, "error: formula too large: 80001 bytes (the limit is 65536 bytes)\n\n");
}

#[test]
fn formula_at_the_size_limit_compiles() {
    // 64 KiB exactly: a long left-deep sum (built by a loop in the parser
    // and lowered without recursion by the semantic pass).
    let mut src = "x".to_string();
    while src.len() + 2 <= MAX_SOURCE_BYTES {
        src.push_str("+y");
    }
    assert!(src.len() <= MAX_SOURCE_BYTES);
    let f = Formula::compile("<formula>", &src).expect("compiles");
    assert_eq!(f.ir.degree(), Some(1));
}

#[test]
fn hundred_thousand_nested_parentheses() {
    // Over the size limit: rejected before parsing, on a small stack.
    let d = on_small_stack(|| {
        let src = format!("{}x{}", "(".repeat(100_000), ")".repeat(100_000));
        error_of(&src).render("<formula>", &src, false)
    });
    assert_eq!(d, "error: formula too large: 200001 bytes (the limit is 65536 bytes)\n\n");
    // Unclosed, still over the limit.
    let d = on_small_stack(|| error_of(&"(".repeat(100_000)).message);
    assert_eq!(d, "formula too large: 100000 bytes (the limit is 65536 bytes)");
}

#[test]
fn thirty_thousand_nested_parentheses_hit_the_depth_limit() {
    // Under the size limit, so the parser itself must stop at MAX_DEPTH.
    let (message, span) = on_small_stack(|| {
        let src = format!("{}x{}", "(".repeat(30_000), ")".repeat(30_000));
        assert!(src.len() <= MAX_SOURCE_BYTES);
        let d = error_of(&src);
        (d.message, d.labels[0].0)
    });
    assert_eq!(message, "formula nested too deeply (more than 200 levels)");
    // Points at the first '(' beyond the limit.
    assert_eq!((span.start, span.end), (MAX_DEPTH as u32, MAX_DEPTH as u32 + 1));
}

#[test]
fn nesting_one_beyond_the_limit() {
    let src = format!("{}x{}", "(".repeat(MAX_DEPTH + 1), ")".repeat(MAX_DEPTH + 1));
    let expected = format!(
        concat!(
            "error: formula nested too deeply (more than 200 levels)\n",
            "  ┌─ <formula>:1:201\n",
            "  │\n",
            "1 │ {}\n",
            "  │ {}^ too deep here\n",
            "  │\n",
            "  = name a sub-expression with a definition `a = ...;` to flatten it\n",
            "\n",
        ),
        src,
        " ".repeat(MAX_DEPTH)
    );
    check(&src, &expected);
    // Unary minus and '^' count as levels too.
    let src = format!("{}x", "-".repeat(MAX_DEPTH + 1));
    assert_eq!(error_of(&src).message, "formula nested too deeply (more than 200 levels)");
    let src = format!("x{}", "^x".repeat(MAX_DEPTH + 1));
    assert_eq!(error_of(&src).message, "formula nested too deeply (more than 200 levels)");
}

#[test]
fn deepest_accepted_nesting_fits_a_small_stack() {
    // Every kind of nesting at exactly MAX_DEPTH compiles on 256 KiB.
    let d = MAX_DEPTH;
    let sources = vec![
        format!("{}x{}", "(".repeat(d), ")".repeat(d)),
        format!("{}x{}", "sin(".repeat(d), ")".repeat(d)),
        format!("{}x{}", "max(1, ".repeat(d), ")".repeat(d)),
        format!("{}x{}", "(x + ".repeat(d), ")".repeat(d)),
        format!("{}x", "-".repeat(d)),
        format!("{}x{}", "-(".repeat(d / 2), ")".repeat(d / 2)),
        format!("x{}", "^1".repeat(d)),
    ];
    on_small_stack(move || {
        for s in &sources {
            if let Err(e) = Formula::compile("<formula>", s) {
                panic!("{}", e.diagnostic.message);
            }
        }
    });
}

#[test]
fn long_chains_fit_a_small_stack() {
    // Left-deep trees tens of thousands of levels tall: parse, lowering and
    // dropping the syntax tree must not recurse on them.
    on_small_stack(|| {
        for op in ["+", "-", "*", "/"] {
            let src = vec!["x"; 30_000].join(op);
            Formula::compile("<formula>", &src).expect("compiles");
        }
        let src = format!("min({})", vec!["x"; 30_000].join(","));
        Formula::compile("<formula>", &src).expect("compiles");
    });
}

// ---- --param binding ------------------------------------------------------

fn params(pairs: &[(&str, f64)]) -> Vec<(String, f64)> {
    pairs.iter().map(|(n, v)| (n.to_string(), *v)).collect()
}

#[test]
fn missing_param_value() {
    let src = "x^2 + y^2 - r^2";
    let f = Formula::compile("<formula>", src).unwrap();
    let e = bind_params(&f.ir, &[]).unwrap_err();
    assert_eq!(
        e.render("<formula>", src, false),
        concat!(
            "error: missing value for parameter 'r'\n",
            "  ┌─ <formula>:1:13\n",
            "  │\n",
            "1 │ x^2 + y^2 - r^2\n",
            "  │             ^ free name, so a parameter\n",
            "  │\n",
            "  = give it a value on the command line: --param r=1.0\n",
            "\n",
        )
    );
}

#[test]
fn missing_param_value_that_looks_like_a_variable() {
    let src = "X^2 + y^2 - 1";
    let f = Formula::compile("<formula>", src).unwrap();
    let e = bind_params(&f.ir, &[]).unwrap_err();
    assert_eq!(
        e.render("<formula>", src, false),
        concat!(
            "error: missing value for parameter 'X'\n",
            "  ┌─ <formula>:1:1\n",
            "  │\n",
            "1 │ X^2 + y^2 - 1\n",
            "  │ ^ free name, so a parameter\n",
            "  │\n",
            "  = give it a value on the command line: --param X=1.0\n",
            "  = did you mean 'x'? names are case-sensitive\n",
            "\n",
        )
    );
}

#[test]
fn non_finite_param_value() {
    let src = "x^2 + y^2 - r^2";
    let f = Formula::compile("<formula>", src).unwrap();
    let e = bind_params(&f.ir, &params(&[("r", 1e39)])).unwrap_err();
    assert_eq!(
        e.render("<formula>", src, false),
        concat!(
            "error: value 1e39 of parameter 'r' is not a finite 32-bit float\n",
            "  ┌─ <formula>:1:13\n",
            "  │\n",
            "1 │ x^2 + y^2 - r^2\n",
            "  │             ^ parameter used here\n",
            "  │\n",
            "  = parameter values must be finite and within the f32 range (|v| < 3.4e38)\n",
            "\n",
        )
    );
    assert!(bind_params(&f.ir, &params(&[("r", f64::NAN)])).is_err());
}

#[test]
fn unused_param_warnings() {
    let src = "x^2 + y^2 - r^2";
    let f = Formula::compile("<formula>", src).unwrap();
    // The last value of a repeated parameter wins; each unused name warns once.
    let (values, warnings) =
        bind_params(&f.ir, &params(&[("r", 1.0), ("rr", 2.0), ("q", 3.0), ("r", 1.5), ("q", 4.0)])).unwrap();
    assert_eq!(values, vec![1.5]);
    let rendered: Vec<String> = warnings.iter().map(|w| w.render("<formula>", src, false)).collect();
    assert_eq!(
        rendered,
        vec![
            concat!(
                "warning: parameter 'rr' is given with --param but the formula does not use it\n",
                " = did you mean 'r'?\n",
                "\n",
            ),
            concat!(
                "warning: parameter 'q' is given with --param but the formula does not use it\n",
                " = the formula's parameters: r\n",
                "\n",
            ),
        ]
    );
    let f = Formula::compile("<formula>", "x - 1").unwrap();
    let (values, warnings) = bind_params(&f.ir, &params(&[("r", 1.0)])).unwrap();
    assert!(values.is_empty());
    assert_eq!(
        warnings[0].render("<formula>", "x - 1", false),
        concat!(
            "warning: parameter 'r' is given with --param but the formula does not use it\n",
            " = the formula has no parameters\n",
            "\n",
        )
    );
}

#[test]
fn params_bind_in_order_of_first_use() {
    let f = Formula::compile("<formula>", "k = b*x; a*k + b + c").unwrap();
    let names: Vec<&str> = f.ir.params.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["b", "a", "c"]);
    let (values, warnings) = bind_params(&f.ir, &params(&[("a", 1.0), ("b", 2.0), ("c", 3.0)])).unwrap();
    assert_eq!(values, vec![2.0, 1.0, 3.0]);
    assert!(warnings.is_empty());
}
