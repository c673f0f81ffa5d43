//! Host memory for whole frames. A frame's pixels, packed records and
//! encoded image grow with width × height (48 bytes a pixel decoded: a
//! 16384² frame needs 12.9 GB), so these allocations are made fallibly:
//! a refused allocation is an error that names the frame and the memory it
//! needs, never an abort. An optional budget refuses them before the
//! allocator is asked, which makes the failure deterministic (tests) and
//! lets a shared machine cap what one run takes.

use std::sync::atomic::{AtomicU64, Ordering};

/// No budget: only the allocator refuses.
const UNLIMITED: u64 = u64::MAX;

static BUDGET: AtomicU64 = AtomicU64::new(UNLIMITED);

/// Sets the largest frame-sized allocation allowed, in bytes (`None`: no
/// budget). Process-wide: every renderer and encoder checks it.
pub fn set_budget(bytes: Option<u64>) {
    BUDGET.store(bytes.unwrap_or(UNLIMITED), Ordering::Relaxed);
}

/// The budget set with [`set_budget`], if any.
pub fn budget() -> Option<u64> {
    Some(BUDGET.load(Ordering::Relaxed)).filter(|&b| b != UNLIMITED)
}

/// A frame-sized allocation that was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("a {width}x{height} frame needs {} of host memory for its {what}{}", human(*bytes), budget.map_or(String::new(), |b| format!(", over the memory budget of {}", human(b))))]
pub struct MemoryError {
    /// Frame width.
    pub width: u32,
    /// Frame height.
    pub height: u32,
    /// Bytes the allocation needs.
    pub bytes: u64,
    /// What it holds (`pixels`, `PNG bytes`, …).
    pub what: &'static str,
    /// The budget that refused it; `None` when the allocator did.
    pub budget: Option<u64>,
}

/// Bytes in decimal units with one decimal: `12.9 GB`, `805.3 MB`.
pub fn human(bytes: u64) -> String {
    let b = bytes as f64;
    match bytes {
        0..1_000 => format!("{bytes} bytes"),
        1_000..1_000_000 => format!("{:.1} kB", b / 1e3),
        1_000_000..1_000_000_000 => format!("{:.1} MB", b / 1e6),
        _ => format!("{:.1} GB", b / 1e9),
    }
}

/// Checks `bytes` for a `width` × `height` frame's `what` against the
/// budget only (for data an encoder allocates in several parts).
pub fn check(bytes: u64, (width, height): (u32, u32), what: &'static str) -> Result<(), MemoryError> {
    match budget() {
        Some(b) if bytes > b => Err(MemoryError { width, height, bytes, what, budget: Some(b) }),
        _ => Ok(()),
    }
}

/// Makes room for `n` elements in `v` (cleared first) for a `width` ×
/// `height` frame's `what`, within the budget, without aborting when the
/// allocator refuses.
pub fn reserve<T>(v: &mut Vec<T>, n: usize, (width, height): (u32, u32), what: &'static str) -> Result<(), MemoryError> {
    v.clear();
    let bytes = (n as u64).saturating_mul(std::mem::size_of::<T>() as u64);
    check(bytes, (width, height), what)?;
    v.try_reserve_exact(n).map_err(|_| MemoryError { width, height, bytes, what, budget: None })
}

/// A vector of the first `n` of `items`, allocated fallibly (see [`reserve`]).
pub fn collect<T>(n: usize, size: (u32, u32), what: &'static str, items: impl Iterator<Item = T>) -> Result<Vec<T>, MemoryError> {
    let mut v = Vec::new();
    reserve(&mut v, n, size, what)?;
    v.extend(items.take(n));
    Ok(v)
}

/// Parses a budget as the environment gives it: bytes, or a number with a
/// decimal suffix `k`, `M`, `G` or `T` (`8G` = 8·10⁹ bytes).
pub fn parse_budget(s: &str) -> Option<u64> {
    let s = s.trim();
    let (num, scale) = match s.char_indices().last()? {
        (i, 'k' | 'K') => (&s[..i], 1e3),
        (i, 'M') => (&s[..i], 1e6),
        (i, 'G') => (&s[..i], 1e9),
        (i, 'T') => (&s[..i], 1e12),
        _ => (s, 1.0),
    };
    let v = num.trim().parse::<f64>().ok()? * scale;
    (v.is_finite() && v >= 0.0 && v < 1.8e19).then_some(v as u64)
}
