//! Analyses of the IR that code generation asks and never the reverse:
//! how large values can get ([`magnitude`]), which are never negative
//! ([`nonneg`]), which are monomials ([`monomials`]).

pub mod magnitude;
pub mod monomials;
pub mod nonneg;
