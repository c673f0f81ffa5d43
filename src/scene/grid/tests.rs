//! The grid's tests: file formats and their errors, the interpolant, its
//! Lipschitz bound and its bounding box.

use super::*;
use std::path::PathBuf;

/// A small deterministic generator (xorshift64*), so failures reproduce.
pub(super) struct Rng(u64);

impl Rng {
    pub(super) fn new(seed: u64) -> Rng {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    pub(super) fn unit(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    pub(super) fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    pub(super) fn point(&mut self, lo: [f64; 3], hi: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|k| self.range(lo[k], hi[k]))
    }
}

/// A fresh file path under the temp dir (unique per process and call).
pub(super) fn temp_path(name: &str) -> PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static N: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!("isotrace-grid-{}-{}", std::process::id(), N.fetch_add(1, Ordering::Relaxed)));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

const AT: Placement = Placement { origin: [0.0; 3], spacing: 1.0 };

/// A `.npy` file's bytes with the given version, header dict and data.
fn npy_bytes(major: u8, dict: &str, data: &[u8]) -> Vec<u8> {
    let mut out = b"\x93NUMPY".to_vec();
    out.extend_from_slice(&[major, 0]);
    let header = format!("{dict}\n");
    if major == 1 {
        out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    } else {
        out.extend_from_slice(&(header.len() as u32).to_le_bytes());
    }
    out.extend_from_slice(header.as_bytes());
    out.extend_from_slice(data);
    out
}

