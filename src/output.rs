//! Image files: PNG (8-bit sRGB) and OpenEXR (float channels), always
//! written atomically (temporary file in the same directory + rename).
//!
//! Every file isotrace writes goes through `write_atomic`: only a regular
//! file (or nothing) may be where it writes. A device, a FIFO, a socket or
//! a directory there is refused before any work (`check_target`), so a
//! write never turns `/dev/full` into a file nor blocks on a FIFO. A
//! symbolic link there is replaced by the new file, like any file, and the
//! file it pointed to is left as it was: a write lands only at the path
//! named, so a link planted in a shared output directory cannot redirect
//! it. The path `-` is standard output (`is_stdout`); an image written
//! there is a PNG.

mod picture;
mod temporaries;
pub use picture::Image;

pub(crate) use temporaries::{remove_stale_temporaries, remove_temporaries};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Output failures, with the path they concern.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The file could not be created or written.
    #[error("cannot write '{path}': {source}")]
    Io {
        /// The destination.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The encoder failed.
    #[error("cannot encode '{path}': {message}")]
    Encode {
        /// The destination.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// Neither `.png` nor `.exr`.
    #[error("unknown output format '{path}': the file name must end in .png or .exr")]
    UnknownExtension {
        /// The destination.
        path: PathBuf,
    },
    /// Not the extension of what a command writes (`.wgsl`, `.scene.json`).
    #[error("unknown output format '{path}': the file name must end in {expected}")]
    WrongExtension {
        /// The destination.
        path: PathBuf,
        /// The ending it needs.
        expected: &'static str,
    },
    /// The destination exists and is not a regular file (a directory, a
    /// device, a FIFO, a socket): replacing it would destroy it, writing
    /// into it would not make a file.
    #[error("cannot write '{path}': it is {kind}")]
    NotRegular {
        /// The destination.
        path: PathBuf,
        /// What it is.
        kind: crate::bounded::FileKind,
    },
    /// The encoded image's host memory could not be had.
    #[error("cannot write '{path}': {source}")]
    Memory {
        /// The destination.
        path: PathBuf,
        /// The refused allocation.
        source: crate::memory::MemoryError,
    },
    /// The destination exists and is read-only: replacing it needs the
    /// caller's explicit consent.
    #[error("'{path}' exists and is read-only")]
    ReadOnly {
        /// The destination.
        path: PathBuf,
    },
}

/// The file formats isotrace writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// 8-bit sRGB PNG.
    Png,
    /// OpenEXR with float channels.
    Exr,
}

/// Whether `path` is `-`, standard output.
pub(crate) fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// The format a path asks for, by extension (case-insensitive); PNG for
/// standard output.
pub(crate) fn format_of(path: &Path) -> Result<Format, OutputError> {
    if is_stdout(path) {
        return Ok(Format::Png);
    }
    match path.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase()).as_deref() {
        Some("png") => Ok(Format::Png),
        Some("exr") => Ok(Format::Exr),
        _ => Err(OutputError::UnknownExtension { path: path.to_path_buf() }),
    }
}

/// The temporary file for `path`: `.NAME.PID.tmp` in the same directory
/// (so the rename is atomic). The PID tells a later run whether the writer
/// is gone ([`remove_stale_temporaries`]).
fn tmp_path(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.tmp", std::process::id()))
}

/// Checks that `path` ends in `expected` (`.wgsl`, `.scene.json`; exactly,
/// since readers recognise files by it). Standard output passes.
pub(crate) fn check_extension(path: &Path, expected: &'static str) -> Result<(), OutputError> {
    match path.to_str() {
        _ if is_stdout(path) => Ok(()),
        Some(p) if p.ends_with(expected) && p.len() > expected.len() => Ok(()),
        _ => Err(OutputError::WrongExtension { path: path.to_path_buf(), expected }),
    }
}

/// Checks that nothing but a regular file or a symbolic link (replaced,
/// not followed) is at `path`. Nothing there is fine; a `stat` that fails
/// otherwise is left for the write to report.
pub(crate) fn check_target(path: &Path) -> Result<(), OutputError> {
    if is_stdout(path) {
        return Ok(());
    }
    match std::fs::symlink_metadata(path).ok().and_then(|m| crate::bounded::FileKind::of(m.file_type())) {
        Some(kind) => Err(OutputError::NotRegular { path: path.to_path_buf(), kind }),
        None => Ok(()),
    }
}

