//! The NumPy `.npy` format, read and written by hand.
//!
//! Why not the `npyz` crate: it reads the header's Python literal through
//! `py_literal`, which brings `pest` and its derive macros, and `num-bigint`
//! — seven crates not otherwise in this build — for a header that is one
//! short dictionary with three known keys. The format
//! (numpy.lib.format, versions 1.0, 2.0 and 3.0): the magic `\x93NUMPY`,
//! two version bytes, the header length (u16 little-endian in 1.0, u32 in
//! 2.0 and 3.0), the header — a Python dict literal
//! `{'descr': '<f4', 'fortran_order': False, 'shape': (nz, ny, nx), }`,
//! ASCII in 1.0 and 2.0, UTF-8 in 3.0, padded with spaces and ended by a
//! newline — then the raw values.

use super::{check_dims, Grid, GridErrorKind, Placement};

const MAGIC: &[u8] = b"\x93NUMPY";

/// A parsed header value.
#[derive(Debug)]
enum Value {
    Str(String),
    Bool(bool),
    Tuple(Vec<u64>),
}

/// Parses `.npy` bytes into a grid placed by `placement`.
pub(super) fn read(bytes: &[u8], placement: Placement) -> Result<Grid, GridErrorKind> {
    if !bytes.starts_with(MAGIC) {
        return Err(GridErrorKind::NotNpy);
    }
    let bad = |m: &str| GridErrorKind::NpyHeader(m.to_string());
    let (major, minor) = match bytes.get(6..8) {
        Some(v) => (v[0], v[1]),
        None => return Err(bad("the file ends inside the version")),
    };
    let (len_bytes, utf8) = match (major, minor) {
        (1, 0) => (2, false),
        (2, 0) => (4, false),
        (3, 0) => (4, true),
        _ => return Err(GridErrorKind::NpyVersion(major, minor)),
    };
    let len_field = bytes.get(8..8 + len_bytes).ok_or_else(|| bad("the file ends inside the header length"))?;
    let header_len = len_field.iter().rev().fold(0usize, |n, &b| n << 8 | b as usize);
    let start = 8 + len_bytes;
    let header = bytes.get(start..start + header_len).ok_or_else(|| bad(&format!("the header length is {header_len} bytes but the file ends before")))?;
    let text = std::str::from_utf8(header).map_err(|_| bad("not UTF-8 text"))?;
    if !utf8 && !text.is_ascii() {
        return Err(bad("non-ASCII text in a version 1.0 or 2.0 header"));
    }
    let (descr, fortran, shape) = fields(text)?;
    let size = match descr.as_str() {
        "<f4" => 4,
        "<f8" => 8,
        _ => return Err(GridErrorKind::Dtype(descr)),
    };
    if shape.len() != 3 {
        return Err(GridErrorKind::Shape(python_tuple(&shape)));
    }
    let (nz, ny, nx) = (shape[0], shape[1], shape[2]);
    let n = check_dims([nx, ny, nz])?;
    let data = &bytes[start + header_len..];
    let held = data.len() / size;
    if held < n {
        return Err(GridErrorKind::Truncated { expected: n as u64, found: held as u64 });
    }
    if data.len() > n * size {
        return Err(GridErrorKind::TrailingBytes { expected: n as u64, extra: (data.len() - n * size) as u64 });
    }
    let (nx, ny, nz) = (nx as usize, ny as usize, nz as usize);
    let mut values = vec![0f32; n];
    for (k, chunk) in data.chunks_exact(size).enumerate() {
        let v = if size == 4 { f64::from(f32::from_le_bytes(chunk.try_into().unwrap())) } else { f64::from_le_bytes(chunk.try_into().unwrap()) };
        // C order: a[z, y, x] at x + nx·(y + ny·z), our layout. Fortran
        // order: the first index fastest, a[z, y, x] at z + nz·(y + ny·x).
        let (x, y, z) = if fortran { (k / (nz * ny), (k / nz) % ny, k % nz) } else { (k % nx, (k / nx) % ny, k / (nx * ny)) };
        let f = v as f32;
        if !f.is_finite() {
            return Err(first_bad(data, size, fortran, [nx, ny, nz]));
        }
        values[x + nx * (y + ny * z)] = f;
    }
    Grid::new([nx, ny, nz].map(|d| d as u32), placement.origin, placement.spacing, values)
}

/// The error for the first non-finite value in our (x fastest) order, so
/// the voxel named does not depend on the file's order.
fn first_bad(data: &[u8], size: usize, fortran: bool, [nx, ny, nz]: [usize; 3]) -> GridErrorKind {
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let k = if fortran { z + nz * (y + ny * x) } else { x + nx * (y + ny * z) };
                let b = &data[k * size..(k + 1) * size];
                let v = if size == 4 { f64::from(f32::from_le_bytes(b.try_into().unwrap())) } else { f64::from_le_bytes(b.try_into().unwrap()) };
                if !(v as f32).is_finite() {
                    return GridErrorKind::NotFinite { index: [x, y, z].map(|c| c as u64), value: v };
                }
            }
        }
    }
    unreachable!("first_bad is called after a non-finite value was seen")
}

/// `(4, 4)`, `(5,)`, `()`: a shape as Python prints it.
fn python_tuple(v: &[u64]) -> String {
    match v {
        [one] => format!("({one},)"),
        _ => format!("({})", v.iter().map(|d| d.to_string()).collect::<Vec<_>>().join(", ")),
    }
}

