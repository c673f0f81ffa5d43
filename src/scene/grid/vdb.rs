//! OpenVDB level sets, through the `vdb-rs` crate (0.6), made dense.
//!
//! **What is read.** A float grid (`Tree_float_5_4_3`) of class "level
//! set": its active voxels and active tiles, and its transform when it is
//! a uniform scale with or without a translation
//! (world = index · voxel size + translation; OpenVDB puts voxel (i, j, k)'s
//! sample at index point (i, j, k)). The dense grid covers the bounding box
//! of the active voxels, one sample per voxel, so the narrow band is
//! complete and every face of the box lies in the band.
//!
//! **What vdb-rs does not give, and what is done instead.** vdb-rs 0.6
//! reads the tree's background value and its root tiles and drops them
//! (`read_tree_topology`), and it sets inactive values stored as ±background
//! to 0 ("jb-todo: proper background value support" in `read_compressed`),
//! so the sign of the inactive voxels — inside or outside — is lost, and
//! with it the level set's interior. So this module
//! - reads the background and the root tiles itself (in the walk of
//!   [`vdb_layout`], which reads the file as vdb-rs will),
//! - fills every inactive voxel of the box with ±background, the sign
//!   flooded from the active voxels (breadth-first, 6 neighbours): each
//!   inactive region is bounded by band voxels of one sign in a well-formed
//!   narrow band, as OpenVDB's own `signedFloodFill` assumes. (Filling with
//!   +background, the rule for other grid classes, would turn the solid
//!   into a hollow shell.)
//!
//! **What is refused**, each with its reason: other value types and grid
//! classes (a fog volume is a density, not a distance); grids saved as half
//! floats (vdb-rs reads an 8-byte size before every half-float block, but
//! OpenVDB's `HalfWriter` writes nothing for a block of 0 values, which
//! every internal node of a narrow band is, so vdb-rs loses its place:
//! "Invalid node meta-data"); instanced grids; other transforms
//! (vdb-rs panics on them), non-uniform or mirrored scales, file versions
//! before 222 (OpenVDB 3.0: vdb-rs has `todo!()`s for older ones), active
//! root tiles (4096³ voxels each), and boxes above the voxel limit.
//!
//! **Hardening.** vdb-rs allocates buffers of sizes read from the file
//! before reading them, so the file is first walked by [`vdb_layout`],
//! which checks every length against the bytes left (a corrupted file
//! otherwise aborted the process: "memory allocation of
//! 221869629939707904 bytes failed"). vdb-rs also asserts and panics on
//! some malformed input; each call into it runs under `catch_unwind`, so
//! such a file gives an error (the panic message still reaches stderr
//! through the panic hook). It decodes the whole tree before the voxel
//! limit can be checked on the actual voxels (the file's own bounding-box
//! metadata is checked first, which stops honest large files early); after
//! the walk, the decoded tree is at most about 16 times the file's size (a
//! leaf decodes to 2 KiB of values and takes at least 137 bytes of the
//! file: two 64-byte masks, a flag and a block size). Blosc blocks are decompressed by the C library c-blosc 1.21
//! (through `blosc-src`), after the walk has checked that each block's
//! header agrees with its length and with the values it should hold.

use super::{check_dims, vdb_layout, Grid, GridErrorKind, MAX_GRID_VOXELS};
use std::collections::VecDeque;
use std::io::Cursor;
use std::panic::{catch_unwind, AssertUnwindSafe};
use vdb_rs::{Map, MetadataValue, VdbLevel, VdbReader};

const MAGIC: [u8; 8] = [0x20, 0x42, 0x44, 0x56, 0, 0, 0, 0];

fn err(m: impl Into<String>) -> GridErrorKind {
    GridErrorKind::Vdb(m.into())
}

/// Runs `f`, turning a panic inside vdb-rs into an error.
fn guarded<T>(what: &str, f: impl FnOnce() -> Result<T, GridErrorKind>) -> Result<T, GridErrorKind> {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|p| {
        let msg = p.downcast_ref::<String>().cloned().or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()));
        Err(err(format!("{what}: the vdb-rs reader failed on this file ({})", msg.unwrap_or_else(|| "panic".into()))))
    })
}

