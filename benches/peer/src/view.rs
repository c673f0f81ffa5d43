//! The view both renderers see: isotrace's pinhole camera, re-expressed as
//! fidget's projective voxel → model matrix, the near-orthographic variant
//! of a camera that frames the domain tightly, and the domain as a fidget
//! solid.

use fidget::context::{BadNode, Context, Node};
use glam::DVec3;
use isotrace::render::{Camera, CameraBasis};
use nalgebra::{Matrix4, Vector3};

/// The vertical field of view of `--view ortho`, degrees: narrow enough
/// that the depth of the domain changes the image scale by only about
/// ±2.5% across a box that fills the frame (a nearly parallel projection),
/// wide enough that the eye stays about 20 box diagonals away, where f32
/// ray positions on the device and in fidget's matrix still resolve
/// eps = 2^-11 × diagonal.
pub const ORTHO_FOV_DEG: f64 = 2.5;

/// Which camera a table was rendered with.
#[derive(Clone, Copy, PartialEq, Debug)]
pub enum ViewKind {
    /// The `.iso` header's camera (or isotrace's default camera).
    Perspective,
    /// The same viewing direction and up vector, a narrow field of view
    /// ([`ORTHO_FOV_DEG`]) and the eye moved back until the domain just
    /// fills the frame ([`framed`]).
    Ortho,
}

impl ViewKind {
    /// The name on the command line and in the table headers.
    pub fn name(self) -> &'static str {
        match self {
            ViewKind::Perspective => "perspective",
            ViewKind::Ortho => "ortho",
        }
    }

    /// The camera this view gives for a base camera and a domain.
    pub fn camera(self, base: &Camera, bbox: &[f64; 6], clip: Option<f64>, aspect: f64) -> Camera {
        match self {
            ViewKind::Perspective => *base,
            ViewKind::Ortho => framed(base, bbox, clip, aspect, ORTHO_FOV_DEG),
        }
    }
}

/// A camera looking along `base`'s direction (with its up vector) at the
/// centre of the domain, with vertical field of view `fov_deg`, placed so
/// that the domain's projection just fits the frame: the nearest eye
/// distance at which every corner of the box is inside the frame, or (for a
/// clipped domain, box ∩ ball) the ball, whichever allows the closer eye
/// (the domain is inside both), plus 1% so silhouettes on the domain's
/// edge are not cut by the frame.
pub fn framed(base: &Camera, bbox: &[f64; 6], clip: Option<f64>, aspect: f64, fov_deg: f64) -> Camera {
    let frame = base.frame().expect("a camera that Settings::check accepted");
    let centre = DVec3::new(bbox[0] + bbox[1], bbox[2] + bbox[3], bbox[4] + bbox[5]) * 0.5;
    let th = (0.5 * fov_deg.to_radians()).tan();
    // corner c at lateral (x, y) and depth z from the centre is in the frame
    // from eye distance D on when |x| <= th·aspect·(D + z) and |y| <= th·(D + z)
    let mut dist = f64::NEG_INFINITY;
    for c in 0..8 {
        let p = DVec3::new(bbox[c & 1], bbox[2 + ((c >> 1) & 1)], bbox[4 + ((c >> 2) & 1)]) - centre;
        let (x, y, z) = (p.dot(frame.right), p.dot(frame.up), p.dot(frame.forward));
        dist = dist.max((x.abs() / (th * aspect)).max(y.abs() / th) - z);
    }
    if let Some(r) = clip {
        // a ball fits a cone of half angle a from distance r / sin(a)
        let half = th.min(th * aspect).atan();
        dist = dist.min(r / half.sin());
    }
    let dist = dist * 1.01;
    Camera { eye: centre - frame.forward * dist, target: centre, up: base.up, fov_deg }
}

