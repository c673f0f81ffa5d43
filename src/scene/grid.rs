//! Voxel-grid signed distances: a dense grid of samples, read from a `.npy`
//! or an OpenVDB `.vdb` file, evaluated by trilinear interpolation. This is
//! the CPU side of the "grid" primitive (the f64 reference the GPU's 3D
//! texture must reproduce); the scene format, tree and shader wiring live
//! elsewhere.
//!
//! **Layout.** Sample (x, y, z), 0 ≤ x < nx…, sits at world point
//! `origin + (x, y, z) · spacing` and is `values[x + nx·(y + ny·z)]`: x
//! fastest, then y, then z, the order of a 3D texture's texels. A `.npy`
//! array therefore has shape **(nz, ny, nx)** and is indexed `a[z, y, x]`:
//! NumPy's C order makes the last index fastest, so a C-order file is our
//! layout byte for byte (a Fortran-order file is transposed on load).
//!
//! **Interpolation** (written once, [`Grid::eval`], for a WGSL port to copy
//! with 8 texel loads): with `lo = origin`, `hi = origin + (dims − 1)·spacing`,
//! ```text
//! q = clamp(p, lo, hi)                      // the nearest point of the box
//! u = (q − origin) / spacing                // voxel coordinates, in [0, dims − 1]
//! i = clamp(floor(u), 0, dims − 2)          // the cell's low corner (integer)
//! t = clamp(u − i, 0, 1)                    // the fraction within the cell
//! c(a, b, c) = values[(i + (a, b, c))]      // a, b, c ∈ {0, 1}
//! x00 = mix(c000, c100, t.x)  x10 = mix(c010, c110, t.x)
//! x01 = mix(c001, c101, t.x)  x11 = mix(c011, c111, t.x)
//! y0  = mix(x00, x10, t.y)    y1  = mix(x01, x11, t.y)
//! g   = mix(y0, y1, t.z)                    // mix(a, b, t) = a·(1 − t) + b·t, WGSL's mix
//! h   = |p − q|                             // 0 inside the box
//! f   = g ≥ 0 ? sqrt(g² + h²) : g + h
//! ```
//! `mix` in WGSL's form is exact at t = 0 and t = 1, so f equals the samples
//! at the sample points.
//!
//! **Outside the box** the field is extended from the nearest boundary point
//! q. Not by the plain sum g + h everywhere: that overestimates distances
//! (for the samples of |p| − 1 over [−1.5, 1.5]³ it gives 2.052 at
//! (2.5, 1.4, 0), where the distance is 1.865) and its gradient is
//! sqrt(|∇g_tangential|² + 1), up to 1.29 there. Where g(q) ≥ 0,
//! sqrt(g² + h²) instead stays a lower bound of the distance to the grid's
//! zero set whenever g(q) is (for z in the box, |z − p|² ≥ |z − q|² + h²
//! because q is the projection of p on a convex set), and its gradient is
//! at most max(|∇g|, 1). Where g(q) < 0 (the solid is cut by the box) the
//! sum g + h is kept, so the solid ends |g| beyond the face; its gradient
//! bound is counted in [`Grid::lipschitz`]. Both pieces equal h at g = 0,
//! so the field is continuous.
//!
//! **Lipschitz bound** ([`Grid::lipschitz`]): the exact maximum gradient of
//! the interpolant and of the extension (proof in src/scene/grid/bounds.rs).
//! A true SDF sampled finely gives ≈ 1 away from its kinks, but at a kink
//! the interpolant's gradient reaches up to √3: 1.37 for |p| − 1 on 64³
//! samples, from the cells at the centre. [`Grid::lipschitz_above`] gives
//! the bound where the field is at least a level, which is what sphere
//! tracing needs: 1.029 for that grid above 0. A grid of a non-distance
//! field (a density, or a distance times 2) gives a larger bound, which the
//! renderer must use.
//!
//! **Limits**: every dimension ≥ 2 (a cell needs two samples a side), at
//! most [`MAX_GRID_VOXELS`] samples, files of at most [`MAX_GRID_FILE_BYTES`],
//! finite values (stored as f32, the GPU texture's format).

mod bounds;
mod npy;
mod vdb;
mod vdb_layout;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod vdb_tests;

pub use bounds::Cell;

use crate::bounded::{self, ReadError};
use std::path::Path;

/// The most samples a grid may have: 256³ = 16,777,216 (64 MiB as f32), a
/// 3D texture every Vulkan device accepts (maxImageDimension3D ≥ 256 is
/// only the minimum, so larger grids would not load everywhere).
pub const MAX_GRID_VOXELS: u64 = 256 * 256 * 256;

