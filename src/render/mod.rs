//! What a render is, independent of the device: the camera model, the
//! typed settings of a frame (`settings`) and of each traversal
//! (`traversal`), the pixel record the kernels write and its decoding
//! (`record`), the per-pixel result and the statistics (`stats`).

use glam::DVec3;

pub(crate) mod record;
pub(crate) mod settings;
pub(crate) mod stats;
pub(crate) mod traversal;
pub(crate) mod view;

pub use settings::{Settings, SettingsError, SettingsField, Unresolved};
pub use stats::{BisectStats, FieldStats, LoopListStats, SphereStats, Stats, TapeListStats};
pub(crate) use stats::StatsAcc;
pub use record::PackedFrame;
pub use crate::layout::KernelColor;
pub use traversal::{BisectOptions, EnvSpec, Environment, EnvImage, ModalitySpec, Modalities, Optimizations, RootSearch, Shading, SphereFeatures, SphereOptions, Traversal};
#[cfg(feature = "internals")]
pub use view::{View, ViewError};
#[cfg(not(feature = "internals"))]
pub(crate) use view::{View, ViewError};

/// A pinhole camera: eye, target, up, vertical field of view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: DVec3,
    /// Point looked at.
    pub target: DVec3,
    /// Approximate up direction.
    pub up: DVec3,
    /// Vertical field of view in degrees.
    pub fov_deg: f64,
}

/// The orthonormal basis a [`Camera`] produces (exactly the formulas of the
/// CLI reference, so renders compare with other tools).
#[derive(Debug, Clone, Copy)]
pub struct CameraBasis {
    /// normalize(target − eye)
    pub forward: DVec3,
    /// normalize(cross(forward, up))
    pub right: DVec3,
    /// cross(right, forward)
    pub up: DVec3,
    /// tan(fov / 2)
    pub tan_half_fov: f64,
}

impl Camera {
    /// The default view of a box: looking at its centre from azimuth 35°,
    /// elevation 25°, +z up, far enough that the whole box is in view.
    pub fn default_for(bx: &[f64; 6], fov_deg: f64, aspect: f64) -> Camera {
        let lo = DVec3::new(bx[0], bx[2], bx[4]);
        let hi = DVec3::new(bx[1], bx[3], bx[5]);
        let target = 0.5 * (lo + hi);
        Self::orbit(target, 0.5 * (hi - lo).length(), 35.0, 25.0, fov_deg, aspect)
    }

    /// A camera on a sphere around `target` that keeps a ball of `radius` in view.
    pub fn orbit(target: DVec3, radius: f64, azimuth_deg: f64, elevation_deg: f64, fov_deg: f64, aspect: f64) -> Camera {
        let (az, el) = (azimuth_deg.to_radians(), elevation_deg.to_radians());
        let dir = DVec3::new(el.cos() * az.cos(), el.cos() * az.sin(), el.sin());
        let half_v = 0.5 * fov_deg.to_radians();
        let half_h = (half_v.tan() * aspect).atan();
        let dist = radius / half_v.min(half_h).sin() * 1.02;
        Camera { eye: target + dir * dist, target, up: DVec3::Z, fov_deg }
    }

    /// The camera frame, or an error when the view is degenerate. The
    /// field of view and finiteness are checked first, so a bad value is
    /// reported as itself and not as a degenerate frame it causes.
    pub fn frame(&self) -> Result<CameraBasis, SettingsError> {
        use SettingsField as F;
        if !(self.fov_deg > 0.0 && self.fov_deg < 180.0) {
            return Err(SettingsError::new(F::Fov, self.fov_deg.to_string(), "the field of view must be between 0 and 180 degrees"));
        }
        let finite = |v: DVec3| v.is_finite() && v.abs().max_element() < 1e30;
        for (field, v) in [(F::Eye, self.eye), (F::Target, self.target), (F::Up, self.up)] {
            if !finite(v) {
                return Err(SettingsError::new(field, format!("{:e},{:e},{:e}", v.x, v.y, v.z), "coordinates must be finite numbers below 1e30"));
            }
        }
        let f = self.target - self.eye;
        if !(f.length() > 0.0) {
            return Err(SettingsError::new(F::Eye, "", "the eye and the target are the same point"));
        }
        let forward = f.normalize();
        let r = forward.cross(self.up);
        if !(r.length() > 1e-9) {
            return Err(SettingsError::new(F::Up, "", "the up vector is parallel to the viewing direction"));
        }
        let right = r.normalize();
        Ok(CameraBasis { forward, right, up: right.cross(forward), tan_half_fov: (0.5 * self.fov_deg.to_radians()).tan() })
    }

