//! A formula rendered to an RGBA picture and a PNG, then the same
//! renderer asked for another view: frames differ only in their settings,
//! so nothing is compiled again.
//!
//!     cargo run --release --example render_formula -- "x^2 + y^2 + z^2 - 1"
//!
//! Writes `formula.png` and `formula-side.png` in the temporary folder.

use isotrace::{Formula, Gpu, Image, Renderer, Settings};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let text = std::env::args().nth(1).unwrap_or_else(|| "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8".into());
    let formula = Formula::compile("<argument>", &text)?;
    let gpu = Gpu::new()?;
    let renderer = Renderer::for_formula(&gpu, &formula)?;

    let mut settings = Settings::for_box([-3.0, 3.0, -3.0, 3.0, -3.0, 3.0], 256, 256);
    let frame = renderer.render(&settings)?;
    let out = std::env::temp_dir();
    Image::from_frame(&frame).save_png(out.join("formula.png"))?;

    // Another camera: a uniform change, no new shader.
    settings.camera.eye = glam::DVec3::new(9.0, 2.0, 0.0);
    let side = renderer.render(&settings)?;
    Image::from_frame(&side).save_png(out.join("formula-side.png"))?;

    println!("{}: {} and {} hits, {:.1} evaluations per pixel; pictures in {}", formula.source, frame.stats.hits, side.stats.hits, frame.stats.evals_mean, out.display());
    Ok(())
}
