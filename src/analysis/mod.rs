//! Analyses of the IR that code generation asks and never the reverse:
//! how large values can get ([`magnitude`]), which are never negative
//! ([`nonneg`]).

pub mod magnitude;
pub mod nonneg;
