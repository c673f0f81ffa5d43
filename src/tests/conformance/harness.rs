//! Shared harness of the conformance suites: the checking loop and the
//! backends' interface. The sampling oracle and the rounding margin are in
//! `oracle.rs`, boxes and ray segments in `regions.rs`, the formula tables
//! and generators in `formulas.rs`, the suite's tests (a macro) in
//! `suite.rs`. `src/tests/conformance.rs` runs the suite against the CPU
//! reference (`crate::reference`) and `src/tests/conformance_device.rs`
//! against the generated WGSL on the device; both include this file with
//! `#[path]`.
//!
//! The property checked: for every box (or ray segment), every *finite*
//! value of the strict f64 scalar function ([`reference::eval_scalar`]) at a
//! sample point of it (corners, random interior points, known extrema) lies
//! within the enclosure computed for it, up to [`margin`]. An empty
//! enclosure is accepted only when the scalar function is undefined (NaN) at
//! every sample, not counting samples whose definedness rounding could
//! decide (a sqrt / log / pow argument within its error bound of the domain's
//! edge, a division by an exact 0, an overflow). NaN ends of an enclosure
//! mean "unbounded on that side".
#![allow(dead_code)]

#[path = "formulas.rs"]
mod formulas;
#[path = "oracle.rs"]
mod oracle;
#[path = "regions.rs"]
mod regions;
#[path = "suite.rs"]
mod suite;

pub use formulas::*;
pub use oracle::*;
pub use regions::*;
pub use suite::*;

use crate::ir::Domain;
use crate::ir::Ir;
use crate::reference;
use std::fmt::Write;

/// A box as the eval kernel takes it: `[x0, x1, y0, y1, z0, z1, t0, t1]`.
pub type Box8 = [f32; 8];

// ---------------------------------------------------------------- RNG ----

/// xorshift64* — small, seeded, reproducible.
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed (any value; 0 is remapped).
    pub fn new(seed: u64) -> Rng {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
    /// Uniform in 0..n.
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
    /// Log-uniform in [a, b] (a, b > 0).
    pub fn log_range(&mut self, a: f64, b: f64) -> f64 {
        (a.ln() + (b.ln() - a.ln()) * self.unit()).exp()
    }
    /// True with probability p.
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }
    /// ±1.
    pub fn sign(&mut self) -> f64 {
        if self.chance(0.5) { 1.0 } else { -1.0 }
    }
    /// One element of a slice.
    pub fn pick<'a, T>(&mut self, s: &'a [T]) -> &'a T {
        &s[self.below(s.len())]
    }
}

// ------------------------------------------------------------ checking ----

/// The two inclusion algebras.
pub const ALGEBRAS: [Domain; 2] = [Domain::Interval, Domain::Affine];

/// Something that computes enclosures over boxes.
pub trait Backend: Sync {
    /// For messages.
    fn name(&self) -> &'static str;
    /// Precision of its arithmetic.
    fn precision(&self) -> Precision;
    /// Enclosures `[lo, hi]` of `ir` in `domain` over every box (one
    /// dispatch on the device). Empty: lo > hi.
    fn eval(&self, ir: &Ir, domain: Domain, boxes: &[Box8], params: &[f32]) -> Vec<[f64; 2]>;
    /// Enclosures over ray segments lifted as the render kernel lifts them
    /// (IA: the segment's bounding box; RAA: x, y, z affine in the one
    /// symbol e1), with t = [`SEG_TIME`].
    fn eval_segments(&self, ir: &Ir, domain: Domain, segs: &[Seg], params: &[f32]) -> Vec<[f64; 2]>;
}

/// The CPU reference: `reference::eval_interval` / `eval_affine` on the
/// same f32 boxes, each side lifted with `affine_from_interval` like the
/// device's eval kernel does.
pub struct Cpu;

