//! Reads of untrusted input: regular files only, with a stated size limit.
//!
//! Every input isotrace reads (a formula on stdin or in a file, an `.iso`
//! file, an `--inline` WGSL file, a scene and its grid files, an
//! environment image, a manifest or a report, the boxes of `eval`) may be
//! endless: `yes | isotrace check -` must end with an error, not with the
//! process killed for lack of memory. So nothing is read whole before its
//! size is known: at most `limit + 1` bytes are read, and one byte over the
//! limit is the error.
//!
//! A named file is opened only when it is a regular file ([`open_regular`]):
//! a FIFO with no writer would block the open (and the read) forever, a
//! device may be endless or have effects when read. Standard input (`-`) is
//! the one stream read, by the callers that accept it.
//!
//! Files named inside other files (an `.iso` header's `env:` image, a
//! scene's grid `file`) are kept inside the naming file's directory by
//! [`leaves_dir`] unless the user allows more.

use std::io::{BufRead, Read};
use std::path::Path;

/// Why a bounded read failed.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// The source could not be opened or read.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// The source holds more than `limit` bytes.
    #[error("larger than the limit of {}", bytes(*.limit))]
    TooLarge {
        /// The limit in bytes.
        limit: u64,
    },
    /// The bytes are not UTF-8 text.
    #[error("not UTF-8 text (invalid byte at offset {offset})")]
    NotUtf8 {
        /// Offset of the first invalid byte.
        offset: usize,
    },
    /// The path names something other than a regular file.
    #[error("not a regular file ({kind})")]
    NotRegular {
        /// What it is.
        kind: FileKind,
    },
}

/// What a path names when it is not a regular file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum FileKind {
    /// A directory.
    #[error("a directory")]
    Directory,
    /// A named pipe.
    #[error("a FIFO")]
    Fifo,
    /// A character device (`/dev/null`, a terminal).
    #[error("a character device")]
    CharDevice,
    /// A block device (a disk).
    #[error("a block device")]
    BlockDevice,
    /// A Unix domain socket.
    #[error("a socket")]
    Socket,
    /// Anything else that is not a regular file.
    #[error("a special file")]
    Other,
}

impl FileKind {
    /// `None` for a regular file (and for a symbolic link, which only
    /// `symlink_metadata` reports), else what the file is.
    pub fn of(t: std::fs::FileType) -> Option<FileKind> {
        if t.is_file() || t.is_symlink() {
            return None;
        }
        if t.is_dir() {
            return Some(FileKind::Directory);
        }
        #[cfg(unix)]
        {
            use std::os::unix::fs::FileTypeExt;
            let kinds = [
                (t.is_fifo(), FileKind::Fifo),
                (t.is_char_device(), FileKind::CharDevice),
                (t.is_block_device(), FileKind::BlockDevice),
                (t.is_socket(), FileKind::Socket),
            ];
            if let Some((_, k)) = kinds.into_iter().find(|(is, _)| *is) {
                return Some(k);
            }
        }
        Some(FileKind::Other)
    }
}

/// Opens `path` for reading if it is a regular file (a symbolic link is
/// followed). The type is checked before opening, so a device is never
/// opened, and again on the opened file, since the name may have been
/// replaced in between; the open does not block (`O_NONBLOCK`), so a FIFO
/// put there meanwhile is refused instead of waiting for a writer.
pub fn open_regular(path: &Path) -> Result<std::fs::File, ReadError> {
    let refuse = |m: std::fs::Metadata| match FileKind::of(m.file_type()) {
        Some(kind) => Err(ReadError::NotRegular { kind }),
        None => Ok(m),
    };
    refuse(std::fs::metadata(path)?)?;
    let file = open_nonblocking(path)?;
    refuse(file.metadata()?)?;
    Ok(file)
}

#[cfg(unix)]
fn open_nonblocking(path: &Path) -> std::io::Result<std::fs::File> {
    use std::os::unix::fs::OpenOptionsExt;
    use std::os::unix::io::AsRawFd;
    let file = std::fs::OpenOptions::new().read(true).custom_flags(libc::O_NONBLOCK | libc::O_NOCTTY).open(path)?;
    // Back to blocking reads for the regular file it turns out to be.
    // SAFETY: fcntl on a descriptor this function owns, with valid flags.
    unsafe {
        let flags = libc::fcntl(file.as_raw_fd(), libc::F_GETFL);
        if flags >= 0 {
            libc::fcntl(file.as_raw_fd(), libc::F_SETFL, flags & !libc::O_NONBLOCK);
        }
    }
    Ok(file)
}