/// Parses a `.vdb` file's bytes; see the module doc.
pub(super) fn read(bytes: &[u8], grid_name: Option<&str>) -> Result<Grid, GridErrorKind> {
    if bytes.len() < 8 || bytes[..8] != MAGIC {
        return Err(err("not an OpenVDB file (no ' BDV' magic)"));
    }
    vdb_layout::archive(bytes).map_err(err)?;
    let mut reader = guarded("the file header", || VdbReader::new(Cursor::new(bytes)).map_err(|e| parse_error("the file header", e)))?;
    let name = pick_grid(&reader, grid_name)?;
    let gd = reader.grid_descriptors[&name].clone();
    if !gd.instance_parent.is_empty() {
        return Err(err(format!("grid '{name}' is an instance of grid '{}' (shares its tree); instanced grids are not supported", gd.instance_parent)));
    }
    if gd.meta_data.is_half_float() || gd.grid_type.ends_with("_HalfFloat") {
        return Err(err(format!(
            "grid '{name}' is saved as half floats, which vdb-rs 0.6 misreads (it expects a size field that OpenVDB omits for empty half-float blocks); save it with full floats"
        )));
    }
    let background = vdb_layout::grid(bytes, gd.grid_pos, gd.block_pos).map_err(|m| err(format!("grid '{name}': {m}")))?;
    check_file_bbox(&name, &gd.meta_data.0)?;
    let grid = guarded(&format!("grid '{name}'"), || reader.read_grid::<f32>(&name).map_err(|e| parse_error(&format!("grid '{name}'"), e)))?;
    let (scale, translation) = match grid.transform {
        Map::UniformScaleMap { scale_values: s, .. } => ([s.x, s.y, s.z], [0.0; 3]),
        Map::ScaleTranslateMap { scale_values: s, translation: t, .. } => ([s.x, s.y, s.z], [t.x, t.y, t.z]),
    };
    let spacing = scale[0];
    if spacing.is_nan() || spacing <= 0.0 || scale.iter().any(|&s| (s - spacing).abs() > 1e-9 * spacing) {
        return Err(err(format!("grid '{name}': voxel size {scale:?} is not uniform and positive; a grid has one spacing")));
    }
    // Two passes over the decoded tree (box, then values) rather than a
    // list of every voxel: 16.8 M voxels would be 670 MB as a list.
    let items = || grid.iter().map(|(c, v, level)| ([c.x as i64, c.y as i64, c.z as i64], v, level_size(level)));
    let (lo, dims) = guarded(&format!("grid '{name}'"), || active_box(&name, items()))?;
    let values = guarded(&format!("grid '{name}'"), || Ok(densify(lo, dims, items(), background)))?;
    let origin = [0, 1, 2].map(|k| lo[k] as f64 * spacing + translation[k]);
    Grid::new(dims.map(|d| d as u32), origin, spacing, values)
}

/// vdb-rs's error, with the I/O error's own text (its Display says only
/// "IoError").
fn parse_error(what: &str, e: vdb_rs::ParseError) -> GridErrorKind {
    match e {
        vdb_rs::ParseError::IoError(io) => err(format!("{what}: {io} (the file is cut short or corrupt)")),
        other => err(format!("{what}: {other}")),
    }
}

fn level_size(level: VdbLevel) -> i64 {
    match level {
        VdbLevel::Voxel => 1,
        VdbLevel::Node3 => 8,
        VdbLevel::Node4 => 128,
    }
}

/// The grid named, or the file's only float level set.
fn pick_grid<R: std::io::Read + std::io::Seek>(reader: &VdbReader<R>, wanted: Option<&str>) -> Result<String, GridErrorKind> {
    let mut names: Vec<&String> = reader.grid_descriptors.keys().collect();
    names.sort();
    let describe = |n: &str| {
        let gd = &reader.grid_descriptors[n];
        let class = match gd.meta_data.0.get("class") {
            Some(MetadataValue::String(c)) => c.as_str(),
            _ => "unknown",
        };
        (gd.grid_type.as_str(), class)
    };
    let usable = |n: &str| {
        let (ty, class) = describe(n);
        (ty == "Tree_float_5_4_3" || ty == "Tree_float_5_4_3_HalfFloat") && class == "level set"
    };
    let listing = || names.iter().map(|n| format!("'{n}' ({}, {})", describe(n).0, describe(n).1)).collect::<Vec<_>>().join(", ");
    match wanted {
        Some(w) if !reader.grid_descriptors.contains_key(w) => Err(err(format!("no grid named '{w}'; the file has {}", listing()))),
        Some(w) if !usable(w) => Err(err(format!("grid '{w}' is {}, class {}; only float level sets are distance fields", describe(w).0, describe(w).1))),
        Some(w) => Ok(w.to_string()),
        None => {
            let ok: Vec<&&String> = names.iter().filter(|n| usable(n)).collect();
            match ok.as_slice() {
                [one] => Ok(one.to_string()),
                [] => Err(err(format!("no float level set grid; the file has {}", if names.is_empty() { "no grids".into() } else { listing() }))),
                _ => Err(err(format!("{} float level sets; name one: {}", ok.len(), listing()))),
            }
        }
    }
}