/// Checks, before any work, that `path` is no directory, device, FIFO or
/// socket ([`check_target`]) and that its directory exists and is writable
/// (by creating and removing the temporary file).
pub(crate) fn check_writable(path: &Path) -> Result<(), OutputError> {
    if is_stdout(path) {
        return Ok(());
    }
    check_target(path)?;
    let tmp = tmp_path(path);
    let _guard = temporaries::Guard::new(&tmp);
    std::fs::File::create(&tmp).map_err(|source| OutputError::Io { path: path.to_path_buf(), source })?;
    let _ = std::fs::remove_file(&tmp);
    Ok(())
}

/// Checks that `path` is not an existing read-only file. Replacing one by a
/// rename works whatever its mode, so without this check a file the user
/// protected would be silently overwritten.
pub(crate) fn check_not_read_only(path: &Path) -> Result<(), OutputError> {
    if is_stdout(path) {
        return Ok(());
    }
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.is_file() && m.permissions().readonly() => Err(OutputError::ReadOnly { path: path.to_path_buf() }),
        _ => Ok(()),
    }
}

/// Writes through a temporary file and a rename, or to standard output
/// for `-`.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    if is_stdout(path) {
        let mut out = std::io::stdout().lock();
        return out.write_all(bytes).and_then(|_| out.flush()).map_err(|source| OutputError::Io { path: path.to_path_buf(), source });
    }
    write_atomic_with(path, |f| f.write_all(bytes).map_err(|e| e.to_string()))
}

/// Like [`write_atomic`], with the content produced by `fill` (a file
/// only: standard output cannot seek, which the EXR writer needs).
pub(crate) fn write_atomic_with(
    path: &Path,
    fill: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> Result<(), String>,
) -> Result<(), OutputError> {
    check_target(path)?;
    let tmp = tmp_path(path);
    // Registered before it exists, so a signal at any point removes it.
    let _guard = temporaries::Guard::new(&tmp);
    let io = |source| OutputError::Io { path: path.to_path_buf(), source };
    let file = std::fs::File::create(&tmp).map_err(io)?;
    let mut w = std::io::BufWriter::new(file);
    let result = fill(&mut w)
        .map_err(|message| OutputError::Encode { path: path.to_path_buf(), message })
        .and_then(|_| w.flush().map_err(io))
        .and_then(|_| keep_mode(path, &tmp).map_err(io))
        .and_then(|_| std::fs::rename(&tmp, path).map_err(io));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Gives the temporary file the mode of the file it replaces, so a
/// replaced file keeps its permissions (a read-only one stays read-only).
fn keep_mode(path: &Path, tmp: &Path) -> std::io::Result<()> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.is_file() => std::fs::set_permissions(tmp, m.permissions()),
        _ => Ok(()),
    }
}

/// Linear [0, 1] → 8-bit sRGB.
pub(crate) fn srgb8(c: f32) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0 + 0.5) as u8
}

/// The frame as 8-bit sRGB RGB bytes, row-major.
pub(crate) fn frame_rgb8(frame: &crate::render::Frame) -> Vec<u8> {
    frame.pixels.iter().flat_map(|p| [srgb8(p.color[0]), srgb8(p.color[1]), srgb8(p.color[2])]).collect()
}

/// [`frame_rgb8`] allocated fallibly (see [`crate::memory`]).
pub(crate) fn try_frame_rgb8(frame: &crate::render::Frame) -> Result<Vec<u8>, crate::memory::MemoryError> {
    let items = frame.pixels.iter().flat_map(|p| [srgb8(p.color[0]), srgb8(p.color[1]), srgb8(p.color[2])]);
    crate::memory::collect(frame.pixels.len() * 3, (frame.width, frame.height), "PNG bytes", items)
}

/// Encodes RGB8 bytes as PNG into `w`.
pub(crate) fn encode_png(w: &mut impl Write, width: u32, height: u32, rgb: &[u8]) -> Result<(), String> {
    use image::ImageEncoder;
    image::codecs::png::PngEncoder::new(w)
        .write_image(rgb, width, height, image::ExtendedColorType::Rgb8)
        .map_err(|e| e.to_string())
}

/// Writes a PNG of RGB8 bytes atomically (or to standard output).
pub fn write_png(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), OutputError> {
    if is_stdout(path) {
        let mut png = Vec::new();
        encode_png(&mut png, width, height, rgb).map_err(|message| OutputError::Encode { path: path.to_path_buf(), message })?;
        return write_atomic(path, &png);
    }
    write_atomic_with(path, |w| encode_png(w, width, height, rgb))
}

