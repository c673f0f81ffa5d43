//! The WGSL pieces every field source shares: the op library of each
//! number domain (the same `op_*`-style names, `s_`, `ia_` and `ra_`
//! prefixes), constants written as f32 enclosures, and the template splicer.

pub(crate) mod template;

/// The `eval` kernel's bind group table, for the device that binds it.
pub(crate) use template::{EVAL_BOXES, EVAL_RESULTS, EVAL_UNIFORMS};

use crate::ir::Domain;

/// Source of `domain`'s op library.
pub fn library(domain: Domain) -> &'static str {
    match domain {
        Domain::Scalar => include_str!("../../templates/domains/scalar.wgsl"),
        Domain::Interval => include_str!("../../templates/domains/interval.wgsl"),
        Domain::Affine => include_str!("../../templates/domains/affine.wgsl"),
    }
}

/// The op libraries a shader using `domains` needs, each once, in
/// dependency order (scalar helpers first; affine builds on interval).
pub(crate) fn libraries(domains: &[Domain]) -> String {
    libraries_with(domains, true)
}

/// [`libraries`] with the affine library's NaN test on the ranges it reads
/// (`template::AFFINE_RANGE`) on or off: off only in a compiled formula's kernel whose
/// forms cannot overflow within the inputs it admits ([`magnitude`]).
pub(crate) fn libraries_with(domains: &[Domain], guard: bool) -> String {
    let mut need = [true, domains.contains(&Domain::Interval) || domains.contains(&Domain::Affine), domains.contains(&Domain::Affine)];
    need[0] = true; // iso_pow_pos / iso_nan live in the scalar library
    let all = [Domain::Scalar, Domain::Interval, Domain::Affine];
    let text = |d: Domain| match d {
        Domain::Affine => format!("{}\n{}", template::optional(template::AFFINE_RANGE, guard), library(d)),
        _ => library(d).to_string(),
    };
    all.iter().zip(need).filter(|(_, n)| *n).map(|(&d, _)| text(d)).collect::<Vec<_>>().join("\n")
}

/// f32 nearest to `c`, and the f32 interval enclosing it. lavapipe flushes
/// subnormal f32 to zero in arithmetic, so a constant below the smallest
/// normal f32 in magnitude is enclosed by normal ends, [0, 2^-126] or its
/// negative: an end the device reads as 0 could exclude the constant
/// (`x / 1e-40` was enclosed by [f32::MAX, inf] for x near 0.5 before).
pub(crate) fn f32_enclosure(c: f64) -> (f32, f32, f32) {
    let n = c as f32;
    let tiny = f64::from(f32::MIN_POSITIVE);
    if c != 0.0 && c.abs() < tiny {
        return if c > 0.0 { (n, 0.0, f32::MIN_POSITIVE) } else { (n, -f32::MIN_POSITIVE, 0.0) };
    }
    let (mut lo, mut hi) = (n, n);
    if (n as f64) > c {
        lo = n.next_down();
    } else if (n as f64) < c {
        hi = n.next_up();
    }
    (n, lo, hi)
}

/// `ra_from_ia` of a finite, non-empty interval worked out on the host in
/// the device's f32 steps: the form's centre and error term.
fn affine_of(lo: f32, hi: f32) -> Option<(f32, f32)> {
    if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
        return None;
    }
    let d = 0.5 * (hi - lo);
    Some((lo + d, d))
}

/// A literal's affine form, `ra_from_ia` of its enclosing f32 interval
/// worked out here (`affine_of`): a `ra_from_ia` per literal was a sizeable
/// part of lavapipe's pipeline creation for a formula with many literals
/// (the RAA op library's helpers are inlined at every use).
pub(crate) fn affine_literal(lo: f32, hi: f32) -> String {
    match affine_of(lo, hi) {
        Some((c, d)) => format!("vec3<f32>({}, 0.0, {})", lit(c), lit(d)),
        None => format!("ra_from_ia(vec2<f32>({}, {}))", lit(lo), lit(hi)),
    }
}