impl Backend for Cpu {
    fn name(&self) -> &'static str {
        "cpu reference"
    }
    fn precision(&self) -> Precision {
        Precision::F64
    }
    fn eval(&self, ir: &Ir, domain: Domain, boxes: &[Box8], params: &[f32]) -> Vec<[f64; 2]> {
        let params: Vec<f64> = params.iter().map(|&p| f64::from(p)).collect();
        boxes
            .iter()
            .map(|b| {
                let iv: [[f64; 2]; 4] = std::array::from_fn(|v| [f64::from(b[2 * v]), f64::from(b[2 * v + 1])]);
                match domain {
                    Domain::Interval => reference::eval_interval(ir, iv, &params),
                    Domain::Affine => {
                        let forms = iv.map(reference::affine_from_interval);
                        reference::affine_range(reference::eval_affine(ir, forms, &params))
                    }
                    Domain::Scalar => unreachable!("not an inclusion algebra"),
                }
            })
            .collect()
    }
    fn eval_segments(&self, ir: &Ir, domain: Domain, segs: &[Seg], params: &[f32]) -> Vec<[f64; 2]> {
        let params: Vec<f64> = params.iter().map(|&p| f64::from(p)).collect();
        let t = f64::from(SEG_TIME);
        segs.iter()
            .map(|s| {
                let s = s.map(f64::from);
                let (sc, sr) = (0.5 * (s[6] + s[7]), 0.5 * (s[7] - s[6]));
                match domain {
                    Domain::Interval => {
                        let b = segment_box(&s);
                        reference::eval_interval(ir, [[b[0], b[1]], [b[2], b[3]], [b[4], b[5]], [t, t]], &params)
                    }
                    Domain::Affine => {
                        let f = |i: usize| [s[i] + s[3 + i] * sc, s[3 + i] * sr, 0.0];
                        reference::affine_range(reference::eval_affine(ir, [f(0), f(1), f(2), [t, 0.0, 0.0]], &params))
                    }
                    Domain::Scalar => unreachable!("not an inclusion algebra"),
                }
            })
            .collect()
    }
}

// ------------------------------------------------------------ checking ----

/// What the enclosures of one check are computed over.
#[derive(Clone, Copy)]
pub enum Regions<'a> {
    /// Boxes, each side an interval.
    Boxes(&'a [Box8]),
    /// Ray segments.
    Segments(&'a [Seg]),
}

impl Regions<'_> {
    fn len(&self) -> usize {
        match self {
            Regions::Boxes(b) => b.len(),
            Regions::Segments(s) => s.len(),
        }
    }
    fn eval(&self, backend: &dyn Backend, case: &Case, d: Domain) -> Vec<[f64; 2]> {
        match self {
            Regions::Boxes(b) => backend.eval(&case.ir, d, b, &case.params),
            Regions::Segments(s) => backend.eval_segments(&case.ir, d, s, &case.params),
        }
    }
    /// Sample points, a box around the region and the magnitudes the inputs
    /// are computed from (for the node scales).
    fn points(&self, i: usize, rng: &mut Rng, ir: &Ir) -> (Vec<[f64; 4]>, Box8, [f64; 4]) {
        match self {
            Regions::Boxes(b) => (sample_points(rng, ir, &b[i]), b[i], [0.0; 4]),
            Regions::Segments(s) => {
                let f = s[i].map(f64::from);
                let b = segment_box(&f).map(|v| v as f32);
                let reach = f[6].abs().max(f[7].abs());
                let mag = [f[0].abs() + f[3].abs() * reach, f[1].abs() + f[4].abs() * reach, f[2].abs() + f[5].abs() * reach, 0.0];
                (segment_points(rng, &s[i]), [b[0], b[1], b[2], b[3], b[4], b[5], SEG_TIME, SEG_TIME], mag)
            }
        }
    }
    fn describe(&self, i: usize) -> String {
        match self {
            Regions::Boxes(b) => format!("box {}", show_box(&b[i])),
            Regions::Segments(s) => {
                let s = s[i];
                format!("segment ({:e}, {:e}, {:e}) + ({:e}, {:e}, {:e})·[{:e}, {:e}] at t = {SEG_TIME}", s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7])
            }
        }
    }
}

/// A formula under test.
pub struct Case {
    /// Short name for messages.
    pub name: String,
    /// The source text.
    pub source: String,
    /// Compiled.
    pub ir: Ir,
    /// Parameter values (f32: the device's uniforms are f32).
    pub params: Vec<f32>,
    /// The domain box of a case from the catalog (its header's `box`).
    pub domain: Option<[f64; 6]>,
}