/// Writes the frame as OpenEXR: `R G B A` (linear), `Z` (distance along the
/// unit primary ray, +inf on misses), `N.X N.Y N.Z` (unit normal) and
/// `evals` (inclusion evaluations) for bisection or `steps` (sphere tracing
/// steps) for sphere tracing, all 32-bit float.
pub fn write_exr(path: &Path, frame: &crate::render::Frame) -> Result<(), OutputError> {
    use exr::prelude::*;
    let px = &frame.pixels;
    let size = (frame.width, frame.height);
    let memory = |source| OutputError::Memory { path: path.to_path_buf(), source };
    let count = 9 + frame.stats.iso_channel as u64;
    crate::memory::check(px.len() as u64 * 4 * count, size, "EXR channels").map_err(memory)?;
    let ch = |name: &str, f: &dyn Fn(&crate::render::PixelOut) -> f32| {
        let samples = crate::memory::collect(px.len(), size, "EXR channels", px.iter().map(f)).map_err(memory)?;
        Ok::<_, OutputError>(AnyChannel::new(name, FlatSamples::F32(samples)))
    };
    let mut channels: Vec<AnyChannel<FlatSamples>> = vec![
        ch("R", &|p| p.color[0])?,
        ch("G", &|p| p.color[1])?,
        ch("B", &|p| p.color[2])?,
        ch("A", &|p| p.color[3])?,
        ch("Z", &|p| p.depth)?,
        ch("N.X", &|p| p.normal[0])?,
        ch("N.Y", &|p| p.normal[1])?,
        ch("N.Z", &|p| p.normal[2])?,
        ch(work_channel(frame), &|p| p.evals as f32)?,
    ];
    if frame.stats.iso_channel {
        // Which isovalue (or CSG surface) each hit is: its index, -1 on misses.
        channels.push(ch("iso", &|p| if p.status == crate::render::Status::Miss { -1.0 } else { p.iso as f32 })?);
    }
    let layer = Layer::new(
        (frame.width as usize, frame.height as usize),
        LayerAttributes::named("isotrace"),
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels.into()),
    );
    let image = Image::from_layer(layer);
    write_atomic_with(path, |w| image.write().to_buffered(w).map_err(|e| e.to_string()))
}

/// Name of the per-pixel work channel: what `evals` counts depends on the
/// traversal.
pub(crate) fn work_channel(frame: &crate::render::Frame) -> &'static str {
    match frame.stats.method {
        crate::render::Method::Bisect => "evals",
        crate::render::Method::Sphere => "steps",
    }
}

/// What the colour channels of an image show (`--color`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) enum ColorMode {
    /// The shaded surface.
    #[default]
    Shade,
    /// The pixel's work (sphere tracing steps or inclusion evaluations) as
    /// a heat map from 0 to `max` (default: the frame's 99th percentile).
    Steps {
        /// The value drawn white.
        max: Option<u32>,
    },
    /// The unit normal as 0.5 + 0.5·n.
    Normal,
    /// Sphere tracing only: f(p) / err(t) at the hit point (drawn by the kernel).
    Field,
    /// Bisection only: |grad f| on a log scale (Knoll et al. Fig. 5; drawn by the kernel).
    Gradient,
    /// Bisection only: depth as a colour ramp (drawn by the kernel).
    Depth,
    /// Scenes only: the active primitives of each 8×8 tile as a heat map
    /// from 0 to the frame's most (Zanni's Fig. 1 right).
    Overlap,
}

/// Parses `shade` (alias `phong`), `steps` (alias `evals`), `steps:MAX`,
/// `normal`, `gradient`, `depth`, `field` or `overlap`.
pub(crate) fn parse_color(s: &str) -> Result<ColorMode, String> {
    match s.trim() {
        "shade" | "phong" => Ok(ColorMode::Shade),
        "steps" | "evals" => Ok(ColorMode::Steps { max: None }),
        "gradient" => Ok(ColorMode::Gradient),
        "depth" => Ok(ColorMode::Depth),
        "normal" => Ok(ColorMode::Normal),
        "field" => Ok(ColorMode::Field),
        "overlap" => Ok(ColorMode::Overlap),
        other => match other.strip_prefix("steps:").map(|m| m.trim().parse::<u32>()) {
            Some(Ok(m)) if m > 0 => Ok(ColorMode::Steps { max: Some(m) }),
            _ => Err("expected shade, steps (or evals), steps:MAX (MAX > 0), normal, gradient, depth, field or overlap".into()),
        },
    }
}

