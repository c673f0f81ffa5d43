//! A blobtree scene built in code, rendered by sphere tracing, one of its
//! primitives moved in place (a few rows of the bound buffers: no new
//! shader, no new pipeline) and rendered again.
//!
//!     cargo run --release --example edit_scene
//!
//! Writes `scene-before.png` and `scene-after.png` in the temporary folder.

use isotrace::render::{SphereOptions, Traversal};
use isotrace::scene::linear::Linear;
use isotrace::scene::{Builder, Operator, Primitive, Shape};
use isotrace::{Gpu, Image, Renderer, Settings};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // Three balls in a row, joined by a sharp union.
    let mut b = Builder::default();
    let balls: Vec<_> = (0..3)
        .map(|i| {
            let mut ball = Primitive::new(Shape::Sphere { radius: 0.45 });
            ball.transform.translate = [i as f64 - 1.0, 0.0, 0.0];
            b.primitive(ball)
        })
        .collect();
    let root = b.fold(Operator::UNION, &balls);
    let scene = b.finish(root)?;

    // The scene's buffers, and a renderer for them.
    let mut linear = Linear::new(&scene)?;
    let gpu = Gpu::new()?;
    let data = linear.field_data();
    let renderer = Renderer::new(&gpu, &data, Traversal::Sphere(SphereOptions::default()))?;
    let settings = Settings::for_box([-1.6, 1.6, -0.6, 1.0, -0.6, 0.6], 192, 128);
    let before = renderer.render(&settings)?;
    let out = std::env::temp_dir();
    Image::from_frame(&before).save_png(out.join("scene-before.png"))?;

    // Lift the middle ball: the edit is a patch of the bound buffers.
    let mut lifted = Primitive::new(Shape::Sphere { radius: 0.45 });
    lifted.transform.translate = [0.0, 0.4, 0.0];
    renderer.edit_field(&linear.set_primitive(1, &lifted)?)?;
    let after = renderer.render(&settings)?;
    Image::from_frame(&after).save_png(out.join("scene-after.png"))?;

    if before.stats.hits == 0 || Image::from_frame(&before) == Image::from_frame(&after) {
        return Err("the edit should change the picture".into());
    }
    println!("{} hits before the edit, {} after; pictures in {}", before.stats.hits, after.stats.hits, out.display());
    Ok(())
}
