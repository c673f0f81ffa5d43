//! The pixel record every traversal's kernel writes
//! (`templates/shared/pixels.wgsl`) and what the host makes of it:
//! [`Frame`] pixels (decoded, for images and tests) or a [`PackedFrame`]
//! (the records themselves, decoded on access, as a viewer would keep
//! them), each with the frame statistics gathered in the same pass. Also
//! the per-ray statistics word of sphere tracing ([`RayStats`]).

use super::{Frame, PixelOut, Stats, StatsAcc, Status};
use crate::layout::{STATUS_HIT, STATUS_UNRESOLVED};
use bytemuck::{Pod, Zeroable};
use std::mem::MaybeUninit;

/// The words every pixel writes (`pixels[idx]` in pixels.wgsl): colour with
/// the status in its top bits, and work.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Head {
    color: u32,
    info: u32,
}

/// The words only hits and unresolved pixels write (`pixels[n + idx]`):
/// the octahedral normal and the depth.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Tail {
    normal: u32,
    depth: f32,
}

impl Head {
    /// A head of its two words as the kernel writes them.
    pub fn from_words([color, info]: [u32; 2]) -> Head {
        Head { color, info }
    }

    fn status(&self) -> Status {
        match self.color >> 30 {
            STATUS_HIT => Status::Hit,
            STATUS_UNRESOLVED => Status::Unresolved,
            _ => Status::Miss,
        }
    }

    /// The statistics' view of the record: (evaluations, depth level,
    /// status code).
    #[inline]
    fn work(&self) -> (u32, u32, u32) {
        (self.info & 0xffff, (self.info >> 16) & 0x1f, self.color >> 30)
    }
}

impl Tail {
    /// What a miss's tail means (the kernels do not write it): no normal, no depth.
    const MISS: Tail = Tail { normal: 0, depth: f32::INFINITY };

    /// A tail of its two words as the kernel writes them.
    pub fn from_words([normal, depth]: [u32; 2]) -> Tail {
        Tail { normal, depth: f32::from_bits(depth) }
    }
}

/// One pixel's whole record: its head, and its tail or, for a miss,
/// `Tail::MISS`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Record {
    head: Head,
    tail: Tail,
}

impl Record {
    /// The record of a head and the tail stored beside it, which a miss
    /// never wrote: whatever an earlier frame left there is not read.
    #[inline]
    pub fn new(head: Head, tail: &Tail) -> Record {
        let tail = if head.status() == Status::Miss { Tail::MISS } else { *tail };
        Record { head, tail }
    }
}

/// The records of a dispatch (or a frame) in the kernel's two planes: the
/// heads of all pixels, then the tails.
#[derive(Debug, Clone, Copy)]
pub struct Planes<'a> {
    heads: &'a [Head],
    tails: &'a [Tail],
}

impl<'a> Planes<'a> {
    /// The planes of `n` pixels' records in the bytes of a kernel's output
    /// (16 bytes a pixel; the output may be longer).
    pub fn of_bytes(bytes: &'a [u8], n: usize) -> Planes<'a> {
        let half = n * std::mem::size_of::<Head>();
        Planes { heads: bytemuck::cast_slice(&bytes[..half]), tails: bytemuck::cast_slice(&bytes[half..2 * half]) }
    }

    /// Pixels.
    pub fn len(&self) -> usize {
        self.heads.len()
    }

    /// Record `i`.
    #[inline]
    pub fn get(&self, i: usize) -> Record {
        Record::new(self.heads[i], &self.tails[i])
    }

    /// Records `range`, as planes of their own.
    pub fn slice(&self, range: std::ops::Range<usize>) -> Planes<'a> {
        Planes { heads: &self.heads[range.clone()], tails: &self.tails[range] }
    }

    /// The records, in order.
    pub fn iter(&self) -> impl Iterator<Item = Record> + 'a {
        self.heads.iter().zip(self.tails).map(|(h, t)| Record::new(*h, t))
    }

    /// Consecutive planes of at most `len` records each.
    fn chunks(&self, len: usize) -> impl Iterator<Item = Planes<'a>> + 'a {
        self.heads.chunks(len).zip(self.tails.chunks(len)).map(|(heads, tails)| Planes { heads, tails })
    }
}

