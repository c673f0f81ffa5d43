//! Whether a frame file on disk is a whole frame of the expected size:
//! what `render --skip-existing` asks before leaving a frame alone, and
//! `manifest merge` before counting one as complete.
//!
//! isotrace writes frames atomically, so a file it wrote is whole; a file
//! damaged afterwards (a copy that stopped, a full disk, an empty file made
//! by hand) must not pass for a frame. The check reads the little that
//! tells a whole file from a cut one, not the pixels:
//!
//! - PNG: the signature, the IHDR chunk's width and height, then chunk
//!   headers only (each chunk's data is skipped by its length) up to the
//!   IEND chunk, which must lie inside the file. A file cut anywhere ends
//!   before its IEND; a zero-filled tail is not a chunk.
//! - EXR: the header (its data window gives the size) and offset tables,
//!   then the last block of scan lines (isotrace writes them in increasing
//!   order, so that block is the end of the file), read and decompressed.
//!
//! Damage inside a file that keeps its length (flipped bits) is not seen:
//! that would take decoding every frame, as long as writing it.

use crate::output::Format;
use std::io::{BufReader, Read, Seek};
use std::path::Path;

const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];

/// Checks that `path` is a regular file holding a whole `format` image of
/// `width` × `height` pixels; the error says what is wrong with it.
pub fn check(path: &Path, format: Format, width: u32, height: u32) -> Result<(), String> {
    let file = crate::bounded::open_regular(path).map_err(|e| match e {
        crate::bounded::ReadError::NotRegular { kind } => format!("not a regular file ({kind})"),
        e => format!("cannot be read: {e}"),
    })?;
    let len = file.metadata().map_err(|e| format!("cannot be read: {e}"))?.len();
    if len == 0 {
        return Err("an empty file".into());
    }
    match format {
        Format::Png => check_png(&mut BufReader::new(file), len, width, height),
        Format::Exr => check_exr(BufReader::new(file), width, height),
    }
}

/// The PNG walk of the module documentation over `r`, which holds `len`
/// bytes.
pub fn check_png(r: &mut (impl Read + Seek), len: u64, width: u32, height: u32) -> Result<(), String> {
    let cut = |at: u64, what: &str| format!("a PNG file cut short: it ends at byte {len}, inside {what} at byte {at}");
    let mut signature = [0u8; 8];
    if r.read_exact(&mut signature).is_err() || signature != PNG_SIGNATURE {
        return Err("not a PNG file (no PNG signature)".into());
    }
    let mut at = 8u64;
    loop {
        let mut head = [0u8; 8];
        r.read_exact(&mut head).map_err(|_| cut(at, "a chunk header"))?;
        let length = u64::from(u32::from_be_bytes([head[0], head[1], head[2], head[3]]));
        let kind = &head[4..8];
        if !kind.iter().all(u8::is_ascii_alphabetic) || length > i32::MAX as u64 {
            return Err(format!("a damaged PNG file: byte {at} does not start a chunk"));
        }
        let kind_name = String::from_utf8_lossy(kind).into_owned();
        let end = at + 12 + length;
        if end > len {
            return Err(cut(at, &format!("its {kind_name} chunk")));
        }
        if at == 8 {
            if kind != b"IHDR" || length != 13 {
                return Err("a damaged PNG file: it does not start with its IHDR chunk".into());
            }
            let mut size = [0u8; 8];
            r.read_exact(&mut size).map_err(|_| cut(at, "its IHDR chunk"))?;
            let w = u32::from_be_bytes([size[0], size[1], size[2], size[3]]);
            let h = u32::from_be_bytes([size[4], size[5], size[6], size[7]]);
            if (w, h) != (width, height) {
                return Err(format!("a PNG of {w}x{h} pixels, not {width}x{height}"));
            }
            r.seek_relative(length as i64 - 8 + 4).map_err(|e| e.to_string())?;
        } else if kind == b"IEND" {
            return Ok(());
        } else {
            r.seek_relative(length as i64 + 4).map_err(|e| e.to_string())?;
        }
        at = end;
    }
}

