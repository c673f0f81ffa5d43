//! The bisection kernel's pixel records and what the host makes of them:
//! [`Frame`] pixels (decoded, for images and tests) or a [`PackedFrame`]
//! (the records themselves, decoded on access, as a viewer would keep
//! them), each with the frame statistics gathered in the same pass.

use super::render::snorm2;
use crate::render::{Frame, PixelOut, Stats, StatsAcc, Status};
use bytemuck::{Pod, Zeroable};
use std::mem::MaybeUninit;

/// One pixel as the render kernel packs it (`pixel_record` in bisect.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct RawPixel {
    color: u32,
    normal: u32,
    depth: f32,
    info: u32,
}

pub(crate) const MISS_PIXEL: PixelOut = PixelOut { color: [0.0; 4], normal: [0.0; 3], depth: f32::INFINITY, evals: 0, level: 0, iso: 0, status: Status::Miss };

/// Converts a whole frame's records on every core (one slice each) and
/// returns their statistics: at 1024² this is 16 MB in, 48 MB out.
pub(crate) fn convert_all(raw: &[RawPixel], dst: &mut [MaybeUninit<PixelOut>]) -> StatsAcc {
    if raw.is_empty() {
        return StatsAcc::default();
    }
    on_every_core(raw, dst, |src, out| {
        let mut acc = StatsAcc::default();
        for (d, r) in out.iter_mut().zip(src) {
            let p = convert(r);
            acc.add(&p);
            d.write(p);
        }
        acc
    })
}

/// Copies a whole frame's records on every core and returns their
/// statistics (the packed path: 16 MB in, 16 MB out at 1024²).
pub(crate) fn copy_all(raw: &[RawPixel], dst: &mut [MaybeUninit<RawPixel>]) -> StatsAcc {
    if raw.is_empty() {
        return StatsAcc::default();
    }
    on_every_core(raw, dst, |src, out| {
        let mut acc = StatsAcc::default();
        for (d, r) in out.iter_mut().zip(src) {
            acc.add_parts(r.info & 0xffff, (r.info >> 16) & 0x1f, status(r));
            d.write(*r);
        }
        acc
    })
}

/// Runs `work` on one slice of `raw` and `dst` per core and merges the
/// statistics.
fn on_every_core<T: Send>(raw: &[RawPixel], dst: &mut [T], work: impl Fn(&[RawPixel], &mut [T]) -> StatsAcc + Sync) -> StatsAcc {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).clamp(1, 8);
    let chunk = raw.len().div_ceil(threads).max(1 << 14);
    std::thread::scope(|scope| {
        let mut jobs: Vec<_> = raw.chunks(chunk).zip(dst.chunks_mut(chunk)).collect();
        let first = jobs.remove(0);
        let work = &work;
        let handles: Vec<_> = jobs.into_iter().map(|(src, out)| scope.spawn(move || work(src, out))).collect();
        let mut acc = work(first.0, first.1);
        for h in handles {
            acc.merge(h.join().expect("pixel conversion panicked"));
        }
        acc
    })
}

fn status(r: &RawPixel) -> Status {
    match r.color >> 30 {
        1 => Status::Hit,
        2 => Status::Unresolved,
        _ => Status::Miss,
    }
}

pub(crate) fn convert(r: &RawPixel) -> PixelOut {
    let status = status(r);
    let c = |shift: u32| {
        let v = ((r.color >> shift) & 0x3ff) as f32 / 1023.0;
        v * v
    };
    let alpha = if status == Status::Miss { 0.0 } else { 1.0 };
    PixelOut {
        color: [c(0), c(10), c(20), alpha],
        normal: if status == Status::Miss { [0.0; 3] } else { octahedral(r.normal) },
        depth: r.depth,
        evals: r.info & 0xffff,
        level: (r.info >> 16) & 0x1f,
        iso: r.info >> 21,
        status,
    }
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

/// A rendered frame kept as the kernel's 16-byte records: what a viewer
/// holds before display, without decoding 1024² pixels (about 4 ms a frame
/// on this machine's two cores). Pixels decode on access.
#[derive(Debug, Clone, Default)]
pub struct PackedFrame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Statistics, as for [`Frame`].
    pub stats: Stats,
    pub(crate) records: Vec<RawPixel>,
}

impl PackedFrame {
    /// Pixel `i` (row-major, top row first), decoded.
    pub fn pixel(&self, i: usize) -> PixelOut {
        convert(&self.records[i])
    }

    /// The whole frame decoded.
    pub fn decode(&self) -> Frame {
        Frame { width: self.width, height: self.height, pixels: self.records.iter().map(convert).collect(), stats: self.stats.clone() }
    }
}