/// Counts `records` in the frame statistics: their heads alone.
pub fn count(records: Planes, acc: &mut StatsAcc) {
    acc.add_records(records.heads, Head::work);
}

/// Writes `f` of every record of a whole frame into `dst`, one slice per
/// core, and returns the records' statistics. With `f` = [`convert`] that is
/// 16 MB in and 48 MB out at 1024² (less: misses' tails are not read); the
/// packed path copies (16 MB out) where it cannot keep the records in place.
pub fn map_all<T: Send>(raw: Planes, dst: &mut [MaybeUninit<T>], f: impl Fn(&Record) -> T + Sync) -> StatsAcc {
    let chunk = chunk_len(raw.len());
    on_cores(raw.chunks(chunk).zip(dst.chunks_mut(chunk)).collect(), |(src, out)| {
        let mut acc = StatsAcc::default();
        for (src, out) in src.chunks(64).zip(out.chunks_mut(64)) {
            for (d, r) in out.iter_mut().zip(src.iter()) {
                d.write(f(&r));
            }
            count(src, &mut acc);
        }
        acc
    })
}

/// The statistics of a whole frame's records, one slice per core.
pub fn count_all(raw: Planes) -> StatsAcc {
    on_cores(raw.chunks(chunk_len(raw.len())).collect(), |src| {
        let mut acc = StatsAcc::default();
        count(src, &mut acc);
        acc
    })
}

/// Records per core's slice: a share of `n` for each core (at most 8), at
/// least 16,384.
fn chunk_len(n: usize) -> usize {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).clamp(1, 8);
    n.div_ceil(threads).max(1 << 14)
}

/// Runs `work` on each job, the first on this thread and the others on
/// scoped threads, and merges their statistics.
fn on_cores<J: Send>(mut jobs: Vec<J>, work: impl Fn(J) -> StatsAcc + Sync) -> StatsAcc {
    if jobs.is_empty() {
        return StatsAcc::default();
    }
    let first = jobs.remove(0);
    let work = &work;
    std::thread::scope(|scope| {
        let handles: Vec<_> = jobs.into_iter().map(|job| scope.spawn(move || work(job))).collect();
        let mut acc = work(first);
        for h in handles {
            acc.merge(h.join().expect("pixel conversion panicked"));
        }
        acc
    })
}

/// A record decoded.
pub fn convert(r: &Record) -> PixelOut {
    let (h, t) = (&r.head, &r.tail);
    let status = h.status();
    let c = |shift: u32| {
        let v = ((h.color >> shift) & 0x3ff) as f32 / 1023.0;
        v * v
    };
    let alpha = if status == Status::Miss { 0.0 } else { 1.0 };
    PixelOut {
        color: [c(0), c(10), c(20), alpha],
        normal: if status == Status::Miss { [0.0; 3] } else { octahedral(t.normal) },
        depth: t.depth,
        evals: h.info & 0xffff,
        level: (h.info >> 16) & 0x1f,
        iso: h.info >> 21,
        status,
    }
}

/// `unpack2x16snorm`.
fn snorm2(v: u32) -> [f32; 2] {
    let c = |x: u16| (x as i16 as f32 / 32767.0).max(-1.0);
    [c(v as u16), c((v >> 16) as u16)]
}

/// The unit vector of an octahedral-encoded normal (two snorm16).
fn octahedral(v: u32) -> [f32; 3] {
    let [mut x, mut y] = snorm2(v);
    let z = 1.0 - x.abs() - y.abs();
    if z < 0.0 {
        (x, y) = ((1.0 - y.abs()) * x.signum(), (1.0 - x.abs()) * y.signum());
    }
    let l = (x * x + y * y + z * z).sqrt();
    if l > 0.0 { [x / l, y / l, z / l] } else { [0.0, 0.0, 1.0] }
}

/// A rendered frame kept as the kernel's records: what a viewer
/// holds before display, without decoding every pixel of a large frame
/// (a cost paid on every frame). Pixels decode on access.
///
/// On a device that maps storage buffers in place (lavapipe) and a frame
/// rendered in one dispatch, the records stay in the kernel's output buffer,
/// mapped, in the kernel's two planes, and are never copied (16 MB at
/// 1024², a copy a frame saved); the next
/// [`crate::gpu::Renderer::render_packed`] into the same frame unmaps that
/// buffer and renders into it again. Otherwise they are copied out, a whole
/// `Record` a pixel.
#[derive(Default)]
pub struct PackedFrame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Statistics, as for [`Frame`].
    pub stats: Stats,
    pub(crate) records: Records,
}

