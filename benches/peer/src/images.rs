//! The pictures of `--images DIR`: per surface or scene and view,
//! isotrace's shaded picture, both depth maps on one grey scale, fidget's
//! normals and a difference map, so a disagreement can be looked at.

use crate::view::View;
use fidget::raster::voxel::{self, GeometryPixel};
use isotrace::render::{Frame, Status};
use std::path::Path;

/// Writes `NAME.isotrace.png` (shaded), `NAME.isotrace-depth.png`,
/// `NAME.fidget-depth.png` (near bright, far dark, miss black),
/// `NAME.fidget-normals.png` and `NAME.diff.png` (green: both hit, brighter
/// the larger the depth difference, saturating at 1% of the depth range;
/// red: only isotrace hits; blue: only fidget hits) into `dir`.
pub fn write(dir: &Path, name: &str, view: &View, iso: &Frame, fid: &voxel::Image) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let (w, h) = (iso.width, iso.height);
    let fid_t = |i: u32, j: u32| {
        let d = fid[(j * w + i) as usize].depth;
        (d > 0).then(|| view.ray_distance(i, j, d as f64 - 1.0))
    };
    let iso_t = |i: u32, j: u32| {
        let p = &iso.pixels[(j * w + i) as usize];
        matches!(p.status, Status::Hit).then_some(p.depth as f64)
    };
    // one grey scale for both: the depth range of the domain along the centre ray
    let (t_near, t_far) = (view.ray_distance(w / 2, h / 2, view.depth as f64), view.ray_distance(w / 2, h / 2, 0.0));
    let grey = |t: Option<f64>| -> u8 {
        match t {
            None => 0,
            Some(t) => (255.0 - 215.0 * ((t - t_near) / (t_far - t_near)).clamp(0.0, 1.0)).round() as u8,
        }
    };
    let save = |img: image::RgbImage, suffix: &str| {
        let p = dir.join(format!("{name}.{suffix}.png"));
        img.save(&p).map_err(|e| format!("{}: {e}", p.display()))
    };
    save(image::RgbImage::from_fn(w, h, |i, j| image::Rgb([grey(iso_t(i, j)); 3])), "isotrace-depth")?;
    save(image::RgbImage::from_fn(w, h, |i, j| image::Rgb([grey(fid_t(i, j)); 3])), "fidget-depth")?;
    save(
        image::RgbImage::from_fn(w, h, |i, j| image::Rgb(GeometryPixel::to_color(&fid[(j * w + i) as usize]))),
        "fidget-normals",
    )?;
    save(
        image::RgbImage::from_fn(w, h, |i, j| {
            let c = iso.pixels[(j * w + i) as usize].color;
            let s = |v: f32| (v.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0).round() as u8;
            image::Rgb([s(c[0]), s(c[1]), s(c[2])])
        }),
        "isotrace",
    )?;
    let scale = 1.0 / (t_far - t_near);
    save(
        image::RgbImage::from_fn(w, h, |i, j| match (iso_t(i, j), fid_t(i, j)) {
            (None, None) => image::Rgb([0, 0, 0]),
            (Some(_), None) => image::Rgb([255, 0, 0]),
            (None, Some(_)) => image::Rgb([0, 80, 255]),
            (Some(a), Some(b)) => {
                // brightness: 64 + |Δt| in units of 1/100 of the depth range
                let g = (64.0 + 19100.0 * ((a - b).abs() * scale).min(0.01)).round() as u8;
                image::Rgb([0, g, 0])
            }
        }),
        "diff",
    )
}