#[cfg(not(unix))]
fn open_nonblocking(path: &Path) -> std::io::Result<std::fs::File> {
    std::fs::File::open(path)
}

/// `65536 bytes (64 KiB)`: a limit as the messages state it.
pub fn bytes(n: u64) -> String {
    match n {
        n if n >= 1 << 20 && n % (1 << 20) == 0 => format!("{n} bytes ({} MiB)", n >> 20),
        n if n >= 1 << 10 && n % (1 << 10) == 0 => format!("{n} bytes ({} KiB)", n >> 10),
        n => format!("{n} bytes"),
    }
}

/// Reads all of `r` if it holds at most `limit` bytes.
pub fn read_bytes(r: impl Read, limit: u64) -> Result<Vec<u8>, ReadError> {
    let mut buf = Vec::new();
    r.take(limit.saturating_add(1)).read_to_end(&mut buf)?;
    if buf.len() as u64 > limit {
        return Err(ReadError::TooLarge { limit });
    }
    Ok(buf)
}

/// Reads all of `r` as UTF-8 text if it holds at most `limit` bytes. A
/// byte-order mark at the start (which some editors write into UTF-8
/// files) is dropped: it is not part of the text.
pub fn read_text(r: impl Read, limit: u64) -> Result<String, ReadError> {
    text_of(read_bytes(r, limit)?)
}

/// `bytes` as UTF-8 text without a leading byte-order mark.
fn text_of(bytes: Vec<u8>) -> Result<String, ReadError> {
    let mut text = String::from_utf8(bytes).map_err(|e| ReadError::NotUtf8 { offset: e.utf8_error().valid_up_to() })?;
    if text.starts_with('\u{feff}') {
        text.drain(..'\u{feff}'.len_utf8());
    }
    Ok(text)
}

/// Reads the regular file at `path` ([`open_regular`]) if it holds at most
/// `limit` bytes: refused from its size first, and the read stops one byte
/// past the limit either way (a file may grow while it is read).
pub fn read_file_bytes(path: &Path, limit: u64) -> Result<Vec<u8>, ReadError> {
    let file = open_regular(path)?;
    if file.metadata()?.len() > limit {
        return Err(ReadError::TooLarge { limit });
    }
    read_bytes(file, limit)
}

/// [`read_file_bytes`] as UTF-8 text (a leading byte-order mark dropped,
/// as [`read_text`] does).
pub fn read_file_text(path: &Path, limit: u64) -> Result<String, ReadError> {
    text_of(read_file_bytes(path, limit)?)
}

/// Whether `p`, as written in a file in `dir` (an `.iso` header's `env:`
/// image, a scene's grid `file`), names a file outside `dir`: an absolute
/// path, a relative one that climbs above `dir` with `..`, or one that
/// exists and resolves (through symbolic links) outside the resolved `dir`.
/// A file that does not exist is not outside: reading it fails anyway.
pub fn leaves_dir(dir: &Path, p: &Path) -> bool {
    use std::path::Component;
    let mut depth = 0i32;
    for c in p.components() {
        match c {
            Component::Normal(_) => depth += 1,
            Component::ParentDir => depth -= 1,
            Component::CurDir => {}
            Component::RootDir | Component::Prefix(_) => return true,
        }
        if depth < 0 {
            return true;
        }
    }
    let base = if dir.as_os_str().is_empty() { Path::new(".") } else { dir };
    match (base.canonicalize(), base.join(p).canonicalize()) {
        (Ok(d), Ok(f)) => !f.starts_with(d),
        _ => false,
    }
}