/// The header's (descr, fortran_order, shape); every key exactly once and
/// no other.
fn fields(text: &str) -> Result<(String, bool, Vec<u64>), GridErrorKind> {
    let mut p = Parser { s: text.as_bytes(), i: 0 };
    let (mut descr, mut fortran, mut shape) = (None, None, None);
    p.expect(b'{')?;
    loop {
        p.skip_ws();
        if p.eat(b'}') {
            break;
        }
        let key = p.string()?;
        p.skip_ws();
        p.expect(b':')?;
        let value = p.value()?;
        let dup = match (key.as_str(), value) {
            ("descr", Value::Str(s)) => descr.replace(s).is_some(),
            ("fortran_order", Value::Bool(b)) => fortran.replace(b).is_some(),
            ("shape", Value::Tuple(t)) => shape.replace(t).is_some(),
            ("descr" | "fortran_order" | "shape", v) => return Err(p.error(&format!("'{key}' has an unexpected value {v:?}"))),
            _ => return Err(p.error(&format!("unknown key '{key}'; expected descr, fortran_order and shape"))),
        };
        if dup {
            return Err(p.error(&format!("'{key}' given twice")));
        }
        p.skip_ws();
        if !p.eat(b',') {
            p.skip_ws();
            p.expect(b'}')?;
            break;
        }
    }
    if p.s[p.i..].iter().any(|b| !b.is_ascii_whitespace()) {
        return Err(p.error("text after the dictionary"));
    }
    let missing = |k: &str| GridErrorKind::NpyHeader(format!("no '{k}' key"));
    Ok((descr.ok_or_else(|| missing("descr"))?, fortran.ok_or_else(|| missing("fortran_order"))?, shape.ok_or_else(|| missing("shape"))?))
}

/// Just enough of Python's literal syntax for a `.npy` header: strings in
/// single or double quotes (no escapes: dtype strings have none), True,
/// False, and tuples of non-negative integers.
struct Parser<'a> {
    s: &'a [u8],
    i: usize,
}

impl Parser<'_> {
    fn error(&self, m: &str) -> GridErrorKind {
        GridErrorKind::NpyHeader(format!("{m} (at byte {} of the header)", self.i))
    }

    fn skip_ws(&mut self) {
        while self.s.get(self.i).is_some_and(|b| b.is_ascii_whitespace()) {
            self.i += 1;
        }
    }

    fn eat(&mut self, b: u8) -> bool {
        let hit = self.s.get(self.i) == Some(&b);
        self.i += usize::from(hit);
        hit
    }

    fn expect(&mut self, b: u8) -> Result<(), GridErrorKind> {
        self.skip_ws();
        if self.eat(b) { Ok(()) } else { Err(self.error(&format!("expected '{}'", b as char))) }
    }

    fn string(&mut self) -> Result<String, GridErrorKind> {
        let q = match self.s.get(self.i) {
            Some(&q @ (b'\'' | b'"')) => q,
            _ => return Err(self.error("expected a quoted string")),
        };
        let start = self.i + 1;
        let len = self.s[start..].iter().position(|&b| b == q).ok_or_else(|| self.error("unterminated string"))?;
        self.i = start + len + 1;
        Ok(String::from_utf8_lossy(&self.s[start..start + len]).into_owned())
    }

    fn value(&mut self) -> Result<Value, GridErrorKind> {
        self.skip_ws();
        let rest = &self.s[self.i..];
        if rest.starts_with(b"True") || rest.starts_with(b"False") {
            let t = rest[0] == b'T';
            self.i += if t { 4 } else { 5 };
            return Ok(Value::Bool(t));
        }
        if self.eat(b'(') {
            let mut v = Vec::new();
            loop {
                self.skip_ws();
                if self.eat(b')') {
                    return Ok(Value::Tuple(v));
                }
                v.push(self.integer()?);
                self.skip_ws();
                if !self.eat(b',') {
                    self.expect(b')')?;
                    return Ok(Value::Tuple(v));
                }
            }
        }
        self.string().map(Value::Str).map_err(|_| self.error("expected a string, True, False or a tuple of integers"))
    }

    fn integer(&mut self) -> Result<u64, GridErrorKind> {
        let start = self.i;
        while self.s.get(self.i).is_some_and(u8::is_ascii_digit) {
            self.i += 1;
        }
        let digits = std::str::from_utf8(&self.s[start..self.i]).unwrap();
        // Python 2's NumPy wrote long integers with an L suffix: (3L, 4L).
        self.eat(b'L');
        // An absurd dimension saturates: the voxel limit reports it.
        match digits {
            "" => Err(self.error("expected a dimension (a non-negative integer)")),
            d => Ok(d.parse::<u64>().unwrap_or(u64::MAX)),
        }
    }
}

/// Format 1.0, `<f4`, C order, shape (nz, ny, nx); the header padded so
/// the data starts at a multiple of 64 bytes, as NumPy writes it.
pub(super) fn write(g: &Grid) -> Vec<u8> {
    let [nx, ny, nz] = g.dims;
    let dict = format!("{{'descr': '<f4', 'fortran_order': False, 'shape': ({nz}, {ny}, {nx}), }}");
    let unpadded = MAGIC.len() + 2 + 2 + dict.len() + 1;
    let header_len = dict.len() + 1 + (64 - unpadded % 64) % 64;
    let mut out = Vec::with_capacity(10 + header_len + 4 * g.values.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&[1, 0]);
    out.extend_from_slice(&(header_len as u16).to_le_bytes());
    out.extend_from_slice(dict.as_bytes());
    out.resize(10 + header_len - 1, b' ');
    out.push(b'\n');
    for v in &g.values {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}