/// Voxel (u, v, k) → model space, homogeneous: the column (u = i, v = j) is
/// isotrace's ray through the centre of pixel (i, j); k ∈ [0, D] runs from the
/// far depth (k = 0) to the near depth (k = D) uniformly in 1/depth (fidget
/// puts +k towards the viewer).
pub struct View {
    frame: CameraBasis,
    eye: Vector3<f64>,
    /// 1 / depth = alpha·k + beta.
    alpha: f64,
    beta: f64,
    width: u32,
    height: u32,
    /// Voxels along k.
    pub depth: u32,
}

impl View {
    /// The view of `cam` over the domain (`bbox`, and the ball of radius
    /// `clip` around its centre), `w × h` pixels and `d` voxels deep.
    pub fn new(cam: &Camera, bbox: &[f64; 6], clip: Option<f64>, w: u32, h: u32, d: u32) -> View {
        let frame = cam.frame().expect("a camera that Settings::check accepted");
        let eye = Vector3::new(cam.eye.x, cam.eye.y, cam.eye.z);
        let fwd = Vector3::new(frame.forward.x, frame.forward.y, frame.forward.z);
        // depth (distance along `forward`) range of the domain
        let (mut near, mut far) = (f64::INFINITY, f64::NEG_INFINITY);
        for c in 0..8 {
            let p = Vector3::new(bbox[c & 1], bbox[2 + ((c >> 1) & 1)], bbox[4 + ((c >> 2) & 1)]);
            let s = (p - eye).dot(&fwd);
            near = near.min(s);
            far = far.max(s);
        }
        if let Some(r) = clip {
            let centre = Vector3::new(bbox[0] + bbox[1], bbox[2] + bbox[3], bbox[4] + bbox[5]) * 0.5;
            let s = (centre - eye).dot(&fwd);
            near = near.max(s - r);
            far = far.min(s + r);
        }
        // a small margin, so the extreme points of the domain are inside the voxel range
        let (near, far) = (near * (1.0 - 1e-3), far * (1.0 + 1e-3));
        assert!(near > 0.0, "the eye is inside the domain's depth range");
        let beta = 1.0 / far;
        let alpha = (1.0 / near - 1.0 / far) / d as f64;
        View { frame, eye, alpha, beta, width: w, height: h, depth: d }
    }

    /// sx(u) = a_x·u + b_x, sy(v) = a_y·v + b_y (pixel centres, as isotrace).
    fn screen(&self) -> (f64, f64, f64, f64) {
        let (w, h) = (self.width as f64, self.height as f64);
        let th = self.frame.tan_half_fov;
        let (ax, bx) = (2.0 / w * th * w / h, (1.0 / w - 1.0) * th * w / h);
        let (ay, by) = (-2.0 / h * th, (1.0 - 1.0 / h) * th);
        (ax, bx, ay, by)
    }

    /// The voxel → model matrix.
    pub fn matrix(&self) -> Matrix4<f64> {
        let v = |d: DVec3| Vector3::new(d.x, d.y, d.z);
        let (f, r, u) = (v(self.frame.forward), v(self.frame.right), v(self.frame.up));
        let (ax, bx, ay, by) = self.screen();
        // x_h = eye·q + f + sx·r + sy·u, w_h = q, q = alpha·k + beta
        let cu = r * ax;
        let cv = u * ay;
        let ck = self.eye * self.alpha;
        let c1 = self.eye * self.beta + f + r * bx + u * by;
        #[rustfmt::skip]
        let m = Matrix4::new(
            cu.x, cv.x, ck.x, c1.x,
            cu.y, cv.y, ck.y, c1.y,
            cu.z, cv.z, ck.z, c1.z,
            0.0,  0.0,  self.alpha, self.beta,
        );
        m
    }

    /// Distance along the unit ray of pixel (i, j) of a voxel depth value
    /// (fidget: the first filled voxel is k = depth − 1).
    pub fn ray_distance(&self, i: u32, j: u32, k: f64) -> f64 {
        let (ax, bx, ay, by) = self.screen();
        let (sx, sy) = (ax * i as f64 + bx, ay * j as f64 + by);
        let dir = self.frame.forward + sx * self.frame.right + sy * self.frame.up;
        dir.length() / (self.alpha * k + self.beta)
    }
}

