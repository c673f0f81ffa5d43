//! Frame statistics: the part every traversal has (time, work per pixel,
//! outcomes) and each traversal's own part, gathered from the pixel records
//! in one pass ([`StatsAcc`]).

use super::{Method, PixelOut, Status};

/// Per-frame statistics.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct Stats {
    /// GPU time of the dispatches (timestamp queries when the device has
    /// them, else submit-to-idle wall time), milliseconds.
    pub gpu_ms: f64,
    /// The part of `gpu_ms` spent in a pre-pass over tiles (bisection's tile
    /// pass; 0 without one).
    pub tile_ms: f64,
    /// The part of `gpu_ms` spent in the field source's pre-passes (a
    /// scene's tile lists and pruned trees; 0 for a compiled formula).
    pub field_ms: f64,
    /// Wall time of the whole frame including read-back, milliseconds.
    pub wall_ms: f64,
    /// Pixels in the image.
    pub pixels: u64,
    /// Pixels whose ray found a root.
    pub hits: u64,
    /// Pixels that ran out of iterations (sphere tracing: unconverged).
    pub unresolved: u64,
    /// Mean work per pixel: inclusion evaluations (bisection) or field
    /// evaluations of all rays of the pixel (sphere tracing steps).
    pub evals_mean: f64,
    /// 99th percentile.
    pub evals_p99: u32,
    /// Maximum.
    pub evals_max: u32,
    /// Mean work of hit pixels.
    pub evals_hit_mean: f64,
    /// Mean work of pixels whose ray crosses the domain and misses.
    pub evals_miss_mean: f64,
    /// Number of dispatches (tiles).
    pub dispatches: u32,
    /// The traversal.
    pub method: Method,
    /// The frame was rendered with several isovalues or CSG surfaces: the
    /// pixels' `iso` field says which one each hit is (EXR channel `iso`).
    pub iso_channel: bool,
    /// Bisection's own figures (zero for other traversals).
    pub bisect: BisectStats,
    /// Sphere tracing's own figures (zero for other traversals).
    pub sphere: SphereStats,
    /// A data-driven field's own figures (zero for a compiled formula).
    pub field: FieldStats,
}

/// Statistics of a field source that culls per tile (a scene).
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct FieldStats {
    /// 8×8 tiles in the frame.
    pub tiles: u64,
    /// Mean active primitives per tile (those whose augmented bounding
    /// volume meets the tile's frustum).
    pub active_mean: f64,
    /// Most active primitives in a tile.
    pub active_max: u32,
    /// Tiles with more active primitives than a tile list holds: they
    /// evaluate the whole tree (exact, slower).
    pub overflow_tiles: u64,
    /// Mean depth slabs per tile (Zanni's depth ranges; each slab has a
    /// pruned tree of its own).
    pub slabs_mean: f64,
    /// Mean nodes in a slab's pruned tree: what a step evaluates (a union
    /// or comb tile's pruned tree holds its members, and a comb's operators).
    pub slab_view_mean: f64,
    /// The share of the tiles with primitives that are union or comb tiles:
    /// each ray evaluates only the members whose balls it meets.
    pub chain_share: f64,
    /// Tiles per row of `tile_active`.
    #[serde(skip)]
    pub tiles_x: u32,
    /// Active primitives of every tile, row-major (for `--color overlap`).
    #[serde(skip)]
    pub tile_active: Vec<u32>,
    /// Bisecting a tape with min or max: its per-tile shortening (`None`
    /// for a tape with nothing to shorten).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tape_lists: Option<TapeListStats>,
    /// Bisecting a compiled formula with rerolled min or max loops: the
    /// tiles' term lists (`None` without such loops).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub loop_lists: Option<LoopListStats>,
}

/// How bisection's tile pass listed the terms of a compiled formula's min
/// and max loops per tile (`templates/fields/loop_tiles.wgsl`): summed over
/// the frame's queued tiles.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct LoopListStats {
    /// Tiles with candidate slabs (the per-pixel pass runs on them).
    pub tiles: u64,
    /// Of them, tiles that run their lists (the others run the whole
    /// loops: the work limit came first, or the optimisation is off).
    pub listed: u64,
    /// Terms the listed tiles keep, summed.
    pub kept: u64,
    /// Terms of the listed loops, summed over the same tiles.
    pub whole: u64,
}

impl LoopListStats {
    /// Bytes of the device's counts (words: tiles, listed tiles, kept
    /// terms, whole terms).
    pub const BYTES: u64 = crate::field::compiled::source::TERM_LIST_COUNT_BYTES;

    /// Adds one dispatch's counts.
    pub fn add(&mut self, words: &[u32]) {
        if let [tiles, listed, kept, whole, ..] = *words {
            self.tiles += u64::from(tiles);
            self.listed += u64::from(listed);
            self.kept += u64::from(kept);
            self.whole += u64::from(whole);
        }
    }

    /// Mean terms a listed tile runs.
    pub fn kept_per_tile(&self) -> f64 {
        if self.listed == 0 { 0.0 } else { self.kept as f64 / self.listed as f64 }
    }

