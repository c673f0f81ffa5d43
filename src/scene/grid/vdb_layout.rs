//! A walk over a `.vdb` file's layout, before vdb-rs reads it, checking
//! every length against the bytes that are left.
//!
//! vdb-rs 0.6 allocates buffers of sizes read from the file before it reads
//! them (`vec![0u8; num_compressed_bytes]`, `String::with_capacity(len)`),
//! so three flipped bytes can ask for 2⁵⁷ bytes and abort the process; and
//! it hands a blosc block to c-blosc trusting the sizes in the block's own
//! header. This walk reads the file exactly as vdb-rs will (the same
//! records in the same order, with vdb-rs's reading of each, not
//! OpenVDB's where they differ: a "bool" metadata value is 1 byte whatever
//! its length says) and refuses the file when a length runs past its end, a
//! blosc block is shorter than its header or its header disagrees with the
//! values it should hold. So every buffer vdb-rs then allocates is bounded
//! by the file's size, or by a node's 32768 values. It also returns what
//! vdb-rs drops: the tree's background value (and it refuses active root
//! tiles, which vdb-rs also drops).

/// File versions this walk (and vdb-rs) reads: 222 (OpenVDB 3.0) and later.
pub(super) const MIN_VERSION: u32 = 222;

/// Compression flags of a grid (OpenVDB's `COMPRESS_*`).
const ZIP: u32 = 1;
const ACTIVE_MASK: u32 = 2;
const BLOSC: u32 = 4;

/// A little-endian cursor over the file that reports running off its end.
struct Bytes<'a> {
    b: &'a [u8],
    i: usize,
}

type Walk<T> = Result<T, String>;

impl Bytes<'_> {
    fn at(b: &[u8], i: u64) -> Walk<Bytes<'_>> {
        match usize::try_from(i) {
            Ok(i) if i <= b.len() => Ok(Bytes { b, i }),
            _ => Err(format!("an offset ({i}) points past the end of the file ({} bytes)", b.len())),
        }
    }
    fn take(&mut self, n: u64) -> Walk<&[u8]> {
        let left = (self.b.len() - self.i) as u64;
        if n > left {
            return Err(format!("a record of {n} bytes at offset {} runs past the end of the file ({left} bytes left)", self.i));
        }
        let s = &self.b[self.i..self.i + n as usize];
        self.i += n as usize;
        Ok(s)
    }
    fn u8(&mut self) -> Walk<u8> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Walk<u32> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().unwrap()))
    }
    fn u64(&mut self) -> Walk<u64> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().unwrap()))
    }
    fn string(&mut self) -> Walk<String> {
        let n = self.u32()?;
        Ok(String::from_utf8_lossy(self.take(u64::from(n))?).into_owned())
    }
    /// A bit mask of `bits` bits; returns how many are set, and their indices.
    fn mask(&mut self, bits: usize) -> Walk<Vec<usize>> {
        let b = self.take(bits as u64 / 8)?;
        Ok((0..bits).filter(|&k| b[k / 8] >> (k % 8) & 1 == 1).collect())
    }
}

/// vdb-rs's `read_metadata`: a count, then per entry a name, a type name,
/// a length, and a value read by type.
fn metadata(r: &mut Bytes) -> Walk<()> {
    for _ in 0..r.u32()? {
        r.string()?;
        let ty = r.string()?;
        let len = r.u32()?;
        match ty.as_str() {
            "string" => r.take(u64::from(len))?,
            "bool" => r.take(1)?,
            "int32" | "float" => r.take(4)?,
            "int64" => r.take(8)?,
            "vec3i" => r.take(12)?,
            _ => r.take(u64::from(len))?,
        };
    }
    Ok(())
}

/// Walks the archive header and every grid descriptor (what
/// `VdbReader::new` reads) and returns each grid's (name, grid offset,
/// blocks offset).
pub(super) fn archive(b: &[u8]) -> Walk<Vec<(String, u64, u64)>> {
    let mut r = Bytes { b, i: 8 };
    let version = r.u32()?;
    if version < MIN_VERSION {
        return Err(format!("OpenVDB file version {version} is not supported (vdb-rs reads version {MIN_VERSION}, OpenVDB 3.0, and later)"));
    }
    r.take(8)?; // library version
    if r.u8()? != 1 {
        return Err("the file has no grid offsets (vdb-rs needs them)".into());
    }
    r.take(36)?; // the UUID
    metadata(&mut r)?;
    let mut grids = Vec::new();
    for _ in 0..r.u32()? {
        let name = r.string()?;
        r.string()?; // grid type
        r.string()?; // instance parent
        let (grid_pos, block_pos, end_pos) = (r.u64()?, r.u64()?, r.u64()?);
        // OpenVDB writes each descriptor, then its grid, then the next one:
        // an offset pointing back would make both walks loop.
        if end_pos <= r.i as u64 {
            return Err(format!("grid '{name}' ends at offset {end_pos}, before its descriptor"));
        }
        if grids.iter().any(|(n, _, _)| *n == name) {
            return Err(format!("two grids are named '{name}'"));
        }
        let mut g = Bytes::at(b, grid_pos)?;
        g.u32()?; // compression
        metadata(&mut g)?;
        grids.push((name, grid_pos, block_pos));
        r = Bytes::at(b, end_pos)?;
    }
    Ok(grids)
}

