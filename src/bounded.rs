//! Reads of untrusted input with a stated size limit.
//!
//! Every input isotrace reads (a formula on stdin or in a file, an `.iso`
//! file, an `--inline` WGSL file, the boxes of `eval`) may be endless:
//! `yes | isotrace check -` must end with an error, not with the process
//! killed for lack of memory. So nothing is read whole before its size is
//! known: at most `limit + 1` bytes are read, and one byte over the limit is
//! the error.

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
    let mut text = String::from_utf8(read_bytes(r, limit)?).map_err(|e| ReadError::NotUtf8 { offset: e.utf8_error().valid_up_to() })?;
    if text.starts_with('\u{feff}') {
        text.drain(..'\u{feff}'.len_utf8());
    }
    Ok(text)
}

/// Reads the file at `path` as UTF-8 text if it holds at most `limit`
/// bytes. The size is checked while reading, not from the metadata, so a
/// FIFO or `/dev/zero` is bounded too.
pub fn read_file_text(path: &Path, limit: u64) -> Result<String, ReadError> {
    read_text(std::fs::File::open(path)?, limit)
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
    fn limits_read_in_binary_units() {
        assert_eq!(bytes(65536), "65536 bytes (64 KiB)");
        assert_eq!(bytes(1 << 20), "1048576 bytes (1 MiB)");
        assert_eq!(bytes(100), "100 bytes");
    }
}