    /// The listed loops' terms (what a tile without a list runs).
    pub fn terms(&self) -> u64 {
        self.whole.checked_div(self.listed).unwrap_or(0)
    }
}

/// How bisection's tile pass shortened a tape (`templates/fields/tape_tiles.wgsl`):
/// summed over the frame's queued tiles.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct TapeListStats {
    /// Tiles with candidate slabs (the per-pixel pass runs on them).
    pub tiles: u64,
    /// Of them, tiles that run a shortened list (the others, the whole
    /// tape: the lists' buffer was full, the work limit came first, or the
    /// optimisation is off).
    pub shortened: u64,
    /// Value-program instructions the shortened tiles keep, summed.
    pub kept: u64,
    /// Value-program instructions of the whole tape, summed over the same tiles.
    pub whole: u64,
    /// Blocks of 2 × 2 tiles the block pass took (`tape_tiles.wgsl`).
    pub blocks: u64,
    /// Of them, blocks it shortened the tape for (the others may hold no
    /// surface, or their tiles start from the whole tape).
    pub blocks_shortened: u64,
    /// Value-program instructions the shortened blocks keep, summed.
    pub blocks_kept: u64,
}

impl TapeListStats {
    /// Bytes of the device's counts (words: list words in use, tiles,
    /// shortened tiles, kept instructions, whole instructions, blocks,
    /// shortened blocks, instructions they keep).
    pub const BYTES: u64 = crate::field::tape::source::TAPE_LIST_COUNT_BYTES;

    /// Adds one dispatch's counts.
    pub fn add(&mut self, words: &[u32]) {
        if let [_, tiles, shortened, kept, whole, blocks, blocks_shortened, blocks_kept, ..] = *words {
            self.tiles += u64::from(tiles);
            self.shortened += u64::from(shortened);
            self.kept += u64::from(kept);
            self.whole += u64::from(whole);
            self.blocks += u64::from(blocks);
            self.blocks_shortened += u64::from(blocks_shortened);
            self.blocks_kept += u64::from(blocks_kept);
        }
    }

    /// Mean share of the value program a shortened block keeps (1 with none).
    pub fn block_kept_share(&self, whole: u64) -> f64 {
        if self.blocks_shortened == 0 || whole == 0 { 1.0 } else { self.blocks_kept as f64 / (self.blocks_shortened * whole) as f64 }
    }

    /// Mean share of the value program a shortened tile runs (1 with none).
    pub fn kept_share(&self) -> f64 {
        if self.whole == 0 { 1.0 } else { self.kept as f64 / self.whole as f64 }
    }
}

/// Statistics only bisection has.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct BisectStats {
    /// Bisection depth for a segment across the whole box diagonal.
    pub d_max: u32,
    /// Work lower bound per pixel: a hit needs one
    /// evaluation per level down to an eps cell of its ray's segment
    /// (d_max + 1, with the ray's own d_max), a miss one.
    pub evals_lower_bound: f64,
}

/// Statistics only sphere tracing has.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct SphereStats {
    /// Over-relaxed steps that failed the overlap test and fell back
    /// (summed over the pixels).
    pub sor_fallbacks: u64,
    /// Pixels whose primary ray saw f / L change faster than the distance
    /// between two samples, i.e. evidence that the formula is not an
    /// L-Lipschitz distance bound (surfaces may be missed).
    pub lipschitz_violations: u64,
    /// The largest |Δf| / |Δp| seen along any primary ray (for f itself,
    /// before the division by L): a lower estimate of the Lipschitz bound
    /// the formula needs.
    pub lipschitz_seen: f64,
}

/// The per-pixel statistics of a frame gathered in one pass, so a renderer
/// can collect them while it unpacks pixels (on several threads, merged
/// after). Summing a large frame's pixels in several passes plus a
/// selection for the 99th percentile cost many times more.
#[derive(Debug, Clone)]
pub struct StatsAcc {
    pixels: u64,
    hits: u64,
    unresolved: u64,
    evals_sum: u64,
    evals_max: u32,
    bound_sum: u64,
    hit_sum: u64,
    miss_sum: u64,
    miss_count: u64,
    /// Counts of each evaluation count below `HIST`; the rest listed.
    hist: Vec<u32>,
    over: Vec<u32>,
}

const HIST: usize = 1 << 12;

impl Default for StatsAcc {
    fn default() -> Self {
        StatsAcc {
            pixels: 0,
            hits: 0,
            unresolved: 0,
            evals_sum: 0,
            evals_max: 0,
            bound_sum: 0,
            hit_sum: 0,
            miss_sum: 0,
            miss_count: 0,
            hist: vec![0; HIST],
            over: Vec::new(),
        }
    }
}

impl StatsAcc {
    /// Counts one pixel.
    #[inline]
    pub fn add(&mut self, p: &PixelOut) {
        self.add_parts(p.evals, p.level, p.status);
    }

