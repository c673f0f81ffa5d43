//! What a render is, independent of the device: the camera model, the
//! settings of one frame, the per-pixel result and the statistics.

use glam::DVec3;

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

/// The orthonormal frame a [`Camera`] produces (exactly the formulas of the
/// CLI reference, so renders compare with other tools).
#[derive(Debug, Clone, Copy)]
pub struct CameraFrame {
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

    /// The camera frame, or an error when the view is degenerate.
    pub fn frame(&self) -> Result<CameraFrame, String> {
        let f = self.target - self.eye;
        if !(f.length() > 0.0) {
            return Err("the eye and the target are the same point".into());
        }
        let forward = f.normalize();
        let r = forward.cross(self.up);
        if !(r.length() > 1e-9) {
            return Err("the up vector is parallel to the viewing direction: give another --up".into());
        }
        let right = r.normalize();
        if !(self.fov_deg > 0.0 && self.fov_deg < 180.0) {
            return Err(format!("--fov must be between 0 and 180 degrees, got {}", self.fov_deg));
        }
        Ok(CameraFrame { forward, right, up: right.cross(forward), tan_half_fov: (0.5 * self.fov_deg.to_radians()).tan() })
    }

    /// The unit primary ray direction through pixel (i, j), j = 0 the top row.
    pub fn ray(frame: &CameraFrame, i: u32, j: u32, w: u32, h: u32) -> DVec3 {
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

/// Per-frame statistics.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct Stats {
    /// GPU time of the dispatches (timestamp queries when the device has
    /// them, else submit-to-idle wall time), milliseconds.
    pub gpu_ms: f64,
    /// The part of `gpu_ms` spent in the tile pass (0 without one).
    pub tile_ms: f64,
    /// Wall time of the whole frame including read-back, milliseconds.
    pub wall_ms: f64,
    /// Pixels in the image.
    pub pixels: u64,
    /// Pixels whose ray found a root.
    pub hits: u64,
    /// Pixels that ran out of iterations.
    pub unresolved: u64,
    /// Mean inclusion evaluations per pixel.
    pub evals_mean: f64,
    /// 99th percentile.
    pub evals_p99: u32,
    /// Maximum.
    pub evals_max: u32,
    /// Bisection depth for a segment across the whole box diagonal.
    pub d_max: u32,
    /// Number of dispatches (tiles).
    pub dispatches: u32,
    /// Work lower bound per pixel, as issue 8 defines it: a hit needs one
    /// evaluation per level down to an eps cell of its ray's segment
    /// (d_max + 1, with the ray's own d_max), a miss one.
    pub evals_lower_bound: f64,
    /// Mean evaluations of hit pixels.
    pub evals_hit_mean: f64,
    /// Mean evaluations of pixels whose ray crosses the domain and misses.
    pub evals_miss_mean: f64,
    /// The traversal. With sphere tracing every `evals` figure counts field
    /// evaluations of all rays of a pixel (steps), and there is no lower bound.
    pub method: Method,
    /// The frame was rendered with several isovalues or CSG surfaces: the
    /// pixels' `iso` field says which one each hit is (EXR channel `iso`).
    pub iso_channel: bool,
    /// Sphere tracing: over-relaxed steps that failed the overlap test and
    /// fell back (summed over the pixels).
    pub sor_fallbacks: u64,
    /// Sphere tracing: pixels whose primary ray saw f / L change faster
    /// than the distance between two samples, i.e. evidence that the formula
    /// is not an L-Lipschitz distance bound (surfaces may be missed).
    pub lipschitz_violations: u64,
    /// Sphere tracing: the largest |Δf| / |Δp| seen along any primary ray
    /// (for f itself, before the division by L): a lower estimate of the
    /// Lipschitz bound `--lipschitz` needs.
    pub lipschitz_seen: f64,
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

/// The per-pixel statistics of a frame gathered in one pass, so a renderer
/// can collect them while it unpacks pixels (on several threads, merged
/// after). Summing 1024² pixels in several passes plus a selection for the
/// 99th percentile cost ~20 ms a frame; this costs ~1 ms.
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

    /// Writes the per-pixel figures into `stats`.
    pub fn finish(mut self, stats: &mut Stats) {
        let n = self.pixels.max(1) as f64;
        stats.pixels = self.pixels;
        stats.hits = self.hits;
        stats.unresolved = self.unresolved;
        stats.evals_mean = self.evals_sum as f64 / n;
        stats.evals_max = self.evals_max;
        stats.evals_lower_bound = self.bound_sum as f64 / n;
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

/// `--eps`: an absolute width (`0.001`) or a power of two (`2^-11`).
pub fn parse_eps(s: &str) -> Result<f64, String> {
    let s = s.trim();
    let v = if let Some(e) = s.strip_prefix("2^") {
        let k: f64 = e.parse().map_err(|_| format!("invalid eps '{s}': expected a number like 0.001 or a power of two like 2^-11"))?;
        2f64.powf(k)
    } else {
        s.parse::<f64>().map_err(|_| format!("invalid eps '{s}': expected a number like 0.001 or a power of two like 2^-11"))?
    };
    if !(v > 0.0 && v.is_finite()) {
        return Err(format!("invalid eps '{s}': it must be a positive width"));
    }
    Ok(v)
}
