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

impl RawPixel {
    fn status(&self) -> Status {
        match self.color >> 30 {
            1 => Status::Hit,
            2 => Status::Unresolved,
            _ => Status::Miss,
        }
    }

    /// Counts this pixel in the frame statistics.
    pub(crate) fn count(&self, acc: &mut StatsAcc) {
        acc.add_parts(self.info & 0xffff, (self.info >> 16) & 0x1f, self.status());
    }
}

/// Writes `f` of every record of a whole frame into `dst`, one slice per
/// core, and returns the records' statistics. With `f` = [`convert`] that is
/// 16 MB in and 48 MB out at 1024²; the packed path copies (16 MB out).
pub(crate) fn map_all<T: Send>(raw: &[RawPixel], dst: &mut [MaybeUninit<T>], f: impl Fn(&RawPixel) -> T + Sync) -> StatsAcc {
    if raw.is_empty() {
        return StatsAcc::default();
    }
    let work = |src: &[RawPixel], out: &mut [MaybeUninit<T>]| {
        let mut acc = StatsAcc::default();
        for (d, r) in out.iter_mut().zip(src) {
            r.count(&mut acc);
            d.write(f(r));
        }
        acc
    };
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

/// A record decoded.
pub(crate) fn convert(r: &RawPixel) -> PixelOut {
    let status = r.status();
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
/// holds before display, without decoding 1024² pixels (about 3.5 ms a frame
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
