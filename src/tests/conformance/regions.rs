//! Regions the conformance suites evaluate over: random boxes of many kinds
//! (each side drawn independently), traversal-like cells of a domain box,
//! and ray segments with their sample points.

use super::oracle::specials;
use super::{Box8, Rng};
use std::f64::consts::{FRAC_PI_2, PI};

/// Kinds of intervals the generator draws for each variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Moderate centre, width up to 16.
    Wide,
    /// Relative width 1e-7 .. 1e-3 around an interesting centre.
    Tiny,
    /// [-a, b] with a, b > 0.
    Straddle,
    /// [0, b], [-a, 0] or [0, 0]: the edge of sqrt / log / pow.
    TouchZero,
    /// lo == hi.
    Point,
    /// Near or across a pole π/2 + kπ of tan.
    TanPole,
    /// Near or across an extremum kπ/2 of sin / cos.
    TrigExtremum,
    /// |values| 8 .. 120: where exp, sinh, cosh and powers approach the f32 limit.
    Large,
    /// |values| up to 1e30.
    Huge,
    /// One or both ends infinite.
    Infinite,
    /// 0 < lo < hi.
    Positive,
}

/// Every kind.
pub const KINDS: [Kind; 11] = [
    Kind::Wide, Kind::Tiny, Kind::Straddle, Kind::TouchZero, Kind::Point,
    Kind::TanPole, Kind::TrigExtremum, Kind::Large, Kind::Huge, Kind::Infinite, Kind::Positive,
];

/// An interesting centre: a moderate value, an integer, a multiple of π/2.
fn centre(rng: &mut Rng) -> f64 {
    match rng.below(4) {
        0 => rng.range(-8.0, 8.0),
        1 => rng.below(17) as f64 - 8.0,
        2 => (rng.below(13) as f64 - 6.0) * FRAC_PI_2,
        _ => rng.sign() * rng.log_range(1e-6, 1.0),
    }
}

/// One interval of the given kind, rounded to f32.
pub fn interval(rng: &mut Rng, kind: Kind) -> [f32; 2] {
    let inf = f64::INFINITY;
    let (lo, hi) = match kind {
        Kind::Wide => {
            let c = rng.range(-8.0, 8.0);
            let h = rng.log_range(0.01, 8.0);
            (c - h, c + h)
        }
        Kind::Tiny => {
            let c = centre(rng);
            let h = rng.log_range(1e-7, 1e-3) * c.abs().max(1.0);
            (c - h * rng.unit(), c + h * rng.unit())
        }
        Kind::Straddle => (-rng.log_range(1e-4, 10.0), rng.log_range(1e-4, 10.0)),
        Kind::TouchZero => match rng.below(3) {
            0 => (0.0, rng.log_range(1e-6, 10.0)),
            1 => (-rng.log_range(1e-6, 10.0), 0.0),
            _ => (0.0, 0.0),
        },
        Kind::Point => {
            let c = if rng.chance(0.8) { centre(rng) } else { rng.sign() * rng.log_range(1e-3, 1e6) };
            (c, c)
        }
        Kind::TanPole => {
            let pole = FRAC_PI_2 + (rng.below(11) as f64 - 5.0) * PI;
            let d = rng.log_range(1e-7, 0.5);
            let w = rng.log_range(1e-7, 1.0);
            match rng.below(3) {
                0 => (pole - d - w, pole - d),
                1 => (pole + d, pole + d + w),
                _ => (pole - d, pole + w),
            }
        }
        Kind::TrigExtremum => {
            let m = (rng.below(13) as f64 - 6.0) * FRAC_PI_2;
            let a = if rng.chance(0.3) { 0.0 } else { rng.log_range(1e-7, 1.0) };
            let b = if rng.chance(0.3) { 0.0 } else { rng.log_range(1e-7, 1.0) };
            if rng.chance(0.5) { (m - a, m + b) } else { (m + a.min(b), m + a.max(b)) }
        }
        Kind::Large => {
            let c = rng.sign() * rng.log_range(8.0, 120.0);
            let h = rng.log_range(1e-6, 2.0);
            (c - h * rng.unit(), c + h * rng.unit())
        }
        Kind::Huge => {
            let c = rng.sign() * rng.log_range(1e3, 1e30);
            let h = c.abs() * rng.log_range(1e-7, 1.0);
            (c - h * rng.unit(), c + h * rng.unit())
        }
        Kind::Infinite => match rng.below(3) {
            0 => (-inf, rng.range(-4.0, 4.0)),
            1 => (rng.range(-4.0, 4.0), inf),
            _ => (-inf, inf),
        },
        Kind::Positive => {
            let a = rng.log_range(1e-6, 10.0);
            (a, a + rng.log_range(1e-6, 10.0))
        }
    };
    let (lo, hi) = (lo as f32, hi as f32);
    if lo <= hi { [lo, hi] } else { [hi, lo] }
}