/// Where a [`PackedFrame`]'s records are.
#[derive(Default)]
pub(crate) enum Records {
    /// None yet.
    #[default]
    Empty,
    /// Copied out of the device's memory.
    Copied(Vec<Record>),
    /// In the kernel's output buffer, left mapped (`view` maps `buffer`).
    Mapped { buffer: wgpu::Buffer, view: wgpu::BufferView },
}

impl Records {
    /// Records held, of a frame of `n` pixels.
    fn len(&self, n: usize) -> usize {
        match self {
            Records::Empty => 0,
            Records::Copied(v) => v.len().min(n),
            Records::Mapped { .. } => n,
        }
    }

    /// Record `i` of a frame of `n` pixels (`i` < [`Records::len`]).
    fn get(&self, i: usize, n: usize) -> Record {
        match self {
            Records::Empty => panic!("record {i} of a frame without records"),
            Records::Copied(v) => v[i],
            Records::Mapped { view, .. } => Planes::of_bytes(view, n).get(i),
        }
    }

    /// Gives up the records for the next frame: the copy's memory to reuse,
    /// or the mapped buffer, unmapped so that a kernel can write it again.
    pub(crate) fn take(&mut self) -> (Vec<Record>, Option<wgpu::Buffer>) {
        match std::mem::take(self) {
            Records::Empty => (Vec::new(), None),
            Records::Copied(v) => (v, None),
            Records::Mapped { buffer, view } => {
                drop(view);
                buffer.unmap();
                (Vec::new(), Some(buffer))
            }
        }
    }
}

impl Clone for PackedFrame {
    /// A copy holds its records in host memory.
    fn clone(&self) -> Self {
        let records = Records::Copied((0..self.len()).map(|i| self.record(i)).collect());
        PackedFrame { width: self.width, height: self.height, stats: self.stats.clone(), records }
    }
}

impl std::fmt::Debug for PackedFrame {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kept = if matches!(self.records, Records::Mapped { .. }) { "mapped" } else { "copied" };
        f.debug_struct("PackedFrame").field("width", &self.width).field("height", &self.height).field("records", &kept).field("stats", &self.stats).finish()
    }
}

impl PackedFrame {
    /// Pixels held: width × height once rendered.
    pub fn len(&self) -> usize {
        self.records.len(self.pixels())
    }

    /// Whether the frame holds no pixels.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn pixels(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// Record `i` (row-major, top row first).
    pub fn record(&self, i: usize) -> Record {
        assert!(i < self.len(), "pixel {i} of a {}x{} frame", self.width, self.height);
        self.records.get(i, self.pixels())
    }

    /// Pixel `i` (row-major, top row first), decoded.
    pub fn pixel(&self, i: usize) -> PixelOut {
        convert(&self.record(i))
    }

    /// The whole frame decoded.
    pub fn decode(&self) -> Frame {
        let pixels = match &self.records {
            Records::Mapped { view, .. } => Planes::of_bytes(view, self.pixels()).iter().map(|r| convert(&r)).collect(),
            _ => (0..self.len()).map(|i| self.pixel(i)).collect(),
        };
        Frame { width: self.width, height: self.height, pixels, stats: self.stats.clone() }
    }
}

/// Sphere tracing's per-ray statistics word (`ray_stats` in
/// traverse/sphere/kernel.wgsl): over-relaxation fallbacks (16 bits,
/// saturated), the largest rate of change of f / L seen along the primary
/// ray (a half float without its sign) and whether it exceeded
/// [`crate::layout::LIPSCHITZ_SLACK`] (bit 31, decided on the device in f32).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RayStats {
    /// Summed fallbacks.
    pub fallbacks: u64,
    /// Rays that saw a Lipschitz violation.
    pub violations: u64,
    /// Largest rate seen.
    pub ratio: f64,
}