impl Case {
    /// Compiles `source`; panics on a front-end error (the tables are fixed).
    pub fn new(name: &str, source: &str) -> Case {
        Case::try_new(name, source).unwrap_or_else(|e| panic!("{name}: {e}"))
    }
    /// Compiles `source`.
    pub fn try_new(name: &str, source: &str) -> Result<Case, crate::FormulaError> {
        let f = crate::Formula::compile(name, source)?;
        Ok(Case { name: name.to_string(), source: source.to_string(), ir: f.ir, params: vec![], domain: None })
    }
    /// With parameter values.
    pub fn with_params(mut self, p: &[f32]) -> Case {
        self.params = p.to_vec();
        self
    }
}

fn show_box(b: &Box8) -> String {
    format!("x∈[{:e}, {:e}] y∈[{:e}, {:e}] z∈[{:e}, {:e}] t∈[{:e}, {:e}]", b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7])
}

/// Counters of one check.
#[derive(Debug, Default, Clone, Copy)]
pub struct Stats {
    /// Boxes evaluated (per algebra).
    pub boxes: usize,
    /// Finite samples compared.
    pub samples: usize,
    /// Empty results seen.
    pub empty: usize,
}

impl Stats {
    fn add(&mut self, s: Stats) {
        self.boxes += s.boxes;
        self.samples += s.samples;
        self.empty += s.empty;
    }
}

/// Evaluates `case` on `boxes` in both algebras (one call each) and checks
/// every box against its samples. Returns the failure messages (at most a
/// few per algebra) and counters.
pub fn check(backend: &dyn Backend, case: &Case, boxes: &[Box8], seed: u64) -> (Vec<String>, Stats) {
    check_regions(backend, case, Regions::Boxes(boxes), seed)
}

/// [`check`] over boxes or ray segments.
pub fn check_regions(backend: &dyn Backend, case: &Case, regions: Regions, seed: u64) -> (Vec<String>, Stats) {
    let prec = backend.precision();
    let results: Vec<Vec<[f64; 2]>> = ALGEBRAS.iter().map(|&d| regions.eval(backend, case, d)).collect();
    let params: Vec<f64> = case.params.iter().map(|&p| f64::from(p)).collect();
    let mut rng = Rng::new(seed);
    let mut fails = Vec::new();
    let mut counts = [0usize; 2];
    let mut stats = Stats { boxes: regions.len(), ..Stats::default() };
    for bi in 0..regions.len() {
        let (points, b, inputs) = regions.points(bi, &mut rng, &case.ir);
        let scale = node_scales(&case.ir, &b, &params, inputs);
        let segments = matches!(regions, Regions::Segments(_));
        let exact: Vec<Sample> = if segments { vec![] } else { points.iter().map(|&p| sample(&case.ir, p, &params, &scale, prec, false)).collect() };
        let lifted: Vec<Sample> = points.iter().map(|&p| sample(&case.ir, p, &params, &scale, prec, true)).collect();
        for (k, &domain) in ALGEBRAS.iter().enumerate() {
            let [lo, hi] = results[k][bi];
            let samples = if domain == Domain::Interval && !segments { &exact } else { &lifted };
            if let Some(p) = judge(samples, lo, hi, prec, &mut stats) {
                counts[k] += 1;
                if counts[k] <= 4 {
                    fails.push(format!("[{}] {} `{}` {:?}, {}: {p}", backend.name(), case.name, case.source, domain, regions.describe(bi)));
                }
            }
        }
    }
    for (k, &c) in counts.iter().enumerate() {
        if c > 4 {
            fails.push(format!("[{}] {} {:?}: {} more failing regions", backend.name(), case.name, ALGEBRAS[k], c - 4));
        }
    }
    (fails, stats)
}