/// Walks one grid (what vdb-rs's `read_grid` reads: metadata, transform,
/// tree topology, then the leaf buffers at `block_pos`) and returns its
/// background value.
pub(super) fn grid(b: &[u8], grid_pos: u64, block_pos: u64) -> Walk<f32> {
    let mut r = Bytes::at(b, grid_pos)?;
    let compression = r.u32()?;
    metadata(&mut r)?;
    let map = r.string()?;
    let triples = match map.as_str() {
        "UniformScaleMap" => 5,
        "UniformScaleTranslateMap" | "ScaleTranslateMap" => 6,
        other => return Err(format!("transform '{other}' is not supported (vdb-rs reads UniformScaleMap, UniformScaleTranslateMap and ScaleTranslateMap)")),
    };
    r.take(triples * 24)?;
    let buffers = r.u32()?;
    if buffers != 1 {
        return Err(format!("{buffers} buffers per node are not supported (vdb-rs reads 1)"));
    }
    let background = f32::from_le_bytes(r.take(4)?.try_into().unwrap());
    let (tiles, roots) = (r.u32()?, r.u32()?);
    for _ in 0..tiles {
        r.take(16)?;
        if r.u8()? != 0 {
            return Err("an active root tile (4096³ voxels) is above the voxel limit".into());
        }
    }
    // Topology: per root child, an internal node of 32³ and its children of
    // 16³, whose leaves' value masks come here and their values later.
    let mut leaves = 0u64;
    for _ in 0..roots {
        r.take(12)?;
        let children = node(&mut r, 5, compression)?;
        for _ in children {
            for _ in node(&mut r, 4, compression)? {
                r.take(64)?;
                leaves += 1;
            }
        }
    }
    let mut r = Bytes::at(b, block_pos)?;
    for _ in 0..leaves {
        let active = r.mask(512)?.len();
        values(&mut r, 512, active, compression)?;
    }
    if !background.is_finite() {
        return Err(format!("the background value {background} is not finite"));
    }
    Ok(background)
}

/// An internal node of 2^(3·log2) entries: child mask, value mask, values;
/// returns its children's indices.
fn node(r: &mut Bytes, log2: u32, compression: u32) -> Walk<Vec<usize>> {
    let n = 1usize << (3 * log2);
    let children = r.mask(n)?;
    let active = r.mask(n)?.len();
    values(r, n, active, compression)?;
    Ok(children)
}

/// vdb-rs's `read_compressed` of `n` f32 values, `active` of them active.
fn values(r: &mut Bytes, n: usize, active: usize, compression: u32) -> Walk<()> {
    let meta = r.u8()?;
    if meta > 6 {
        return Err(format!("invalid node metadata {meta}"));
    }
    r.take(match meta {
        2 | 4 => 4,
        5 => 8,
        _ => 0,
    })?;
    if matches!(meta, 3..=5) {
        r.take(n as u64 / 8)?;
    }
    let count = if compression & ACTIVE_MASK != 0 && meta != 6 { active } else { n };
    let bytes = 4 * count as u64;
    if compression & (BLOSC | ZIP) == 0 {
        r.take(bytes)?;
        return Ok(());
    }
    let size = r.u64()? as i64;
    if size <= 0 {
        // Stored raw: vdb-rs reads (−size / 4) values.
        let raw = 4 * (size / 4).unsigned_abs();
        if compression & BLOSC != 0 && raw != bytes {
            return Err(format!("a raw block of {raw} bytes where {count} values belong"));
        }
        r.take(raw)?;
        return Ok(());
    }
    let block = r.take(size as u64)?;
    if compression & BLOSC != 0 && count > 0 {
        // c-blosc's header: version bytes, then nbytes and cbytes (u32 at 4 and 12).
        if block.len() < 16 {
            return Err(format!("a blosc block of {} bytes, shorter than its header", block.len()));
        }
        let word = |k: usize| u64::from(u32::from_le_bytes(block[k..k + 4].try_into().unwrap()));
        if word(4) != bytes || word(12) > block.len() as u64 {
            return Err(format!("a blosc block of {} bytes claims {} bytes compressed to {}, where {count} values belong", block.len(), word(4), word(12)));
        }
    }
    Ok(())
}