/// The largest grid file read: a 256³ grid of f8 values is 128 MiB, and a
/// `.vdb` of the same grid may hold more (masks, tiles, metadata).
pub const MAX_GRID_FILE_BYTES: u64 = 256 << 20;

/// The file extensions [`load`] reads.
pub const EXTENSIONS: [&str; 2] = ["npy", "vdb"];

/// A dense grid of signed distances (see the module doc for the layout and
/// the interpolation).
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    dims: [u32; 3],
    origin: [f64; 3],
    spacing: f64,
    values: Vec<f32>,
    /// [`Grid::lipschitz`], measured once.
    lipschitz: f64,
}

/// Where a `.npy` grid sits in the world (the file holds only values); a
/// `.vdb` carries its own transform.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// World position of sample (0, 0, 0).
    pub origin: [f64; 3],
    /// Distance between neighbouring samples, > 0.
    pub spacing: f64,
}

/// A grid file that could not be loaded: the file as given and what is
/// wrong (`pebble.npy: voxel (3, 4, 5) is NaN`).
#[derive(Debug, thiserror::Error)]
#[error("{file}: {kind}")]
pub struct GridError {
    /// The path as the caller gave it.
    pub file: String,
    /// What is wrong.
    pub kind: GridErrorKind,
}

/// What is wrong with a grid or its file.
#[derive(Debug, thiserror::Error)]
pub enum GridErrorKind {
    /// The file could not be read, or is larger than [`MAX_GRID_FILE_BYTES`].
    #[error("{0}")]
    Read(#[from] ReadError),
    /// Neither `.npy` nor `.vdb`.
    #[error("unknown grid file type {0}; supported: .npy (NumPy) and .vdb (OpenVDB level set)")]
    UnknownExtension(String),
    /// `.npy` without a placement, or `.vdb` with one.
    #[error("{0}")]
    Placement(&'static str),
    /// The NumPy magic is missing.
    #[error("not a NumPy file (no \\x93NUMPY magic)")]
    NotNpy,
    /// A NumPy format version other than 1.0, 2.0, 3.0.
    #[error("NumPy format version {0}.{1} is not supported; expected 1.0, 2.0 or 3.0")]
    NpyVersion(u8, u8),
    /// The header dictionary is malformed.
    #[error("bad NumPy header: {0}")]
    NpyHeader(String),
    /// Not little-endian f4 or f8.
    #[error("dtype '{0}' is not supported; expected '<f4' or '<f8'")]
    Dtype(String),
    /// Not 3 dimensions; the shape as Python prints it.
    #[error("expected a 3-dimensional array of shape (nz, ny, nx), indexed a[z, y, x], found shape {0}")]
    Shape(String),
    /// Fewer values than the header announces.
    #[error("truncated: the header says {expected} values but the file holds {found}")]
    Truncated {
        /// Values announced.
        expected: u64,
        /// Whole values present.
        found: u64,
    },
    /// Bytes after the announced values.
    #[error("{extra} bytes after the {expected} values the header announces")]
    TrailingBytes {
        /// Values announced.
        expected: u64,
        /// Bytes left over.
        extra: u64,
    },
    /// A dimension below 2.
    #[error("{0} x {1} x {2} voxels: every dimension must be at least 2 (a cell needs two samples a side)")]
    TooSmall(u64, u64, u64),
    /// More than [`MAX_GRID_VOXELS`] samples.
    #[error("{0} x {1} x {2} voxels is above the limit of {MAX_GRID_VOXELS}")]
    TooLarge(u64, u64, u64),
    /// `values` does not hold nx·ny·nz samples.
    #[error("{found} values for {nx} x {ny} x {nz} voxels")]
    ValueCount {
        /// Samples given.
        found: usize,
        /// Dimensions.
        nx: u32,
        /// Dimensions.
        ny: u32,
        /// Dimensions.
        nz: u32,
    },
    /// A NaN, an infinity, or an f8 beyond the f32 range.
    #[error("voxel ({}, {}, {}) is {}", .index[0], .index[1], .index[2], describe_bad(*.value))]
    NotFinite {
        /// (x, y, z).
        index: [u64; 3],
        /// The value as read.
        value: f64,
    },
    /// Spacing not finite and > 0, or origin not finite.
    #[error("{0}")]
    BadPlacement(String),
    /// A `.vdb` this reader cannot turn into a grid (with the reason).
    #[error("{0}")]
    Vdb(String),
}

fn describe_bad(v: f64) -> String {
    if v.is_nan() {
        "NaN".into()
    } else if v.is_infinite() {
        if v > 0.0 { "inf".into() } else { "-inf".into() }
    } else {
        format!("{v:e}, beyond the f32 range")
    }
}

/// Reads the grid file at `path` (`.npy` or `.vdb`, by extension; see
/// [`check_kind`] for the placement). Only a regular file is opened, and
/// the read stops at [`MAX_GRID_FILE_BYTES`] ([`bounded::read_file_bytes`]).
pub fn load(path: &Path, placement: Option<Placement>) -> Result<Grid, GridError> {
    let file = path.display().to_string();
    check_kind(path, placement)?;
    let bytes = bounded::read_file_bytes(path, MAX_GRID_FILE_BYTES).map_err(|e| GridError { file: file.clone(), kind: e.into() })?;
    match placement {
        Some(pl) => Grid::from_npy(&file, &bytes, pl),
        None => Grid::from_vdb(&file, &bytes, None),
    }
}

/// Checks what a grid file's name and placement promise, without reading
/// it: a known extension; a `.npy` holds only values, so `placement` must
/// be given; a `.vdb` has its own voxel size and origin, so it must be
/// `None` (a silent override would hide a mistake in the scene).
pub fn check_kind(path: &Path, placement: Option<Placement>) -> Result<(), GridError> {
    let err = |kind| GridError { file: path.display().to_string(), kind };
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    match (ext.as_deref(), placement) {
        (Some("npy"), None) => Err(err(GridErrorKind::Placement("a .npy file holds only values: the grid's spacing and origin must be given"))),
        (Some("vdb"), Some(_)) => Err(err(GridErrorKind::Placement("a .vdb file has its own voxel size and origin: spacing and origin must not be given"))),
        (Some(e), _) if EXTENSIONS.contains(&e) => Ok(()),
        (Some(e), _) => Err(err(GridErrorKind::UnknownExtension(format!("'.{e}'")))),
        (None, _) => Err(err(GridErrorKind::UnknownExtension("(no extension)".into()))),
    }
}

/// nx·ny·nz when every dimension is ≥ 2 and the count within the limit.
pub(crate) fn check_dims(d: [u64; 3]) -> Result<usize, GridErrorKind> {
    if d.iter().any(|&n| n < 2) {
        return Err(GridErrorKind::TooSmall(d[0], d[1], d[2]));
    }
    let n = (d[0] as u128) * (d[1] as u128) * (d[2] as u128);
    if n > MAX_GRID_VOXELS as u128 {
        return Err(GridErrorKind::TooLarge(d[0], d[1], d[2]));
    }
    Ok(n as usize)
}

impl Grid {
    /// A grid from its samples (layout in the module doc), validated:
    /// dimensions, limits, a finite positive spacing, a finite origin and
    /// finite values. Measures the Lipschitz bound (one pass over the cells).
    pub fn new(dims: [u32; 3], origin: [f64; 3], spacing: f64, values: Vec<f32>) -> Result<Grid, GridErrorKind> {
        let n = check_dims(dims.map(u64::from))?;
        if values.len() != n {
            return Err(GridErrorKind::ValueCount { found: values.len(), nx: dims[0], ny: dims[1], nz: dims[2] });
        }
        check_placement(Placement { origin, spacing }, dims)?;
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            let (nx, ny) = (dims[0] as usize, dims[1] as usize);
            let index = [k % nx, (k / nx) % ny, k / (nx * ny)].map(|c| c as u64);
            return Err(GridErrorKind::NotFinite { index, value: f64::from(values[k]) });
        }
        let mut g = Grid { dims, origin, spacing, values, lipschitz: 0.0 };
        g.lipschitz = g.lipschitz_above(f64::NEG_INFINITY);
        Ok(g)
    }

    /// Samples `f` at every sample point `origin + (x, y, z)·spacing`
    /// (rounded to f32, as stored).
    pub fn from_fn(dims: [u32; 3], origin: [f64; 3], spacing: f64, mut f: impl FnMut([f64; 3]) -> f64) -> Result<Grid, GridErrorKind> {
        check_dims(dims.map(u64::from))?;
        check_placement(Placement { origin, spacing }, dims)?;
        let mut values = Vec::with_capacity(dims.iter().map(|&d| d as usize).product());
        for z in 0..dims[2] {
            for y in 0..dims[1] {
                for x in 0..dims[0] {
                    let p = [x, y, z].map(f64::from);
                    values.push(f([0, 1, 2].map(|k| origin[k] + p[k] * spacing)) as f32);
                }
            }
        }
        Grid::new(dims, origin, spacing, values)
    }

    /// The samples of |p| − `radius` on an n³ grid over [−h, h]³: a test
    /// and example shape.
    ///
    /// # Panics
    /// If n < 2, n > 256, h ≤ 0 or a value is not finite.
    pub fn sphere(n: u32, half_extent: f64, radius: f64) -> Grid {
        let spacing = 2.0 * half_extent / f64::from(n - 1);
        Grid::from_fn([n; 3], [-half_extent; 3], spacing, |p| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - radius)
            .expect("a valid sphere grid")
    }

    /// `examples/pebble.npy`: a 48³ grid, spacing 0.05, origin
    /// (−1.175, −1.175, −1.175), so the samples cover [−1.175, 1.175]³. The
    /// shape: a round box (half extents 0.8, 0.55, 0.35, rounding 0.3) and a
    /// sphere (centre (0.3, 0.2, 0.15), radius 0.5, displaced by
    /// 0.02·sin 6x·sin 6y·sin 6z) joined by a polynomial smooth union of
    /// blend 0.2, sampled exactly. Not an exact distance (the blend and the
    /// bumps bend it): its Lipschitz bound is measured, not assumed.
    pub fn pebble() -> Grid {
        use crate::scene::Shape;
        let rbox = Shape::RoundBox { half: [0.8, 0.55, 0.35], radius: 0.3 };
        Grid::from_fn([48; 3], [-1.175; 3], 0.05, |p| {
            let a = rbox.local_distance(glam::DVec3::from(p));
            let c = [p[0] - 0.3, p[1] - 0.2, p[2] - 0.15];
            let bumps = 0.02 * (6.0 * p[0]).sin() * (6.0 * p[1]).sin() * (6.0 * p[2]).sin();
            let b = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt() - 0.5 + bumps;
            let k = 0.2;
            let h = (k - (a - b).abs()).max(0.0) / k;
            a.min(b) - h * h * k * 0.25
        })
        .expect("a valid pebble grid")
    }

    /// Samples per axis (nx, ny, nz).
    pub fn dims(&self) -> [u32; 3] {
        self.dims
    }

    /// World position of sample (0, 0, 0).
    pub fn origin(&self) -> [f64; 3] {
        self.origin
    }

    /// Distance between neighbouring samples.
    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    /// The samples, x fastest, then y, then z.
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// Sample (x, y, z).
    ///
    /// # Panics
    /// If out of range.
    pub fn value(&self, x: u32, y: u32, z: u32) -> f32 {
        assert!(x < self.dims[0] && y < self.dims[1] && z < self.dims[2], "sample ({x}, {y}, {z}) outside {:?}", self.dims);
        self.values[self.index(x as usize, y as usize, z as usize)]
    }

    fn index(&self, x: usize, y: usize, z: usize) -> usize {
        x + self.dims[0] as usize * (y + self.dims[1] as usize * z)
    }

    /// The box the samples span: [origin, origin + (dims − 1)·spacing].
    pub fn extent(&self) -> ([f64; 3], [f64; 3]) {
        (self.origin, [0, 1, 2].map(|k| self.origin[k] + f64::from(self.dims[k] - 1) * self.spacing))
    }

    /// The field at `p`: the trilinear interpolant inside the box, its
    /// extension outside, written exactly as the module doc's formula.
    pub fn eval(&self, p: [f64; 3]) -> f64 {
        let (lo, hi) = self.extent();
        let q = [0, 1, 2].map(|k| p[k].clamp(lo[k], hi[k]));
        let mut i = [0usize; 3];
        let mut t = [0.0f64; 3];
        for k in 0..3 {
            let u = (q[k] - self.origin[k]) / self.spacing;
            let top = f64::from(self.dims[k] - 2);
            let cell = u.floor().clamp(0.0, top);
            i[k] = cell as usize;
            t[k] = (u - cell).clamp(0.0, 1.0);
        }
        let c = |a: usize, b: usize, d: usize| f64::from(self.values[self.index(i[0] + a, i[1] + b, i[2] + d)]);
        let mix = |a: f64, b: f64, t: f64| a * (1.0 - t) + b * t;
        let x00 = mix(c(0, 0, 0), c(1, 0, 0), t[0]);
        let x10 = mix(c(0, 1, 0), c(1, 1, 0), t[0]);
        let x01 = mix(c(0, 0, 1), c(1, 0, 1), t[0]);
        let x11 = mix(c(0, 1, 1), c(1, 1, 1), t[0]);
        let g = mix(mix(x00, x10, t[1]), mix(x01, x11, t[1]), t[2]);
        let d = [0, 1, 2].map(|k| p[k] - q[k]);
        let h = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if g >= 0.0 { (g * g + h * h).sqrt() } else { g + h }
    }

    /// A bound L on |∇f| everywhere, inside the box and out, measured on
    /// load: the exact maximum over cells of the interpolant's gradient
    /// ([`Cell::max_gradient`]), with the outside extension's (at least 1,
    /// its gradient along the face normal). |f(a) − f(b)| ≤ L·|a − b|, so a
    /// sphere tracer may step f/L.
    pub fn lipschitz(&self) -> f64 {
        self.lipschitz
    }

    /// A bound on |∇f| on the set {f ≥ `level`}: the maximum over the cells
    /// whose largest sample is ≥ `level` (the others lie below it: the
    /// interpolant never exceeds a cell's largest sample), with the outside
    /// extension's. A sphere tracer steps only where f > 0, and the segment
    /// from such a point to the first zero stays in {f ≥ 0}, so
    /// `lipschitz_above(0.0)` is the bound for tracing this field alone; a
    /// tree would pass the lowest value its operators still look at (the
    /// node's range of interest r⁻ lowered by its blend). It leaves out the
    /// kinks deep inside (the centre of a sphere), where the interpolant's
    /// gradient reaches √3. One pass over the cells.
    pub fn lipschitz_above(&self, level: f64) -> f64 {
        bounds::lipschitz_above(self, level)
    }

    /// An axis-aligned box holding {p : f(p) ≤ r} (the primitive's
    /// augmented bounding volume for a range of interest reaching r), or
    /// `None` when that set is empty. One pass over the cells; the proof is
    /// in src/scene/grid/bounds.rs.
    pub fn bounding_box(&self, r: f64) -> Option<crate::scene::roi::Aabb> {
        bounds::bounding_box(self, r)
    }

    /// The grid as a NumPy file: format 1.0, little-endian `<f4`, C order,
    /// shape (nz, ny, nx). [`Grid::from_npy`] reads it back identically.
    pub fn to_npy(&self) -> Vec<u8> {
        npy::write(self)
    }

    /// The same samples at another placement (a `.npy` grid's values read
    /// once, placed by another node): the placement is checked and the
    /// Lipschitz bound measured again, since it depends on the spacing.
    pub fn placed(&self, p: Placement) -> Result<Grid, GridErrorKind> {
        Grid::new(self.dims, p.origin, p.spacing, self.values.clone())
    }

    /// Parses `.npy` bytes; `file` names the file in errors.
    pub fn from_npy(file: &str, bytes: &[u8], placement: Placement) -> Result<Grid, GridError> {
        npy::read(bytes, placement).map_err(|kind| GridError { file: file.to_string(), kind })
    }

    /// Converts an OpenVDB float level set to a dense grid over its active
    /// voxels' bounding box (see the `vdb` module for what is read and
    /// what is refused). `grid_name` picks one grid; `None` needs exactly
    /// one float level set in the file.
    pub fn from_vdb(file: &str, bytes: &[u8], grid_name: Option<&str>) -> Result<Grid, GridError> {
        vdb::read(bytes, grid_name).map_err(|kind| GridError { file: file.to_string(), kind })
    }

    /// The cell with low corner (x, y, z), 0 ≤ x ≤ nx − 2….
    pub fn cell(&self, x: usize, y: usize, z: usize) -> Cell {
        let mut c = [[[0.0; 2]; 2]; 2];
        for (a, plane) in c.iter_mut().enumerate() {
            for (b, row) in plane.iter_mut().enumerate() {
                for (d, v) in row.iter_mut().enumerate() {
                    *v = f64::from(self.values[self.index(x + a, y + b, z + d)]);
                }
            }
        }
        Cell(c)
    }
}

fn check_placement(p: Placement, dims: [u32; 3]) -> Result<(), GridErrorKind> {
    if !(p.spacing.is_finite() && p.spacing > 0.0) {
        return Err(GridErrorKind::BadPlacement(format!("spacing must be finite and > 0, found {}", p.spacing)));
    }
    for (k, d) in dims.into_iter().enumerate() {
        let top = p.origin[k] + f64::from(d - 1) * p.spacing;
        if !p.origin[k].is_finite() || !top.is_finite() {
            return Err(GridErrorKind::BadPlacement(format!("origin[{k}] = {} with spacing {}: the grid's box must be finite", p.origin[k], p.spacing)));
        }
    }
    Ok(())
}
