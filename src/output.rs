//! Image files: PNG (8-bit sRGB) and OpenEXR (float channels), always
//! written atomically (temporary file in the same directory + rename).

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
}

/// The file formats isotrace writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// 8-bit sRGB PNG.
    Png,
    /// OpenEXR with float channels.
    Exr,
}

/// The format a path asks for, by extension (case-insensitive).
pub fn format_of(path: &Path) -> Result<Format, OutputError> {
    match path.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase()).as_deref() {
        Some("png") => Ok(Format::Png),
        Some("exr") => Ok(Format::Exr),
        _ => Err(OutputError::UnknownExtension { path: path.to_path_buf() }),
    }
}

fn tmp_path(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.tmp", std::process::id()))
}

/// Checks, before any work, that `path`'s directory exists and is writable
/// (by creating and removing the temporary file).
pub fn check_writable(path: &Path) -> Result<(), OutputError> {
    let tmp = tmp_path(path);
    std::fs::File::create(&tmp).map_err(|source| OutputError::Io { path: path.to_path_buf(), source })?;
    let _ = std::fs::remove_file(&tmp);
    Ok(())
}

/// Writes through a temporary file and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    write_atomic_with(path, |f| f.write_all(bytes).map_err(|e| e.to_string()))
}

/// Like [`write_atomic`], with the content produced by `fill`.
pub fn write_atomic_with(
    path: &Path,
    fill: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> Result<(), String>,
) -> Result<(), OutputError> {
    let tmp = tmp_path(path);
    let io = |source| OutputError::Io { path: path.to_path_buf(), source };
    let file = std::fs::File::create(&tmp).map_err(io)?;
    let mut w = std::io::BufWriter::new(file);
    let result = fill(&mut w)
        .map_err(|message| OutputError::Encode { path: path.to_path_buf(), message })
        .and_then(|_| w.flush().map_err(io))
        .and_then(|_| std::fs::rename(&tmp, path).map_err(io));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}