impl RayStats {
    /// Counts the words of a tile.
    pub fn add(&mut self, words: &[u32]) {
        for &w in words {
            self.fallbacks += (w & 0xffff) as u64;
            self.violations += (w >> 31) as u64;
            self.ratio = self.ratio.max(half_to_f32(((w >> 16) & 0x7fff) as u16) as f64);
        }
    }
}

/// An IEEE half float's value (no NaN handling needed: the kernel writes
/// finite non-negative rates, saturating to +inf).
fn half_to_f32(h: u16) -> f32 {
    let exp = ((h >> 10) & 0x1f) as i32;
    let man = (h & 0x3ff) as f32;
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    sign * match exp {
        0 => man * 2f32.powi(-24),
        31 => f32::INFINITY,
        e => (1.0 + man / 1024.0) * 2f32.powi(e - 15),
    }
}

#[cfg(test)]
mod tests {
    use super::half_to_f32;

    #[test]
    fn half_floats_decode() {
        assert_eq!(half_to_f32(0x3c00), 1.0);
        assert_eq!(half_to_f32(0x4000), 2.0);
        assert_eq!(half_to_f32(0x3e00), 1.5);
        assert_eq!(half_to_f32(0x0001), 2f32.powi(-24));
        assert_eq!(half_to_f32(0x7bff), 65504.0);
    }
}

/// A data-driven field's per-tile statistics (a scene's active primitives
/// per 8×8 tile and whether the tile overflowed to the whole tree), gathered
/// over the rectangles of a frame into the frame's tile grid.
#[derive(Debug, Clone, Default)]
pub struct TileStats {
    tiles_x: u32,
    active: Vec<u32>,
    overflow: u64,
    /// Depth slabs and their views' nodes, summed over tiles with views.
    slabs: u64,
    pruned_nodes: u64,
    /// Tiles with primitives, and those of them that are union or comb tiles.
    listed: u64,
    chain: u64,
}

impl TileStats {
    /// For a `width × height` frame.
    pub fn new(width: u32, height: u32) -> TileStats {
        let tiles_x = width.div_ceil(8);
        TileStats { tiles_x, active: vec![0; (tiles_x * height.div_ceil(8)) as usize], ..Default::default() }
    }

    /// The words (views' length | slabs << 24 | chain << 28, active count) of the tiles of the
    /// rectangle at pixel (x, y) that is `w` pixels wide (x, y multiples of 8).
    pub fn add(&mut self, (x, y, w): (u32, u32, u32), words: &[[u32; 2]]) {
        let rx = w.div_ceil(8);
        for (k, w) in words.iter().enumerate() {
            let (tx, ty) = (x / 8 + k as u32 % rx, y / 8 + k as u32 / rx);
            if let Some(a) = self.active.get_mut((ty * self.tiles_x + tx) as usize) {
                *a = w[1];
            }
            if w[0] == crate::field::scene::SCENE_WHOLE_TREE {
                self.overflow += u64::from(w[1] > crate::field::scene::SCENE_TILE_MAX);
            } else {
                self.slabs += u64::from((w[0] >> 24) & 0xf);
                self.pruned_nodes += u64::from(w[0] & 0xff_ffff);
            }
            self.listed += u64::from(w[1] > 0);
            self.chain += u64::from(w[1] > 0 && w[0] != crate::field::scene::SCENE_WHOLE_TREE && (w[0] >> 28) & 1 == 1);
        }
    }

    /// Writes the summary and the per-tile counts into `stats`.
    pub fn finish(self, stats: &mut Stats) {
        let n = self.active.len().max(1) as f64;
        stats.field.tiles = self.active.len() as u64;
        stats.field.active_mean = self.active.iter().map(|&a| a as f64).sum::<f64>() / n;
        stats.field.active_max = self.active.iter().copied().max().unwrap_or(0);
        stats.field.overflow_tiles = self.overflow;
        stats.field.slabs_mean = self.slabs as f64 / n;
        stats.field.slab_view_mean = self.pruned_nodes as f64 / self.slabs.max(1) as f64;
        stats.field.chain_share = self.chain as f64 / self.listed.max(1) as f64;
        stats.field.tiles_x = self.tiles_x;
        stats.field.tile_active = self.active;
    }
}