fn f4(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// The error text of reading `bytes` as `pebble.npy`.
fn npy_err(bytes: &[u8]) -> String {
    Grid::from_npy("pebble.npy", bytes, AT).unwrap_err().to_string()
}

/// A 4 x 3 x 2 grid (nx, ny, nz) whose value is its storage index.
fn counting() -> Grid {
    Grid::new([4, 3, 2], [1.0, 2.0, 3.0], 0.5, (0..24).map(|i| i as f32).collect()).unwrap()
}

#[test]
fn npy_round_trip_is_identical_and_64_byte_aligned() {
    let g = Grid::sphere(9, 1.5, 1.0);
    let bytes = g.to_npy();
    assert_eq!(&bytes[..10], b"\x93NUMPY\x01\x00\x76\x00");
    assert_eq!((10 + 0x76) % 64, 0);
    assert!(std::str::from_utf8(&bytes[10..128]).unwrap().starts_with("{'descr': '<f4', 'fortran_order': False, 'shape': (9, 9, 9), }"));
    let back = Grid::from_npy("s.npy", &bytes, Placement { origin: g.origin(), spacing: g.spacing() }).unwrap();
    assert_eq!(back, g);
    // Through a file and load().
    let path = temp_path("sphere.npy");
    std::fs::write(&path, &bytes).unwrap();
    assert_eq!(load(&path, Some(Placement { origin: g.origin(), spacing: g.spacing() })).unwrap(), g);
}

#[test]
fn npy_axes_are_z_y_x_with_x_fastest() {
    let g = counting();
    assert!(String::from_utf8_lossy(&g.to_npy()).contains("'shape': (2, 3, 4)"));
    // values[x + nx (y + ny z)]: sample (1, 2, 1) is 1 + 4 (2 + 3) = 21.
    assert_eq!(g.value(1, 2, 1), 21.0);
    assert_eq!(g.eval([1.5, 3.0, 3.5]), 21.0);
}

#[test]
fn npy_f8_fortran_order_and_versions_2_and_3() {
    let g = counting();
    let c_f8: Vec<u8> = g.values().iter().flat_map(|&v| f64::from(v).to_le_bytes()).collect();
    let dict = |d: &str, f: &str| format!("{{'descr': '{d}', 'fortran_order': {f}, 'shape': (2, 3, 4), }}");
    let read = |b: Vec<u8>| Grid::from_npy("g.npy", &b, Placement { origin: [1.0, 2.0, 3.0], spacing: 0.5 }).unwrap();
    assert_eq!(read(npy_bytes(1, &dict("<f8", "False"), &c_f8)), g);
    // Fortran order: a[z, y, x] at z + nz (y + ny x).
    let mut fortran = Vec::new();
    for x in 0..4 {
        for y in 0..3 {
            for z in 0..2 {
                fortran.push(g.value(x, y, z));
            }
        }
    }
    assert_eq!(read(npy_bytes(1, &dict("<f4", "True"), &f4(&fortran))), g);
    assert_eq!(read(npy_bytes(2, &dict("<f4", "False"), &f4(g.values()))), g);
    assert_eq!(read(npy_bytes(3, &dict("<f4", "False"), &f4(g.values()))), g);
    // Key order, double quotes, no trailing comma, Python 2's 3L.
    let odd = "{\"shape\": (2L, 3L, 4L), \"fortran_order\": False, \"descr\": \"<f4\"}";
    assert_eq!(read(npy_bytes(1, odd, &f4(g.values()))), g);
}

#[test]
fn npy_errors_name_the_file_and_the_problem() {
    let d = |descr: &str, shape: &str| format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    assert_eq!(npy_err(&npy_bytes(1, &d("<f4", "(4, 4)"), &[0; 64])), "pebble.npy: expected a 3-dimensional array of shape (nz, ny, nx), indexed a[z, y, x], found shape (4, 4)");
    assert_eq!(npy_err(&npy_bytes(1, &d("<f4", "(5,)"), &[0; 20])), "pebble.npy: expected a 3-dimensional array of shape (nz, ny, nx), indexed a[z, y, x], found shape (5,)");
    assert_eq!(npy_err(&npy_bytes(1, &d("<i4", "(2, 2, 2)"), &[0; 32])), "pebble.npy: dtype '<i4' is not supported; expected '<f4' or '<f8'");
    assert_eq!(npy_err(&npy_bytes(1, &d(">f4", "(2, 2, 2)"), &[0; 32])), "pebble.npy: dtype '>f4' is not supported; expected '<f4' or '<f8'");
    assert_eq!(npy_err(&npy_bytes(1, &d("<f4", "(32, 32, 32)"), &[0; 4000])), "pebble.npy: truncated: the header says 32768 values but the file holds 1000");
    assert_eq!(npy_err(&npy_bytes(1, &d("<f4", "(2, 2, 2)"), &[0; 34])), "pebble.npy: 2 bytes after the 8 values the header announces");
    assert_eq!(npy_err(&npy_bytes(1, &d("<f4", "(300, 300, 300)"), &[])), "pebble.npy: 300 x 300 x 300 voxels is above the limit of 16777216");
    assert_eq!(npy_err(&npy_bytes(1, &d("<f4", "(4, 1, 5)"), &[0; 80])), "pebble.npy: 5 x 1 x 4 voxels: every dimension must be at least 2 (a cell needs two samples a side)");
    let mut v = vec![0f32; 6 * 6 * 6];
    v[3 + 6 * (4 + 6 * 5)] = f32::NAN;
    v[5 + 6 * (5 + 6 * 5)] = f32::INFINITY;
    assert_eq!(npy_err(&npy_bytes(1, &d("<f4", "(6, 6, 6)"), &f4(&v))), "pebble.npy: voxel (3, 4, 5) is NaN");
    v[3 + 6 * (4 + 6 * 5)] = 0.0;
    assert_eq!(npy_err(&npy_bytes(1, &d("<f4", "(6, 6, 6)"), &f4(&v))), "pebble.npy: voxel (5, 5, 5) is inf");
    let big: Vec<u8> = (0..8).flat_map(|i| if i == 6 { 1e300f64 } else { 0.0 }.to_le_bytes()).collect();
    assert_eq!(npy_err(&npy_bytes(1, &d("<f8", "(2, 2, 2)"), &big)), "pebble.npy: voxel (0, 1, 1) is 1e300, beyond the f32 range");
    assert_eq!(Grid::from_npy("grid.npy", b"PK\x03\x04 not numpy", AT).unwrap_err().to_string(), "grid.npy: not a NumPy file (no \\x93NUMPY magic)");
    assert_eq!(npy_err(b"\x93NUMPY\x04\x00"), "pebble.npy: NumPy format version 4.0 is not supported; expected 1.0, 2.0 or 3.0");
    assert_eq!(npy_err(&npy_bytes(1, "{'descr': '<f4', 'shape': (2, 2, 2), }", &[0; 32])), "pebble.npy: bad NumPy header: no 'fortran_order' key");
    assert_eq!(npy_err(&npy_bytes(1, "{'descr': '<f4', 'order': 1}", &[])), "pebble.npy: bad NumPy header: expected a string, True, False or a tuple of integers (at byte 26 of the header)");
    let mut cut = npy_bytes(1, &d("<f4", "(2, 2, 2)"), &[]);
    cut.truncate(30);
    assert_eq!(npy_err(&cut), "pebble.npy: bad NumPy header: the header length is 63 bytes but the file ends before");
}

#[test]
fn load_checks_extension_placement_and_size() {
    let e = |p: &std::path::Path, pl| load(p, pl).unwrap_err().to_string();
    let p = temp_path("pebble.obj");
    assert_eq!(e(&p, Some(AT)), format!("{}: unknown grid file type '.obj'; supported: .npy (NumPy) and .vdb (OpenVDB level set)", p.display()));
    let p = temp_path("pebble");
    assert_eq!(e(&p, Some(AT)), format!("{}: unknown grid file type (no extension); supported: .npy (NumPy) and .vdb (OpenVDB level set)", p.display()));
    let p = temp_path("pebble.npy");
    assert_eq!(e(&p, None), format!("{}: a .npy file holds only values: the grid's spacing and origin must be given", p.display()));
    assert!(e(&p, Some(AT)).starts_with(&format!("{}: No such file", p.display())), "{}", e(&p, Some(AT)));
    let v = temp_path("rock.vdb");
    assert_eq!(e(&v, Some(AT)), format!("{}: a .vdb file has its own voxel size and origin: spacing and origin must not be given", v.display()));
    // A sparse file one byte over the limit: refused from its size, unread.
    let f = std::fs::File::create(&p).unwrap();
    f.set_len(MAX_GRID_FILE_BYTES + 1).unwrap();
    assert_eq!(e(&p, Some(AT)), format!("{}: larger than the limit of 268435456 bytes (256 MiB)", p.display()));
    std::fs::remove_file(&p).unwrap();
}

#[test]
fn grid_new_validates_placement_and_counts() {
    let e = |d, o, s, v| Grid::new(d, o, s, v).unwrap_err().to_string();
    assert_eq!(e([2, 2, 2], [0.0; 3], 0.0, vec![0.0; 8]), "spacing must be finite and > 0, found 0");
    assert_eq!(e([2, 2, 2], [0.0, f64::NAN, 0.0], 1.0, vec![0.0; 8]), "origin[1] = NaN with spacing 1: the grid's box must be finite");
    assert_eq!(e([2, 2, 2], [0.0; 3], 1.0, vec![0.0; 7]), "7 values for 2 x 2 x 2 voxels");
    assert_eq!(e([2, 2, 2], [0.0; 3], 1.0, vec![f32::NEG_INFINITY; 8]), "voxel (0, 0, 0) is -inf");
}

#[test]
fn eval_is_exact_at_samples_and_reproduces_linear_functions() {
    let g = counting();
    for z in 0..2 {
        for y in 0..3 {
            for x in 0..4 {
                let p = [1.0 + 0.5 * x as f64, 2.0 + 0.5 * y as f64, 3.0 + 0.5 * z as f64];
                assert_eq!(g.eval(p), f64::from(g.value(x, y, z)), "sample ({x}, {y}, {z})");
            }
        }
    }
    // 0.25x − 0.5y + 0.125z + 2 over a 9 x 7 x 5 grid, values exact in f32.
    let lin = |p: [f64; 3]| 0.25 * p[0] - 0.5 * p[1] + 0.125 * p[2] + 2.0;
    let g = Grid::from_fn([9, 7, 5], [-1.0, 0.5, 2.0], 0.25, lin).unwrap();
    let (lo, hi) = g.extent();
    let mut rng = Rng::new(1);
    for _ in 0..10_000 {
        let p = rng.point(lo, hi);
        assert!((g.eval(p) - lin(p)).abs() < 1e-9, "{p:?}: {} vs {}", g.eval(p), lin(p));
    }
    // The cell gradient of a linear field is its gradient, in every cell.
    assert!((g.lipschitz_above(f64::NEG_INFINITY) - (0.25f64.powi(2) + 0.25 + 0.125f64.powi(2)).sqrt().max(1.0)).abs() < 1e-12);
}

/// Largest |f − (|p| − 1)| found over `n` random points of the shell
/// |p| ∈ [1 − w, 1 + w].
fn sphere_error(g: &Grid, n: usize, w: f64, rng: &mut Rng) -> f64 {
    let mut worst: f64 = 0.0;
    for _ in 0..n {
        let dir = loop {
            let d = rng.point([-1.0; 3], [1.0; 3]);
            let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            if l > 0.1 && l <= 1.0 {
                break d.map(|c| c / l);
            }
        };
        let r = rng.range(1.0 - w, 1.0 + w);
        worst = worst.max((g.eval(dir.map(|c| c * r)) - (r - 1.0)).abs());
    }
    worst
}

#[test]
fn sphere_grid_is_within_a_fraction_of_spacing_squared_near_the_surface() {
    let g = Grid::sphere(64, 1.5, 1.0);
    let s = g.spacing();
    let err = sphere_error(&g, 100_000, 0.1, &mut Rng::new(2));
    // Measured: 0.000627 = 0.28 s² (s = 3/63); the trilinear error of
    // |p| − 1 is about s²/8 times the sum of its curvatures, 2/|p| ≤ 2/0.9.
    assert!(err < 0.3 * s * s, "error {err} vs spacing² {}", s * s);
    assert!(err > 0.01 * s * s, "error {err}: suspiciously exact");
}

#[test]
fn outside_the_box_the_extension_is_a_lower_bound_within_root_2() {
    let g = Grid::sphere(64, 1.5, 1.0);
    let tol = 0.3 * g.spacing() * g.spacing();
    let mut rng = Rng::new(3);
    let mut seen = 0;
    for _ in 0..20_000 {
        let p = rng.point([-4.0; 3], [4.0; 3]);
        if p.iter().all(|c| c.abs() <= 1.5) {
            continue;
        }
        seen += 1;
        let truth = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 1.0;
        let f = g.eval(p);
        // Never above the distance (safe for sphere tracing), and not far below.
        assert!(f <= truth + tol, "{p:?}: {f} above the distance {truth}");
        assert!(f >= (truth - tol) / 2f64.sqrt(), "{p:?}: {f} far below the distance {truth}");
    }
    assert!(seen > 15_000);
    // The plain sum g + h would give 2.052 here, above the distance 1.865;
    // sqrt(g² + h²) gives 1.451.
    let f = g.eval([2.5, 1.4, 0.0]);
    assert!((f - 1.4514).abs() < 1e-3, "{f}");
}

#[test]
fn lipschitz_of_sdf_grids_and_of_a_scaled_one() {
    let g = Grid::sphere(64, 1.5, 1.0);
    // Where the field is ≥ 0 (away from the centre's kink): ≈ 1.
    let above = g.lipschitz_above(0.0);
    assert!((1.0..=1.05).contains(&above), "{above}");
    // The kink at the centre: the cell corner next to it has one-sided
    // differences of 0.79 spacing along all three axes, 1.37 together.
    let all = g.lipschitz();
    assert!((1.3..=1.45).contains(&all), "{all}");
    let g2 = Grid::from_fn([64; 3], [-1.5; 3], 3.0 / 63.0, |p| 2.0 * ((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 1.0)).unwrap();
    let above2 = g2.lipschitz_above(0.0);
    assert!((2.0..=2.1).contains(&above2), "{above2}");
    assert!((above2 - 2.0 * above).abs() < 1e-6, "{above2} vs 2 × {above}");
}

/// Finite differences between random pairs never exceed the bound: pairs
/// anywhere against `lipschitz()`, pairs with both ends ≥ 0 (on a segment
/// that stays ≥ 0, checked at 16 points) against `lipschitz_above(0)`.
#[test]
fn finite_differences_stay_below_the_bounds() {
    for (g, seed) in [(Grid::sphere(24, 1.5, 1.0), 4), (Grid::pebble(), 5), (box_cut_sphere(), 6)] {
        let (all, above) = (g.lipschitz(), g.lipschitz_above(0.0));
        let mut rng = Rng::new(seed);
        let (worst_all, worst_above) = (std::cell::Cell::new(0.0f64), std::cell::Cell::new(0.0f64));
        for _ in 0..50_000 {
            let a = rng.point([-3.0; 3], [3.0; 3]);
            let step = rng.range(1e-4, 0.3);
            let dir = rng.point([-1.0; 3], [1.0; 3]);
            let l = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt().max(1e-9);
            let b = [0, 1, 2].map(|k| a[k] + dir[k] / l * step);
            let slope = (g.eval(a) - g.eval(b)).abs() / step;
            assert!(slope <= all * (1.0 + 1e-9), "slope {slope} > L {all} between {a:?} and {b:?}");
            worst_all.set(worst_all.get().max(slope));
            let positive = (0..=16).all(|i| g.eval([0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * i as f64 / 16.0)) >= 0.0);
            if positive {
                assert!(slope <= above * (1.0 + 1e-9), "slope {slope} > L⁺ {above} between {a:?} and {b:?}");
                worst_above.set(worst_above.get().max(slope));
            }
        }
        assert!(worst_all.get() > 0.9 && worst_above.get() > 0.9, "{} {}", worst_all.get(), worst_above.get());
    }
}

/// A sphere of radius 1.2 sampled on [−1, 1]³: the solid is cut by the
/// box, so the outside extension's g + h branch is used.
fn box_cut_sphere() -> Grid {
    Grid::from_fn([20; 3], [-1.0; 3], 2.0 / 19.0, |p| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 1.2).unwrap()
}

#[test]
fn bounding_box_holds_every_point_at_or_below_r() {
    for (g, name) in [(Grid::sphere(32, 1.5, 1.0), "sphere"), (Grid::pebble(), "pebble"), (box_cut_sphere(), "cut sphere"), (Grid::sphere(16, 1.0, 0.4), "small")] {
        let (lo, hi) = g.extent();
        let (c, w) = ([0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k])), [0, 1, 2].map(|k| hi[k] - lo[k]));
        for r in [0.0, 0.3] {
            let b = g.bounding_box(r).unwrap_or_else(|| panic!("{name}: no box for r = {r}"));
            let mut rng = Rng::new(7);
            let mut inside = 0;
            for _ in 0..200_000 {
                let p = rng.point([0, 1, 2].map(|k| c[k] - w[k]), [0, 1, 2].map(|k| c[k] + w[k]));
                if g.eval(p) <= r {
                    inside += 1;
                    assert!((0..3).all(|k| b.min[k] <= p[k] && p[k] <= b.max[k]), "{name}, r = {r}: {p:?} (f = {}) outside {b:?}", g.eval(p));
                }
            }
            assert!(inside > 100, "{name}: only {inside} samples at or below {r}");
        }
    }
    // Every sample above r and a positive boundary: nothing.
    assert_eq!(Grid::sphere(8, 1.0, 0.01).bounding_box(-0.5), None);
}

