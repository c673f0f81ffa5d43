//! Helpers shared by the integration tests: one GPU device per test binary,
//! quick render settings, and a brute-force f64 CPU reference ray caster.
#![allow(dead_code)]

use glam::DVec3;
use crate::gpu::Renderer;
use crate::render::Settings;
use crate::gpu::Gpu;
use crate::render::{Camera, Frame};
use crate::Formula;
use std::sync::OnceLock;

/// The device shared by every test of a binary.
pub fn gpu() -> &'static Gpu {
    static GPU: OnceLock<Gpu> = OnceLock::new();
    GPU.get_or_init(|| Gpu::new().expect("a Vulkan device (install mesa-vulkan-drivers)"))
}

/// The text of a catalog surface (`examples/*.iso`, header lines and all:
/// they are comments to the formula language).
pub fn catalog_formula(name: &str) -> String {
    crate::catalog::lookup(name).unwrap().formula
}

/// Settings with the CLI's defaults for a box and size.
pub fn settings(bbox: [f64; 6], w: u32, h: u32) -> Settings {
    Settings::for_box(bbox, w, h)
}

/// Compiles and renders.
pub fn render(src: &str, domain: crate::ir::Domain, s: &Settings) -> Frame {
    let f = Formula::compile("<test>", src).unwrap();
    Renderer::bisect(gpu(), &f.ir, domain).unwrap().render(s).unwrap()
}

/// Whether f changes sign within 2 eps of distance `t` along pixel k's ray.
pub fn sign_change_near(f: &Formula, s: &Settings, k: u32, t: f64) -> bool {
    let cf = s.camera.frame().unwrap();
    let d = Camera::ray(&cf, k % s.width, k / s.width, s.width, s.height);
    let g = |t: f64| {
        let p = s.camera.eye + d * t;
        crate::reference::eval_scalar(&f.ir, [p.x, p.y, p.z, s.time], &[])
    };
    let (a, b) = (g(t - 2.0 * s.eps), g(t + 2.0 * s.eps));
    (a <= 0.0) != (b <= 0.0)
}

/// A cube box.
pub fn cube(a: f64) -> [f64; 6] {
    [-a, a, -a, a, -a, a]
}

/// Brute-force reference: the first sign change of f along the pixel's ray
/// inside the box, found by dense sampling (`samples` steps) and refined by
/// f64 bisection. Returns the distance from the eye and the width of the
/// sampling step that bracketed it.
pub fn reference_root(f: &Formula, s: &Settings, i: u32, j: u32, samples: usize) -> Option<(f64, f64)> {
    let frame = s.camera.frame().unwrap();
    let d = Camera::ray(&frame, i, j, s.width, s.height);
    let o = s.camera.eye;
    let (t0, t1) = clip(o, d, &s.bbox)?;
    let g = |t: f64| {
        let p = o + d * t;
        crate::reference::eval_scalar(&f.ir, [p.x, p.y, p.z, s.time], &[])
    };
    let step = (t1 - t0) / samples as f64;
    let mut a = t0;
    let mut fa = g(a);
    for k in 1..=samples {
        let b = t0 + step * k as f64;
        let fb = g(b);
        if fa.is_finite() && fb.is_finite() && (fa < 0.0) != (fb < 0.0) && fa != 0.0 {
            let (mut lo, mut hi, mut flo) = (a, b, fa);
            for _ in 0..60 {
                let m = 0.5 * (lo + hi);
                let fm = g(m);
                if (fm < 0.0) == (flo < 0.0) { lo = m; flo = fm; } else { hi = m; }
            }
            return Some((0.5 * (lo + hi), step));
        }
        if fa == 0.0 {
            return Some((a, step));
        }
        a = b;
        fa = fb;
    }
    None
}

/// Ray–box clip: entry and exit distances (entry ≥ 0).
pub fn clip(o: DVec3, d: DVec3, b: &[f64; 6]) -> Option<(f64, f64)> {
    let lo = DVec3::new(b[0], b[2], b[4]);
    let hi = DVec3::new(b[1], b[3], b[5]);
    let inv = DVec3::ONE / d;
    let ta = (lo - o) * inv;
    let tb = (hi - o) * inv;
    let tmin = ta.min(tb);
    let tmax = ta.max(tb);
    let t0 = tmin.max_element().max(0.0);
    let t1 = tmax.min_element();
    (t0 < t1).then_some((t0, t1))
}

/// Writes the frame as EXR and reads the named channel back (tests that
/// check depth or isovalues through the file a user gets).
pub fn exr_channel(frame: &Frame, name: &str) -> Vec<f32> {
    static N: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = N.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let path = std::env::temp_dir().join(format!("isotrace-test-{}-{k}.exr", std::process::id()));
    crate::output::write_exr(&path, frame).unwrap();
    let (w, h, channels) = crate::output::read_exr_channels(&path).unwrap();
    let _ = std::fs::remove_file(&path);
    assert_eq!((w, h), (frame.width, frame.height));
    channels.into_iter().find(|(n, _)| n == name).unwrap_or_else(|| panic!("no EXR channel {name}")).1
}

/// A deterministic point cloud in the box [-s, s]³.
pub fn points(s: f64, n: usize, seed: u64) -> Vec<[f64; 3]> {
    let mut st = 0x9e3779b97f4a7c15u64 ^ seed;
    let mut r = move || {
        st ^= st << 13;
        st ^= st >> 7;
        st ^= st << 17;
        (st >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n).map(|_| [s * (2.0 * r() - 1.0), s * (2.0 * r() - 1.0), s * (2.0 * r() - 1.0)]).collect()
}