/// Compares one enclosure with the samples of its region; the problem, if any.
fn judge(samples: &[Sample], lo: f64, hi: f64, prec: Precision, stats: &mut Stats) -> Option<String> {
    let (lo, hi) = (if lo.is_nan() { f64::NEG_INFINITY } else { lo }, if hi.is_nan() { f64::INFINITY } else { hi });
    // An end that overflowed to the far infinity ([inf, inf]) stands for
    // "beyond the largest finite number": without outward rounding that is
    // all f32 can say about 1e46.
    let (lo, hi) = if lo <= hi { (lo.min(prec.max()), hi.max(-prec.max())) } else { (lo, hi) };
    if lo > hi {
        stats.empty += 1;
        // Only trustworthy samples witness that f is defined: not at the edge
        // of a domain, not past an overflow or a division by an exact 0.
        return samples.iter().find(|s| s.v.is_finite() && !s.marginal && s.err.is_finite()).map(|s| {
            format!("empty enclosure [{lo:e}, {hi:e}], but f({:?}) = {:e} is defined", s.p, s.v)
        });
    }
    samples.iter().filter(|s| s.v.is_finite()).find_map(|s| {
        stats.samples += 1;
        let m = margin(s, lo, hi, prec);
        (s.v < lo - m || s.v > hi + m).then(|| {
            format!("f({:?}) = {:e} escapes the enclosure [{lo:e}, {hi:e}] (margin {m:.3e}, error bound {:.3e})", s.p, s.v, s.err)
        })
    })
}

/// The boxes a Knoll surface is checked on, by both suites: 1000 cells of
/// its own domain and 500 random boxes.
pub fn knoll_boxes(c: &Case, rng: &mut Rng) -> Vec<Box8> {
    let domain = c.domain.unwrap_or_else(|| panic!("{}: not a catalog case, it has no box", c.name));
    let mut b = domain_cells(rng, domain, 1000);
    b.extend(random_boxes(rng, 500));
    b
}

/// Runs `check` over many cases and panics with every failure.
pub fn check_all(backend: &dyn Backend, cases: &[Case], boxes_for: &mut dyn FnMut(&Case, &mut Rng) -> Vec<Box8>, seed: u64) {
    let mut rng = Rng::new(seed);
    let mut all = Vec::new();
    let mut total = Stats::default();
    for (i, case) in cases.iter().enumerate() {
        let boxes = boxes_for(case, &mut rng);
        let (f, s) = check(backend, case, &boxes, seed.wrapping_add(i as u64 * 7919));
        total.add(s);
        all.extend(f);
    }
    report(backend, cases.len(), "boxes", total, all);
}

/// Runs `check_regions` on `n` random ray segments per case and panics with
/// every failure.
pub fn check_all_segments(backend: &dyn Backend, cases: &[Case], n: usize, seed: u64) {
    let mut rng = Rng::new(seed);
    let mut all = Vec::new();
    let mut total = Stats::default();
    for (i, case) in cases.iter().enumerate() {
        let segs = random_segments(&mut rng, n);
        let (f, s) = check_regions(backend, case, Regions::Segments(&segs), seed.wrapping_add(i as u64 * 7919));
        total.add(s);
        all.extend(f);
    }
    report(backend, cases.len(), "ray segments", total, all);
}

fn report(backend: &dyn Backend, cases: usize, what: &str, total: Stats, all: Vec<String>) {
    eprintln!(
        "[{}] {} formulas, {} {what} x 2 algebras, {} samples compared, {} empty results",
        backend.name(), cases, total.boxes, total.samples, total.empty
    );
    if !all.is_empty() {
        let mut msg = format!("{} conformance failures:\n", all.len());
        for f in &all {
            let _ = writeln!(msg, "  {f}");
        }
        panic!("{msg}");
    }
}

/// Checks that every box gives an empty result in each of `domains`.
pub fn check_all_empty(backend: &dyn Backend, cases: &[Case], boxes: &[Box8], domains: &[Domain]) {
    let mut fails = Vec::new();
    for case in cases {
        for &d in domains {
            let r = backend.eval(&case.ir, d, boxes, &case.params);
            if let Some((i, r)) = r.iter().enumerate().find(|(_, r)| !(r[0] > r[1])) {
                fails.push(format!("[{}] `{}` {d:?}: box {} gives [{:e}, {:e}], expected empty", backend.name(), case.source, show_box(&boxes[i]), r[0], r[1]));
            }
        }
    }
    assert!(fails.is_empty(), "{} formulas are not empty:\n  {}", fails.len(), fails.join("\n  "));
}