/// Reads the next line (without its `\n`, or `\r\n`) into `line` if it
/// holds at most `limit` bytes; `Ok(false)` at the end of the input.
/// A longer line is [`ReadError::TooLarge`] after reading `limit + 1`
/// bytes of it, so one endless line cannot fill the memory.
pub fn read_line(r: &mut impl BufRead, line: &mut Vec<u8>, limit: u64) -> Result<bool, ReadError> {
    line.clear();
    let n = r.by_ref().take(limit.saturating_add(2)).read_until(b'\n', line)?;
    if n == 0 {
        return Ok(false);
    }
    if line.last() == Some(&b'\n') {
        line.pop();
        if line.last() == Some(&b'\r') {
            line.pop();
        }
    }
    if line.len() as u64 > limit {
        return Err(ReadError::TooLarge { limit });
    }
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_up_to_the_limit_and_refuses_one_byte_more() {
        assert_eq!(read_bytes(&b"abcd"[..], 4).unwrap(), b"abcd");
        assert!(matches!(read_bytes(&b"abcde"[..], 4), Err(ReadError::TooLarge { limit: 4 })));
        // An endless source ends after limit + 1 bytes.
        assert!(matches!(read_bytes(std::io::repeat(b'y'), 1000), Err(ReadError::TooLarge { limit: 1000 })));
        assert!(matches!(read_text(&b"a\xffb"[..], 10), Err(ReadError::NotUtf8 { offset: 1 })));
        assert_eq!(read_text(&b"\xef\xbb\xbfx\xef\xbb\xbf"[..], 10).unwrap(), "x\u{feff}");
    }

    #[test]
    fn lines_are_bounded_one_by_one() {
        let mut r = std::io::BufReader::new(&b"12345\r\n123456\n"[..]);
        let mut line = Vec::new();
        assert!(read_line(&mut r, &mut line, 5).unwrap());
        assert_eq!(line, b"12345");
        assert!(matches!(read_line(&mut r, &mut line, 5), Err(ReadError::TooLarge { limit: 5 })));
        let mut r = std::io::BufReader::new(&b"abc"[..]);
        assert!(read_line(&mut r, &mut line, 5).unwrap());
        assert_eq!(line, b"abc");
        assert!(!read_line(&mut r, &mut line, 5).unwrap());
        let mut endless = std::io::BufReader::new(std::io::repeat(b'x'));
        assert!(matches!(read_line(&mut endless, &mut line, 64), Err(ReadError::TooLarge { limit: 64 })));
    }

    #[test]
    fn leaving_the_directory_is_seen_lexically_and_through_links() {
        let d = std::env::temp_dir().join(format!("isotrace-leaves-dir-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(d.join("sub")).unwrap();
        std::fs::write(d.join("sub/in.npy"), b"").unwrap();
        std::fs::write(d.join("out.npy"), b"").unwrap();
        let sub = d.join("sub");
        assert!(!leaves_dir(&sub, Path::new("in.npy")));
        assert!(!leaves_dir(&sub, Path::new("./a/../in.npy")));
        assert!(leaves_dir(&sub, Path::new("../out.npy")));
        assert!(leaves_dir(&sub, Path::new("a/../../out.npy")));
        assert!(leaves_dir(&sub, &d.join("sub/in.npy")), "absolute, even inside");
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(d.join("out.npy"), sub.join("link.npy")).unwrap();
            assert!(leaves_dir(&sub, Path::new("link.npy")));
        }
        let _ = std::fs::remove_dir_all(&d);
    }

    #[cfg(unix)]
    #[test]
    fn only_regular_files_are_opened() {
        let dev = |p: &str| open_regular(Path::new(p)).err().map(|e| e.to_string());
        assert_eq!(dev("/dev/null"), Some("not a regular file (a character device)".into()));
        assert_eq!(dev("/"), Some("not a regular file (a directory)".into()));
        let d = std::env::temp_dir().join(format!("isotrace-open-regular-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        let fifo = d.join("f.npy");
        let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        // SAFETY: a valid NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
        // No writer: a blocking open would wait here forever.
        assert_eq!(open_regular(&fifo).err().map(|e| e.to_string()), Some("not a regular file (a FIFO)".into()));
        std::fs::write(d.join("r.txt"), b"abc").unwrap();
        assert_eq!(read_file_text(&d.join("r.txt"), 3).unwrap(), "abc");
        assert!(matches!(read_file_bytes(&d.join("r.txt"), 2), Err(ReadError::TooLarge { limit: 2 })));
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn limits_read_in_binary_units() {
        assert_eq!(bytes(65536), "65536 bytes (64 KiB)");
        assert_eq!(bytes(1 << 20), "1048576 bytes (1 MiB)");
        assert_eq!(bytes(100), "100 bytes");
    }
}