#[test]
fn bounding_box_of_the_sphere_is_tight() {
    let g = Grid::sphere(64, 1.5, 1.0);
    for r in [0.0, 0.3] {
        let b = g.bounding_box(r).unwrap();
        for k in 0..3 {
            // The true box is ±(1 + r); cells straddling it add < 1 spacing.
            assert!(b.min[k] <= -(1.0 + r) && b.min[k] > -(1.0 + r) - 2.0 * g.spacing(), "r = {r}: {b:?}");
            assert!(b.max[k] >= 1.0 + r && b.max[k] < 1.0 + r + 2.0 * g.spacing(), "r = {r}: {b:?}");
        }
    }
    // The set reaches past the box when r is larger than the margin: grown
    // by sqrt(r² − m²), m ≈ 0.204 the smallest face sample.
    let b = Grid::sphere(16, 1.0, 0.8).bounding_box(0.5).unwrap();
    assert!(b.max.iter().chain(&b.min.map(|c| -c)).all(|&c| c > 1.45 && c < 1.46), "{b:?}");
}

#[test]
fn pebble_example_matches_its_generator() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/pebble.npy");
    let g = Grid::pebble();
    let file = load(&path, Some(Placement { origin: [-1.175; 3], spacing: 0.05 })).unwrap();
    assert_eq!(file.dims(), [48; 3]);
    let worst = file.values().iter().zip(g.values()).map(|(a, b)| (a - b).abs()).fold(0.0f32, f32::max);
    assert!(worst < 1e-6, "examples/pebble.npy differs from Grid::pebble() by {worst}: regenerate it");
    assert!(std::fs::metadata(&path).unwrap().len() < 1 << 20);
    // The surface is well inside the box, and the field is near a distance.
    assert!(g.bounding_box(0.0).unwrap().max.iter().all(|&c| c < 1.0));
    let l = g.lipschitz_above(0.0);
    assert!((1.0..1.15).contains(&l), "{l}");
}

/// Writes examples/pebble.npy: `cargo test --release --lib write_pebble_example -- --ignored`.
#[test]
#[ignore]
fn write_pebble_example() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/pebble.npy");
    std::fs::write(path, Grid::pebble().to_npy()).unwrap();
}

#[test]
fn a_grid_placed_anew_keeps_its_samples() {
    let g = Grid::sphere(16, 1.5, 1.0);
    let moved = g.placed(Placement { origin: [1.0, 2.0, 3.0], spacing: g.spacing() / 2.0 }).unwrap();
    assert_eq!(moved.values(), g.values());
    assert_eq!(moved.origin(), [1.0, 2.0, 3.0]);
    // Half the spacing doubles every gradient inside (the bound is measured again).
    assert!(g.lipschitz() > 1.0 && (moved.lipschitz() - 2.0 * g.lipschitz()).abs() < 1e-9, "{} {}", moved.lipschitz(), g.lipschitz());
    assert_eq!(g.placed(Placement { origin: [0.0; 3], spacing: -1.0 }).unwrap_err().to_string(), "spacing must be finite and > 0, found -1");
}