/// The emptiness check: every operation applied to an undefined argument
/// is empty, in IA on every kind of box and in RAA on bounded boxes. (On an
/// unbounded box RAA cannot prove `-1 - x^2 < 0`: an unbounded interval
/// becomes the whole-line form (0, 0, inf), which forgets that x^2 ≥ 0, so
/// sqrt(-1 - x^2) is merely unbounded there, a valid if loose enclosure.)
pub fn check_emptiness(backend: &dyn Backend, cases: &[Case], seed: u64) {
    let mut rng = Rng::new(seed);
    let all = random_boxes(&mut rng, 300);
    let bounded: Vec<Kind> = KINDS.iter().copied().filter(|&k| k != Kind::Infinite).collect();
    let finite = random_boxes_of(&mut rng, 300, &bounded);
    check_all_empty(backend, cases, &all, &[Domain::Interval]);
    check_all_empty(backend, cases, &finite, &[Domain::Affine]);
}

// ------------------------------------------------------- self-tests ----

#[cfg(test)]
mod self_tests {
    use super::*;

    /// A backend that is wrong on purpose: it shrinks every enclosure.
    struct Shrunk(f64);
    impl Backend for Shrunk {
        fn name(&self) -> &'static str {
            "shrunk cpu"
        }
        fn precision(&self) -> Precision {
            Precision::F32
        }
        fn eval_segments(&self, ir: &Ir, d: Domain, segs: &[Seg], params: &[f32]) -> Vec<[f64; 2]> {
            Cpu.eval_segments(ir, d, segs, params)
        }
        fn eval(&self, ir: &Ir, d: Domain, boxes: &[Box8], params: &[f32]) -> Vec<[f64; 2]> {
            Cpu.eval(ir, d, boxes, params)
                .into_iter()
                .map(|[lo, hi]| if lo.is_finite() && hi.is_finite() && lo < hi { let c = 0.5 * (lo + hi); let h = 0.5 * (hi - lo) * (1.0 - self.0); [c - h, c + h] } else { [lo, hi] })
                .collect()
        }
    }

    #[test]
    fn the_checker_catches_shrunk_enclosures() {
        let mut rng = Rng::new(5);
        let boxes: Vec<Box8> = (0..200).map(|_| {
            let i = interval(&mut rng, Kind::Wide);
            [i[0], i[1], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
        }).collect();
        for (name, src) in [("cube", "x^3"), ("sin", "sin(x)"), ("sum", "x + 1")] {
            let c = Case::new(name, src);
            let (f, _) = check(&Shrunk(1e-3), &c, &boxes, 1);
            assert!(!f.is_empty(), "{name}: a 0.1% shrink went unnoticed");
            let (f, _) = check(&Cpu, &c, &boxes, 1);
            assert!(f.is_empty(), "{f:?}");
        }
    }

    #[test]
    fn margin_follows_cancellation() {
        let c = Case::new("c", "x^2 - y^2");
        let b = [1000.0, 1000.0, 1000.0, 1000.0, 0.0, 0.0, 0.0, 0.0];
        let s = sample(&c.ir, [1000.0, 1000.0, 0.0, 0.0], &[], &node_scales(&c.ir, &b, &[], [0.0; 4]), Precision::F32, false);
        assert_eq!(s.v, 0.0);
        assert!(s.err > 0.05 && s.err < 1.0, "{}", s.err);
        let b = [1.0, 1.0, 0.5, 0.5, 0.0, 0.0, 0.0, 0.0];
        let s = sample(&c.ir, [1.0, 0.5, 0.0, 0.0], &[], &node_scales(&c.ir, &b, &[], [0.0; 4]), Precision::F64, false);
        assert!(s.err < 1e-14);
    }

    #[test]
    fn rng_is_reproducible() {
        let (mut a, mut b) = (Rng::new(42), Rng::new(42));
        assert!((0..100).all(|_| a.next_u64() == b.next_u64()));
    }
}