/// `n` boxes, each side of an independently drawn kind.
pub fn random_boxes(rng: &mut Rng, n: usize) -> Vec<Box8> {
    random_boxes_of(rng, n, &KINDS)
}

/// `n` boxes, each side of a kind drawn from `kinds`.
pub fn random_boxes_of(rng: &mut Rng, n: usize, kinds: &[Kind]) -> Vec<Box8> {
    (0..n)
        .map(|_| {
            let mut b = [0.0f32; 8];
            for v in 0..4 {
                let kind = *rng.pick(kinds);
                let i = interval(rng, kind);
                b[2 * v] = i[0];
                b[2 * v + 1] = i[1];
            }
            b
        })
        .collect()
}

/// `n` cells of a traversal-like subdivision of `domain` (x0 x1 y0 y1 z0 z1)
/// at random depths 0..12, with t a point or a short interval.
pub fn domain_cells(rng: &mut Rng, domain: [f64; 6], n: usize) -> Vec<Box8> {
    (0..n)
        .map(|_| {
            let mut b = [0.0f32; 8];
            let depth = rng.below(13) as i32;
            let cells = 2f64.powi(depth);
            for v in 0..3 {
                let (lo, hi) = (domain[2 * v], domain[2 * v + 1]);
                let k = rng.below(cells as usize) as f64;
                let w = (hi - lo) / cells;
                b[2 * v] = (lo + k * w) as f32;
                b[2 * v + 1] = (lo + (k + 1.0) * w) as f32;
            }
            let t = rng.range(-1.0, 4.0);
            b[6] = t as f32;
            b[7] = if rng.chance(0.5) { t as f32 } else { (t + rng.log_range(1e-4, 1.0)) as f32 };
            b
        })
        .collect()
}

/// A ray segment o + d·[s0, s1]: `[ox, oy, oz, dx, dy, dz, s0, s1]`.
pub type Seg = [f32; 8];

/// The time at which segments are evaluated.
pub const SEG_TIME: f32 = 0.7;

/// Bounding box of a segment (x0 x1 y0 y1 z0 z1).
pub(super) fn segment_box(s: &[f64; 8]) -> [f64; 6] {
    let mut b = [0.0; 6];
    for i in 0..3 {
        let (a, c) = (s[i] + s[3 + i] * s[6], s[i] + s[3 + i] * s[7]);
        b[2 * i] = a.min(c);
        b[2 * i + 1] = a.max(c);
    }
    b
}

/// `n` segments: origins at moderate or (a fifth) large coordinates,
/// random directions, lengths from 1e-4 to 4.
pub fn random_segments(rng: &mut Rng, n: usize) -> Vec<Seg> {
    (0..n)
        .map(|_| {
            let big = rng.chance(0.2);
            let mut s = [0.0f32; 8];
            for i in 0..3 {
                s[i] = if big { (rng.sign() * rng.log_range(10.0, 1e5)) as f32 } else { rng.range(-4.0, 4.0) as f32 };
                s[3 + i] = rng.range(-1.0, 1.0) as f32;
            }
            let s0 = if rng.chance(0.5) { 0.0 } else { rng.range(-2.0, 2.0) };
            s[6] = s0 as f32;
            s[7] = (s0 + rng.log_range(1e-4, 4.0)) as f32;
            s
        })
        .collect()
}

/// Sample points of a segment: its ends, random points, and the points where
/// a coordinate crosses one of its special values (0, ±1, kπ/2, integers).
pub(super) fn segment_points(rng: &mut Rng, s: &Seg) -> Vec<[f64; 4]> {
    let s = s.map(f64::from);
    let at = |u: f64| [s[0] + s[3] * u, s[1] + s[4] * u, s[2] + s[5] * u, f64::from(SEG_TIME)];
    let mut ts = vec![s[6], s[7]];
    for _ in 0..8 {
        ts.push(rng.range(s[6], s[7]));
    }
    let b = segment_box(&s);
    for i in 0..3 {
        if s[3 + i] != 0.0 {
            for v in specials(b[2 * i], b[2 * i + 1]) {
                ts.push(((v - s[i]) / s[3 + i]).clamp(s[6], s[7]));
            }
        }
    }
    ts.into_iter().map(at).collect()
}