/// `a / c` for a literal `c` in an inclusion domain, as the product with
/// `1 / c` that the domain's division takes for a divisor without 0
/// (`ia_div`, `ra_div`), its reciprocal worked out here in the same f32
/// steps: the same value, without the division's other cases, which
/// lavapipe compiles at every use (a sixth of `@creature`'s RAA pipeline,
/// 48 divisions by its blend radii). `None`: the scalar domain (a plain
/// division), a divisor whose enclosure holds 0, or one whose reciprocal
/// is not a finite f32.
pub(crate) fn divide_by_literal(domain: Domain, a: &str, c: f64) -> Option<String> {
    let (n, lo, hi) = f32_enclosure(c);
    match domain {
        Domain::Scalar => None,
        Domain::Interval => {
            let (lo, hi) = if lo != hi { (lo, hi) } else { (n, n) };
            // A reciprocal past f32 (a divisor below 2^-128) has no WGSL literal.
            let (r_lo, r_hi) = (1.0 / hi, 1.0 / lo);
            let usable = (lo > 0.0 || hi < 0.0) && r_lo.is_finite() && r_hi.is_finite();
            usable.then(|| format!("ia_mul({a}, vec2<f32>({}, {}))", lit(r_lo), lit(r_hi)))
        }
        Domain::Affine => {
            // ra_div: the divisor's form, its range (its radius is d), the
            // reciprocal's form.
            let (c, d) = if lo != hi { affine_of(lo, hi)? } else { (n, 0.0) };
            let (lo, hi) = (c - d, c + d);
            if !(lo > 0.0 || hi < 0.0) {
                return None;
            }
            let (c, d) = affine_of(1.0 / hi, 1.0 / lo)?;
            Some(format!("ra_mul({a}, vec3<f32>({}, 0.0, {}))", lit(c), lit(d)))
        }
    }
}

pub(crate) fn lit(c: f32) -> String {
    let s = format!("{c:?}");
    if s.contains(['.', 'e', 'E']) { s } else { format!("{s}.0") }
}


#[cfg(test)]
mod tests {
    use super::Domain;

    /// A constant's f32 ends enclose it, and are normal f32 (lavapipe
    /// flushes subnormals to zero): a tiny constant gets [0, 2^-126].
    #[test]
    fn constant_enclosures_have_normal_ends() {
        for c in [0.3, -7.1, 1e-30, 3e38, 1.5, 0.0, -2e-39, 1e-40, 1e-45] {
            let (_, lo, hi) = super::f32_enclosure(c);
            assert!(f64::from(lo) <= c && c <= f64::from(hi), "{c}: [{lo}, {hi}]");
            for e in [lo, hi] {
                assert!(e == 0.0 || e.is_normal() || e.is_infinite(), "{c}: end {e} is subnormal");
            }
        }
        assert_eq!(super::f32_enclosure(1e-40).1..super::f32_enclosure(1e-40).2, 0.0..f32::MIN_POSITIVE);
    }

    /// The op libraries choose with `select`, never branch: lavapipe runs
    /// both sides of a branch anyway, and branches cost its compiler far
    /// more (a branchy affine min and max made `@city`'s RAA compile several
    /// times longer).
    #[test]
    fn the_op_libraries_are_branch_free() {
        let derivative = [include_str!("../../templates/domains/derivative.wgsl"), include_str!("../../templates/domains/derivative_affine.wgsl")];
        let libraries = [Domain::Scalar, Domain::Interval, Domain::Affine].map(super::library);
        for (i, lib) in libraries.iter().chain(&derivative).enumerate() {
            for line in lib.lines().map(|l| l.split("//").next().unwrap_or("")) {
                let words: Vec<&str> = line.split(|c: char| !c.is_alphanumeric() && c != '_').collect();
                for branch in ["if", "else", "switch", "loop", "for", "while"] {
                    assert!(!words.contains(&branch), "library {i} branches: {line}");
                }
            }
        }
    }
}