/// A heat map colour (linear RGB) for v in [0, 1]: black, purple, red,
/// orange, pale yellow, monotone in brightness so the picture reads in grey too.
pub(crate) fn heat(v: f64) -> [f32; 3] {
    const STOPS: [[f64; 3]; 5] = [[0.0, 0.0, 0.02], [0.27, 0.03, 0.45], [0.78, 0.13, 0.30], [0.98, 0.55, 0.05], [1.0, 1.0, 0.75]];
    let x = if v.is_finite() { v.clamp(0.0, 1.0) } else { 1.0 } * 4.0;
    let k = (x.floor() as usize).min(3);
    let f = x - k as f64;
    let c = |i: usize| (STOPS[k][i] + (STOPS[k + 1][i] - STOPS[k][i]) * f).powf(2.2) as f32;
    [c(0), c(1), c(2)]
}

/// Recolours a frame for `mode` (`Shade` and `Field` leave it as the
/// kernel drew it). Returns the heat map's full-scale value for `Steps`
/// and `Overlap`.
pub(crate) fn recolor(frame: &mut crate::render::Frame, mode: ColorMode) -> Option<u32> {
    match mode {
        ColorMode::Shade | ColorMode::Field | ColorMode::Gradient | ColorMode::Depth => None,
        ColorMode::Steps { max } => {
            let max = max.unwrap_or_else(|| {
                let mut v: Vec<u32> = frame.pixels.iter().map(|p| p.evals).collect();
                v.sort_unstable();
                v.get(v.len() * 99 / 100).copied().unwrap_or(1).max(1)
            });
            for p in &mut frame.pixels {
                let [r, g, b] = heat(p.evals as f64 / max as f64);
                p.color = [r, g, b, p.color[3]];
            }
            Some(max)
        }
        ColorMode::Overlap => {
            let st = &frame.stats.field;
            let max = st.active_max.max(1);
            let tx = st.tiles_x.max(1);
            let w = frame.width;
            for (i, p) in frame.pixels.iter_mut().enumerate() {
                let (x, y) = (i as u32 % w, i as u32 / w);
                let a = st.tile_active.get(((y / 8) * tx + x / 8) as usize).copied().unwrap_or(0);
                let [r, g, b] = heat(a as f64 / max as f64);
                p.color = [r, g, b, p.color[3]];
            }
            Some(max)
        }
        ColorMode::Normal => {
            for p in &mut frame.pixels {
                if p.color[3] > 0.0 {
                    let n = p.normal;
                    p.color = [0.5 + 0.5 * n[0], 0.5 + 0.5 * n[1], 0.5 + 0.5 * n[2], 1.0].map(|c| c.powf(2.2));
                } else {
                    p.color = [0.0, 0.0, 0.0, 0.0];
                }
            }
            None
        }
    }
}

/// Writes the frame in the format its extension names.
pub fn write_frame(path: &Path, frame: &crate::render::Frame) -> Result<(), OutputError> {
    match format_of(path)? {
        Format::Png => {
            let rgb = try_frame_rgb8(frame).map_err(|source| OutputError::Memory { path: path.to_path_buf(), source })?;
            write_png(path, frame.width, frame.height, &rgb)
        }
        Format::Exr => write_exr(path, frame),
    }
}

/// The largest image file read back: an `--env` image (a 16384 × 8192
/// equirectangular PNG of noise is about 400 MiB; real ones compress far
/// better) or a bench job's frame.
pub(crate) const MAX_IMAGE_BYTES: u64 = 512 << 20;

/// Reads an image file ([`crate::bounded::read_file_bytes`]: a regular
/// file of at most [`MAX_IMAGE_BYTES`]) and decodes it from memory (by its
/// content, within the decoder's default allocation limit).
pub(crate) fn read_image(path: &Path) -> Result<image::DynamicImage, String> {
    let bytes = crate::bounded::read_file_bytes(path, MAX_IMAGE_BYTES).map_err(|e| e.to_string())?;
    image::ImageReader::new(std::io::Cursor::new(bytes)).with_guessed_format().map_err(|e| e.to_string())?.decode().map_err(|e| e.to_string())
}

/// Reads the float channels of an EXR written by [`write_exr`] (tests, tools):
/// channel name → samples, and the size.
pub fn read_exr_channels(path: &Path) -> Result<(u32, u32, Vec<(String, Vec<f32>)>), String> {
    use exr::prelude::*;
    // 16384² pixels of 10 float channels.
    let bytes = crate::bounded::read_file_bytes(path, 16 << 30).map_err(|e| e.to_string())?;
    let reader = read().no_deep_data().largest_resolution_level().all_channels().all_layers().all_attributes();
    let image = reader.from_buffered(std::io::Cursor::new(bytes)).map_err(|e| e.to_string())?;
    let layer = image.layer_data.into_iter().next().ok_or("no layer")?;
    let size = layer.size;
    let channels = layer
        .channel_data
        .list
        .into_iter()
        .map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect()))
        .collect();
    Ok((size.0 as u32, size.1 as u32, channels))
}