/// Refuses early a grid whose own metadata says it is above the voxel limit.
fn check_file_bbox(name: &str, meta: &std::collections::HashMap<String, MetadataValue>) -> Result<(), GridErrorKind> {
    if let (Some(MetadataValue::Vec3i(a)), Some(MetadataValue::Vec3i(b))) = (meta.get("file_bbox_min"), meta.get("file_bbox_max")) {
        let d = [b.x as i64 - a.x as i64 + 1, b.y as i64 - a.y as i64 + 1, b.z as i64 - a.z as i64 + 1];
        if d.iter().all(|&n| n >= 2) {
            check_dims(d.map(|n| n as u64)).map_err(|e| err(format!("grid '{name}': {e}")))?;
        }
    }
    Ok(())
}

/// The low corner and size of the active voxels' box (tiles included).
fn active_box(name: &str, items: impl Iterator<Item = ([i64; 3], f32, i64)>) -> Result<([i64; 3], [u64; 3]), GridErrorKind> {
    let mut lo = [i64::MAX; 3];
    let mut hi = [i64::MIN; 3];
    for (c, _, size) in items {
        for k in 0..3 {
            lo[k] = lo[k].min(c[k]);
            hi[k] = hi[k].max(c[k] + size - 1);
        }
    }
    if lo[0] == i64::MAX {
        return Err(err(format!("grid '{name}' has no active voxels")));
    }
    let dims = [0, 1, 2].map(|k| (hi[k] - lo[k] + 1) as u64);
    check_dims(dims).map_err(|_| err(format!("grid '{name}': its active voxels span {} x {} x {}, above the limit of {MAX_GRID_VOXELS} voxels (or below 2 a side)", dims[0], dims[1], dims[2])))?;
    Ok((lo, dims))
}

/// The dense samples: active values where given, ±background elsewhere
/// with the sign flooded from the active voxels (module doc).
fn densify(lo: [i64; 3], dims: [u64; 3], items: impl Iterator<Item = ([i64; 3], f32, i64)>, background: f32) -> Vec<f32> {
    let [nx, ny, nz] = dims.map(|d| d as usize);
    let mut values = vec![0f32; nx * ny * nz];
    let mut known = vec![false; values.len()];
    let mut queue = VecDeque::new();
    for (c, v, size) in items {
        let s = size as usize;
        let base = [0, 1, 2].map(|k| (c[k] - lo[k]) as usize);
        for z in base[2]..base[2] + s {
            for y in base[1]..base[1] + s {
                for x in base[0]..base[0] + s {
                    let i = x + nx * (y + ny * z);
                    values[i] = v;
                    known[i] = true;
                    queue.push_back(i);
                }
            }
        }
    }
    let bg = background.abs();
    while let Some(i) = queue.pop_front() {
        let fill = if values[i] < 0.0 { -bg } else { bg };
        let (x, y, z) = (i % nx, (i / nx) % ny, i / (nx * ny));
        let neighbours = [
            (x > 0).then(|| i - 1),
            (x + 1 < nx).then(|| i + 1),
            (y > 0).then(|| i - nx),
            (y + 1 < ny).then(|| i + nx),
            (z > 0).then(|| i - nx * ny),
            (z + 1 < nz).then(|| i + nx * ny),
        ];
        for n in neighbours.into_iter().flatten() {
            if !known[n] {
                known[n] = true;
                values[n] = fill;
                queue.push_back(n);
            }
        }
    }
    values
}
