//! A rendered frame as 8-bit sRGB pixels with alpha: what a program that
//! shows or stores pictures takes from isotrace.

use super::{srgb8, write_atomic_with, OutputError};
use crate::render::Frame;
use std::path::Path;

/// An 8-bit RGBA picture, row-major, top row first: colour in sRGB, alpha
/// 255 on hits and 0 where the ray met nothing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width × height × 4` bytes: R, G, B, A of each pixel.
    pub rgba: Vec<u8>,
}

impl Image {
    /// The frame's colours, as `render -o picture.png` writes them, with
    /// its coverage as alpha.
    pub fn from_frame(frame: &Frame) -> Image {
        let alpha = |a: f32| (a.clamp(0.0, 1.0) * 255.0).round() as u8;
        let rgba = frame.pixels.iter().flat_map(|p| [srgb8(p.color[0]), srgb8(p.color[1]), srgb8(p.color[2]), alpha(p.color[3])]).collect();
        Image { width: frame.width, height: frame.height, rgba }
    }

    /// Writes the picture as an RGBA PNG, through a temporary file and a
    /// rename (never a partial file; only a regular file is replaced).
    pub fn save_png(&self, path: impl AsRef<Path>) -> Result<(), OutputError> {
        use ::image::ImageEncoder;
        let path = path.as_ref();
        super::check_target(path)?;
        write_atomic_with(path, |w| {
            ::image::codecs::png::PngEncoder::new(w).write_image(&self.rgba, self.width, self.height, ::image::ExtendedColorType::Rgba8).map_err(|e| e.to_string())
        })
    }
}