    /// Counts one pixel given by its evaluations, ray depth and outcome.
    #[inline]
    pub fn add_parts(&mut self, e: u32, level: u32, status: Status) {
        self.pixels += 1;
        self.evals_sum += e as u64;
        self.evals_max = self.evals_max.max(e);
        match self.hist.get_mut(e as usize) {
            Some(c) => *c += 1,
            None => self.over.push(e),
        }
        match status {
            Status::Hit => {
                self.hits += 1;
                self.hit_sum += e as u64;
                self.bound_sum += level as u64 + 1;
            }
            Status::Unresolved => {
                self.unresolved += 1;
                self.bound_sum += 1;
            }
            Status::Miss => {
                self.bound_sum += 1;
                if level > 0 {
                    self.miss_sum += e as u64;
                    self.miss_count += 1;
                }
            }
        }
    }

    /// Counts `items`, each seen by `work` as (evaluations, depth level,
    /// status code in the kernel's packing, `layout::STATUS_*`): the same
    /// sums as [`StatsAcc::add_parts`] for each. Blocks of 64 are summed in
    /// 32-bit locals without branches, and a block whose pixels all share
    /// one count (a background tile's) enters the histogram at once: this
    /// runs near memory speed, where a call per pixel took a noticeable part
    /// of a fast frame (a dependent histogram increment each).
    #[inline]
    pub fn add_records<T>(&mut self, items: &[T], work: impl Fn(&T) -> (u32, u32, u32)) {
        use crate::layout::{STATUS_HIT, STATUS_UNRESOLVED};
        for block in items.chunks(64) {
            let (mut hits, mut unres, mut evals, mut lo, mut hi) = (0u32, 0u32, 0u32, u32::MAX, 0u32);
            let (mut levels, mut hit_evals, mut miss_evals, mut misses) = (0u32, 0u32, 0u32, 0u32);
            for item in block {
                let (e, level, status) = work(item);
                let hit = (status == STATUS_HIT) as u32;
                let un = (status == STATUS_UNRESOLVED) as u32;
                let deep_miss = (1 - hit - un) & (level > 0) as u32;
                hits += hit;
                unres += un;
                evals += e;
                lo = lo.min(e);
                hi = hi.max(e);
                levels += hit * level;
                hit_evals += hit * e;
                miss_evals += deep_miss * e;
                misses += deep_miss;
            }
            let n = block.len() as u64;
            self.pixels += n;
            self.hits += hits as u64;
            self.unresolved += unres as u64;
            self.evals_sum += evals as u64;
            self.evals_max = self.evals_max.max(hi);
            self.bound_sum += n + levels as u64;
            self.hit_sum += hit_evals as u64;
            self.miss_sum += miss_evals as u64;
            self.miss_count += misses as u64;
            if lo == hi && (hi as usize) < HIST {
                self.hist[hi as usize] += block.len() as u32;
                continue;
            }
            for item in block {
                let e = work(item).0;
                match self.hist.get_mut(e as usize) {
                    Some(c) => *c += 1,
                    None => self.over.push(e),
                }
            }
        }
    }

    /// Adds another accumulator's pixels.
    pub fn merge(&mut self, o: StatsAcc) {
        self.pixels += o.pixels;
        self.hits += o.hits;
        self.unresolved += o.unresolved;
        self.evals_sum += o.evals_sum;
        self.evals_max = self.evals_max.max(o.evals_max);
        self.bound_sum += o.bound_sum;
        self.hit_sum += o.hit_sum;
        self.miss_sum += o.miss_sum;
        self.miss_count += o.miss_count;
        for (a, b) in self.hist.iter_mut().zip(&o.hist) {
            *a += b;
        }
        self.over.extend(o.over);
    }

    /// Writes the per-pixel figures into `stats` (the lower bound only
    /// for bisection: sphere tracing has none).
    pub fn finish(mut self, stats: &mut Stats) {
        let n = self.pixels.max(1) as f64;
        stats.pixels = self.pixels;
        stats.hits = self.hits;
        stats.unresolved = self.unresolved;
        stats.evals_mean = self.evals_sum as f64 / n;
        stats.evals_max = self.evals_max;
        if stats.method == Method::Bisect {
            stats.bisect.evals_lower_bound = self.bound_sum as f64 / n;
        }
        let mean = |s: u64, c: u64| if c > 0 { s as f64 / c as f64 } else { 0.0 };
        stats.evals_hit_mean = mean(self.hit_sum, self.hits);
        stats.evals_miss_mean = mean(self.miss_sum, self.miss_count);
        // The 99th percentile: the k-th smallest count, k = ⌊0.99 n⌋.
        stats.evals_p99 = 0;
        if self.pixels > 0 {
            let k = (self.pixels * 99 / 100).min(self.pixels - 1);
            let mut seen = 0u64;
            let mut found = None;
            for (v, &c) in self.hist.iter().enumerate() {
                seen += c as u64;
                if seen > k {
                    found = Some(v as u32);
                    break;
                }
            }
            stats.evals_p99 = found.unwrap_or_else(|| {
                self.over.sort_unstable();
                self.over[(k - seen) as usize]
            });
        }
    }
}