/// The domain isotrace traces: the box, and the ball of radius R around the
/// box centre when the entry clips. Negative inside (fidget's convention).
pub fn domain(ctx: &mut Context, b: &[f64; 6], clip: Option<f64>) -> Result<Node, BadNode> {
    let axes = [ctx.x(), ctx.y(), ctx.z()];
    let mut d: Option<Node> = None;
    let mut r2: Option<Node> = None;
    for (k, &v) in axes.iter().enumerate() {
        let (lo, hi) = (b[2 * k], b[2 * k + 1]);
        let c = ctx.sub(v, (0.5 * (lo + hi)) as f32)?;
        let abs = ctx.abs(c)?;
        let s = ctx.sub(abs, (0.5 * (hi - lo)) as f32)?;
        d = Some(match d {
            None => s,
            Some(p) => ctx.max(p, s)?,
        });
        let sq = ctx.square(c)?;
        r2 = Some(match r2 {
            None => sq,
            Some(p) => ctx.add(p, sq)?,
        });
    }
    let mut d = d.unwrap();
    if let Some(r) = clip {
        let ball = ctx.sub(r2.unwrap(), (r * r) as f32)?;
        d = ctx.max(d, ball)?;
    }
    Ok(d)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The framed camera puts the extreme corner of the box on the frame's
    /// edge (within the 1% margin) and every corner inside it.
    #[test]
    fn framed_box_just_fits() {
        let bbox = [-1.0, 2.0, -0.5, 0.5, 0.0, 3.0];
        let base = Camera::default_for(&bbox, 40.0, 1.0);
        let cam = framed(&base, &bbox, None, 1.0, ORTHO_FOV_DEG);
        let f = cam.frame().unwrap();
        let mut extreme: f64 = 0.0;
        for c in 0..8 {
            let p = DVec3::new(bbox[c & 1], bbox[2 + ((c >> 1) & 1)], bbox[4 + ((c >> 2) & 1)]) - cam.eye;
            let z = p.dot(f.forward);
            let s = (p.dot(f.right) / z).abs().max((p.dot(f.up) / z).abs()) / f.tan_half_fov;
            extreme = extreme.max(s);
        }
        assert!(extreme < 1.0 && extreme > 0.98, "largest corner at {extreme} of the half frame");
        let d0 = (base.target - base.eye).normalize();
        assert!((f.forward - d0).length() < 1e-12, "the viewing direction is kept");
    }

    /// Voxel columns are isotrace's rays: the model point of voxel (i, j, k)
    /// lies on the ray through pixel (i, j), at the distance `ray_distance` says.
    #[test]
    fn matrix_maps_columns_onto_rays() {
        let bbox = [-2.0, 2.0, -2.0, 2.0, -2.0, 2.0];
        let cam = framed(&Camera::default_for(&bbox, 40.0, 1.0), &bbox, None, 1.0, ORTHO_FOV_DEG);
        let (w, h, d) = (64, 64, 64);
        let view = View::new(&cam, &bbox, None, w, h, d);
        let m = view.matrix();
        let frame = cam.frame().unwrap();
        for (i, j, k) in [(0u32, 0u32, 0.0), (63, 10, 32.0), (31, 63, 64.0)] {
            let p = m * nalgebra::Vector4::new(i as f64, j as f64, k, 1.0);
            let p = DVec3::new(p.x / p.w, p.y / p.w, p.z / p.w);
            let ray = Camera::ray(&frame, i, j, w, h);
            let t = view.ray_distance(i, j, k);
            assert!((cam.eye + ray * t - p).length() < 1e-9 * t, "voxel ({i}, {j}, {k})");
        }
    }
}