    /// The unit primary ray direction through pixel (i, j), j = 0 the top row.
    pub fn ray(frame: &CameraBasis, i: u32, j: u32, w: u32, h: u32) -> DVec3 {
        let (wf, hf) = (w as f64, h as f64);
        let sx = ((i as f64 + 0.5) / wf * 2.0 - 1.0) * frame.tan_half_fov * wf / hf;
        let sy = (1.0 - (j as f64 + 0.5) / hf * 2.0) * frame.tan_half_fov;
        (frame.forward + sx * frame.right + sy * frame.up).normalize()
    }
}

/// The traversal that made a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Interval / affine bisection: robust for any formula.
    #[default]
    Bisect,
    /// Sphere tracing: only for distance bounds, fast.
    Sphere,
}

impl Method {
    /// The spelling on the command line and in `.iso` headers.
    pub fn name(self) -> &'static str {
        match self {
            Method::Bisect => "bisect",
            Method::Sphere => "sphere",
        }
    }

    /// Parses `sphere` or `bisect`.
    pub fn parse(s: &str) -> Result<Method, String> {
        match s.trim() {
            "bisect" => Ok(Method::Bisect),
            "sphere" => Ok(Method::Sphere),
            _ => Err("expected 'sphere' or 'bisect'".into()),
        }
    }
}

/// A convex volume declared to contain a convex object: sphere tracing
/// clips rays to it, and traces rays that start inside the object
/// backwards from its far side (Keinert et al.'s technique 5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bound {
    /// `sphere:cx,cy,cz,r`
    Sphere {
        /// Centre.
        center: [f64; 3],
        /// Radius, > 0.
        radius: f64,
    },
    /// `box:x0,x1,y0,y1,z0,z1`
    Box([f64; 6]),
}

impl Bound {
    /// Parses `sphere:cx,cy,cz,r` or `box:x0,x1,y0,y1,z0,z1`.
    pub fn parse(s: &str) -> Result<Bound, String> {
        let nums = |v: &str| -> Option<Vec<f64>> { v.split(',').map(|n| n.trim().parse::<f64>().ok().filter(|x| x.is_finite())).collect() };
        let s = s.trim();
        if let Some(v) = s.strip_prefix("sphere:") {
            if let Some(&[cx, cy, cz, r]) = nums(v).as_deref() {
                if r > 0.0 {
                    return Ok(Bound::Sphere { center: [cx, cy, cz], radius: r });
                }
            }
            return Err("expected sphere:cx,cy,cz,r with a radius r > 0".into());
        }
        if let Some(v) = s.strip_prefix("box:") {
            if let Some(&[x0, x1, y0, y1, z0, z1]) = nums(v).as_deref() {
                if x0 < x1 && y0 < y1 && z0 < z1 {
                    return Ok(Bound::Box([x0, x1, y0, y1, z0, z1]));
                }
            }
            return Err("expected box:x0,x1,y0,y1,z0,z1 with lo < hi on every axis".into());
        }
        Err("expected sphere:cx,cy,cz,r or box:x0,x1,y0,y1,z0,z1".into())
    }
}

/// Length of a box's diagonal (`x0, x1, y0, y1, z0, z1`): the default eps
/// is 2^-11 of it.
pub fn box_diagonal(b: &[f64; 6]) -> f64 {
    ((b[1] - b[0]).powi(2) + (b[3] - b[2]).powi(2) + (b[5] - b[4]).powi(2)).sqrt()
}

/// Pixel outcome.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Status {
    /// The ray misses the surface (or the box).
    Miss,
    /// A root was found.
    Hit,
    /// The iteration budget ran out before the traversal finished.
    Unresolved,
}

/// One rendered pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PixelOut {
    /// Linear RGB and alpha (1 on hits).
    pub color: [f32; 4],
    /// Unit normal (zero on misses).
    pub normal: [f32; 3],
    /// Distance along the unit primary ray from the eye (+inf on misses).
    pub depth: f32,
    /// Inclusion evaluations spent on this pixel.
    pub evals: u32,
    /// d_max of the ray's whole segment through the domain,
    /// ceil(log2(length / eps)) (0 when the ray misses the domain).
    pub level: u32,
    /// Index of the isovalue hit (0 without `--iso`).
    pub iso: u32,
    /// Outcome. For sphere tracing, `Unresolved` means the step budget
    /// ran out before the ray converged ("unconverged").
    pub status: Status,
}

/// A rendered image.
#[derive(Debug, Clone)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major, top row first.
    pub pixels: Vec<PixelOut>,
    /// Statistics.
    pub stats: Stats,
}

impl Frame {
    /// Fills the statistics that follow from the pixels.
    pub fn summarize(&mut self) {
        let mut acc = StatsAcc::default();
        for p in &self.pixels {
            acc.add(p);
        }
        acc.finish(&mut self.stats);
    }
}

