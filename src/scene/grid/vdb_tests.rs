//! `.vdb` tests on fixtures written by OpenVDB 10 itself
//! (tests/grid/make_vdb_fixtures.py, Debian's python3-openvdb).

use super::tests::Rng;
use super::*;
use std::path::PathBuf;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/grid").join(name)
}

fn vdb_err(name: &str, grid: Option<&str>) -> String {
    Grid::from_vdb(name, &std::fs::read(fixture(name)).unwrap(), grid).unwrap_err().to_string()
}

/// The fixture sphere: radius 0.3, centre (0.1, 0, 0) in index space
/// translated by (0.02, −0.01, 0.03), voxel size 0.05 as an f32,
/// background 0.15.
const CENTRE: [f64; 3] = [0.12, -0.01, 0.03];

#[test]
fn level_set_equals_openvdbs_own_dense_copy() {
    let g = load(&fixture("sphere.vdb"), None).unwrap();
    assert_eq!(g.dims(), [17; 3]);
    assert_eq!(g.spacing(), 0.05000000074505806);
    // Voxel (−6, −8, −8), the active box's low corner, as OpenVDB places it.
    let want = [-0.28000000447034834, -0.4100000059604645, -0.37000000596046445];
    assert!((0..3).all(|k| (g.origin()[k] - want[k]).abs() < 1e-12), "{:?}", g.origin());
    // copyToArray's values, inactive ones included (±background by side).
    let dense = load(&fixture("sphere_dense.npy"), Some(Placement { origin: g.origin(), spacing: g.spacing() })).unwrap();
    assert_eq!(g, dense);
    assert!(g.values().contains(&-0.15f32) && g.values().contains(&0.15f32));
}

/// vdb-rs 0.6 reads an 8-byte size before every half-float block, but
/// OpenVDB writes none for a block of 0 values (`HalfWriter::write`
/// returns at once), which every internal node of a narrow band is: the
/// reader loses its place ("Invalid node meta-data: 15" on this file).
#[test]
fn half_float_level_sets_are_refused_with_the_reason() {
    assert_eq!(
        vdb_err("sphere_half.vdb", None),
        "sphere_half.vdb: grid 'surface' is saved as half floats, which vdb-rs 0.6 misreads (it expects a size field that OpenVDB omits for empty half-float blocks); save it with full floats"
    );
}

#[test]
fn level_set_is_a_distance_near_its_surface_and_solid_inside() {
    let g = load(&fixture("sphere.vdb"), None).unwrap();
    let truth = |p: [f64; 3]| (0..3).map(|k| (p[k] - CENTRE[k]).powi(2)).sum::<f64>().sqrt() - 0.3;
    // Inside, 6 voxels from the band: the flooded sign, −background.
    assert_eq!(g.eval(CENTRE), -0.15000000596046448);
    let mut rng = Rng::new(8);
    let mut worst: f64 = 0.0;
    for _ in 0..20_000 {
        let p = rng.point(CENTRE.map(|c| c - 0.4), CENTRE.map(|c| c + 0.4));
        let d = truth(p);
        let f = g.eval(p);
        if d.abs() < 0.05 {
            worst = worst.max((f - d).abs());
        }
        if d.abs() > 0.01 {
            assert_eq!(f < 0.0, d < 0.0, "{p:?}: {f} vs {d}");
        }
    }
    // Measured 0.0025 (spacing 0.05, so about s²): the band values are distances.
    assert!(worst < 0.005, "{worst}");
    assert!(g.bounding_box(0.0).is_some_and(|b| (0..3).all(|k| b.min[k] < CENTRE[k] - 0.3 && b.max[k] > CENTRE[k] + 0.3)));
}

#[test]
fn grids_are_chosen_by_name_and_non_level_sets_refused() {
    let listing = "'a' (Tree_float_5_4_3, level set), 'density' (Tree_float_5_4_3, fog volume), 'rotated' (Tree_float_5_4_3, level set)";
    assert_eq!(vdb_err("several.vdb", None), format!("several.vdb: 2 float level sets; name one: {listing}"));
    assert_eq!(vdb_err("several.vdb", Some("nope")), format!("several.vdb: no grid named 'nope'; the file has {listing}"));
    assert_eq!(vdb_err("several.vdb", Some("density")), "several.vdb: grid 'density' is Tree_float_5_4_3, class fog volume; only float level sets are distance fields");
    assert_eq!(
        vdb_err("several.vdb", Some("rotated")),
        "several.vdb: grid 'rotated': transform 'AffineMap' is not supported (vdb-rs reads UniformScaleMap, UniformScaleTranslateMap and ScaleTranslateMap)"
    );
    let a = Grid::from_vdb("several.vdb", &std::fs::read(fixture("several.vdb")).unwrap(), Some("a")).unwrap();
    assert!(a.eval([0.0; 3]) < -0.05, "{}", a.eval([0.0; 3]));
}

#[test]
fn broken_vdb_files_give_errors_not_crashes() {
    let e = |b: &[u8]| Grid::from_vdb("rock.vdb", b, None).unwrap_err().to_string();
    assert_eq!(e(b"garbage, not a volume at all"), "rock.vdb: not an OpenVDB file (no ' BDV' magic)");
    let p = tests::temp_path("rock.vdb");
    std::fs::write(&p, b"\x20BDV\0\0\0\0\xe0\0\0\0\x0a").unwrap();
    assert_eq!(load(&p, None).unwrap_err().to_string(), format!("{}: a record of 8 bytes at offset 12 runs past the end of the file (1 bytes left)", p.display()));
    let mut old = std::fs::read(fixture("sphere.vdb")).unwrap();
    old[8..12].copy_from_slice(&221u32.to_le_bytes());
    assert_eq!(e(&old), "rock.vdb: OpenVDB file version 221 is not supported (vdb-rs reads version 222, OpenVDB 3.0, and later)");
    // Every prefix of a real file: an error each time (a panic inside
    // vdb-rs would be one too; none may abort).
    let full = std::fs::read(fixture("sphere.vdb")).unwrap();
    for len in (0..full.len()).step_by(1499) {
        assert!(Grid::from_vdb("cut.vdb", &full[..len], None).is_err(), "prefix of {len} bytes");
    }
    // Random damage: 3 bytes changed, 400 times. Before the layout walk,
    // one of these aborted the process on a 2⁵⁷-byte allocation.
    let mut rng = tests::Rng::new(99);
    let mut refused = 0;
    for _ in 0..400 {
        let mut b = full.clone();
        for _ in 0..3 {
            let i = (rng.unit() * b.len() as f64) as usize;
            b[i] = (rng.unit() * 256.0) as u8;
        }
        refused += usize::from(Grid::from_vdb("damaged.vdb", &b, None).is_err());
    }
    assert!(refused > 20, "{refused}");
}