/// The EXR check of the module documentation over `r`.
pub fn check_exr(r: impl Read + Seek, width: u32, height: u32) -> Result<(), String> {
    use exr::block::chunk::Chunk;
    use exr::block::UncompressedBlock;
    let damaged = |e: exr::error::Error| format!("not a whole EXR file: {e}");
    let reader = exr::block::read(r, false).map_err(damaged)?;
    let [header] = reader.headers() else { return Err("an EXR file of several layers; isotrace writes one".into()) };
    let (w, h) = (header.layer_size.width(), header.layer_size.height());
    if (w, h) != (width as usize, height as usize) {
        return Err(format!("an EXR of {w}x{h} pixels, not {width}x{height}"));
    }
    let meta = reader.meta_data().clone();
    let last = reader.filter_chunks(false, |_, _, block| block.pixel_position.y() + block.pixel_size.height() == h).map_err(damaged)?;
    let chunks: Vec<Chunk> = last.collect::<Result<_, _>>().map_err(damaged)?;
    if chunks.is_empty() {
        return Err("a damaged EXR file: no block holds its last scan line".into());
    }
    for chunk in chunks {
        UncompressedBlock::decompress_chunk(chunk, &meta, false).map_err(damaged)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Cursor;

    fn png(width: u32, height: u32) -> Vec<u8> {
        let mut bytes = Vec::new();
        crate::output::encode_png(&mut bytes, width, height, &vec![90; (width * height * 3) as usize]).unwrap();
        bytes
    }

    fn png_check(bytes: &[u8], width: u32, height: u32) -> Result<(), String> {
        check_png(&mut Cursor::new(bytes), bytes.len() as u64, width, height)
    }

    #[test]
    fn a_whole_png_of_the_size_passes_and_every_cut_fails() {
        let whole = png(7, 5);
        assert_eq!(png_check(&whole, 7, 5), Ok(()));
        assert_eq!(png_check(&whole, 8, 5), Err("a PNG of 7x5 pixels, not 8x5".into()));
        for len in 0..whole.len() {
            assert!(png_check(&whole[..len], 7, 5).is_err(), "cut at {len} passed");
        }
        let at = whole.len() - 12;
        assert_eq!(png_check(&whole[..whole.len() - 1], 7, 5), Err(format!("a PNG file cut short: it ends at byte {}, inside its IEND chunk at byte {at}", whole.len() - 1)));
        assert_eq!(png_check(b"GIF89a....", 7, 5), Err("not a PNG file (no PNG signature)".into()));
        // A zero-filled tail, as a crash may leave: the length is kept, the chunks are not.
        let mut zeros = whole.clone();
        let half = zeros.len() / 2;
        zeros[half..].fill(0);
        assert!(png_check(&zeros, 7, 5).unwrap_err().starts_with("a "), "zero-filled tail passed");
    }

    #[test]
    fn a_whole_exr_of_the_size_passes_and_a_cut_one_fails() {
        let dir = std::env::temp_dir().join(format!("isotrace-frame-check-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("f.exr");
        let pixel = crate::render::PixelOut { color: [0.5; 4], normal: [0.0; 3], depth: 1.0, evals: 1, level: 0, iso: 0, status: crate::render::Status::Hit };
        let frame = crate::render::Frame { width: 9, height: 40, pixels: vec![pixel; 9 * 40], stats: Default::default() };
        crate::output::write_exr(&path, &frame).unwrap();
        let whole = std::fs::read(&path).unwrap();
        assert_eq!(check(&path, Format::Exr, 9, 40), Ok(()));
        assert_eq!(check(&path, Format::Exr, 9, 41), Err("an EXR of 9x40 pixels, not 9x41".into()));
        for len in [0, 50, whole.len() / 2, whole.len() - 1] {
            assert!(check_exr(Cursor::new(&whole[..len]), 9, 40).is_err(), "cut at {len} passed");
        }
        std::fs::write(&path, b"").unwrap();
        assert_eq!(check(&path, Format::Exr, 9, 40), Err("an empty file".into()));
        assert_eq!(check(&dir, Format::Png, 9, 40), Err("not a regular file (a directory)".into()));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
