//! The surface catalog: the built-in `.iso` files and the header parser.

use crate::catalog::{self, CatalogError, Clip, Status, parse_box, parse_eps, parse_iso, parse_vec3};
use crate::Formula;
use std::collections::BTreeSet;
use std::path::Path;

fn err_text(r: Result<catalog::Entry, CatalogError>) -> String {
    r.expect_err("expected an error").to_string()
}

#[test]
fn every_builtin_parses_and_compiles() {
    let all = catalog::builtin();
    assert!(all.len() >= 22, "{} entries", all.len());
    for e in &all {
        assert!(e.path.is_none(), "{}: a built-in has no path", e.name);
        let f = Formula::compile(&e.origin(), &e.formula).unwrap_or_else(|err| panic!("{}: {err}", e.name));
        assert_eq!(f.origin, format!("@{}", e.name));
        assert!(e.compile().is_ok());
    }
}

#[test]
fn builtin_table_lists_every_example_file_with_its_stem_as_name() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut on_disk = BTreeSet::new();
    for f in std::fs::read_dir(&dir).unwrap() {
        let p = f.unwrap().path();
        if p.extension().is_some_and(|x| x == "iso") {
            let stem = p.file_stem().unwrap().to_str().unwrap().to_string();
            let text = std::fs::read_to_string(&p).unwrap();
            let from_disk = catalog::load_file(&p).unwrap();
            assert_eq!(from_disk.name, stem);
            assert_eq!(from_disk.path.as_deref(), Some(p.as_path()));
            let builtin = catalog::lookup(&stem).unwrap();
            assert_eq!(builtin.formula, text, "{stem}: embedded text differs from the file");
            assert_eq!(builtin.header, from_disk.header);
            on_disk.insert(stem);
        }
    }
    let names: Vec<String> = catalog::builtin().into_iter().map(|e| e.name).collect();
    let unique: BTreeSet<String> = names.iter().cloned().collect();
    assert_eq!(unique.len(), names.len(), "duplicate names in {names:?}");
    assert_eq!(unique, on_disk, "the include_str! table and examples/*.iso differ");
}

#[test]
fn the_16_knoll_surfaces_are_present_and_fully_described() {
    let knoll = catalog::suite("knoll").unwrap();
    assert_eq!(knoll.len(), 16);
    for name in knoll {
        let e = catalog::lookup(name).unwrap_or_else(|err| panic!("{err}"));
        assert_eq!(e.name, name);
    }
    for e in catalog::builtin() {
        let h = &e.header;
        assert!(h.title.is_some() && h.degree.is_some() && h.source.is_some() && h.notes.is_some(), "{}", e.name);
        // A status says whether a named surface's formula is the published
        // one; the distance-field scenes are isotrace's own and have none.
        let scene = h.method == Some(catalog::Method::Sphere);
        assert!(h.status.is_some() != scene, "{}: status {:?}, method {:?}", e.name, h.status, h.method);
    }
    let status = |n: &str| catalog::lookup(n).unwrap().header.status.unwrap();
    for n in ["teardrop", "4-bretzel", "superquadric", "icos.csg", "sq.csg", "sin.blob", "cloth", "water"] {
        assert_eq!(status(n), Status::Reconstruction, "{n}");
    }
    for n in ["sphere", "steiner", "mitchell", "klein-bottle", "tangle", "decocube", "barth-sextic", "barth-decic"] {
        assert_eq!(status(n), Status::Published, "{n}");
    }
    for n in ["barth-sextic", "barth-decic"] {
        assert_eq!(catalog::lookup(n).unwrap().header.clip, Some(Clip::Sphere(2.0)));
    }
    for n in ["sin.blob", "water"] {
        let h = catalog::lookup(n).unwrap().header;
        assert!(h.t.is_some() && h.animate.is_some(), "{n}");
    }
}

/// A header degree that starts with a number is the IR's degree; the others
/// are not polynomials.
#[test]
fn header_degree_matches_the_formula() {
    for e in catalog::builtin() {
        let d = e.header.degree.as_deref().unwrap();
        let ir = e.compile().unwrap().ir;
        let lead: String = d.chars().take_while(char::is_ascii_digit).collect();
        match lead.parse::<u32>() {
            Ok(n) => assert_eq!(ir.degree(), Some(n), "{}", e.name),
            Err(_) => assert_eq!(ir.degree(), None, "{}: degree '{d}'", e.name),
        }
    }
}

/// Every parameter of a formula has a header value, and every header
/// parameter is used.
#[test]
fn header_params_match_the_formula() {
    for e in catalog::builtin() {
        let ir = e.compile().unwrap().ir;
        let used: BTreeSet<&str> = ir.params.iter().map(|(n, _)| n.as_str()).collect();
        let given: BTreeSet<&str> = e.header.params.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(used, given, "{}", e.name);
    }
    assert_eq!(catalog::lookup("torus").unwrap().header.param("r"), Some(0.35));
}

/// The formula changes sign on a grid inside the box, at the header's t and
/// at both ends of an animation range.
#[test]
fn every_surface_changes_sign_inside_its_box() {
    const N: usize = 41;
    for e in catalog::builtin() {
        let ir = e.compile().unwrap().ir;
        let params: Vec<f64> = ir.params.iter().map(|(n, _)| e.header.param(n).unwrap()).collect();
        let b = e.header.bbox;
        let mut times = vec![e.header.t.unwrap_or(0.0)];
        times.extend(e.header.animate.into_iter().flatten());
        for t in times {
            let (mut neg, mut pos) = (0, 0);
            for i in 0..N {
                for j in 0..N {
                    for k in 0..N {
                        let at = |lo: f64, hi: f64, n: usize| lo + (hi - lo) * n as f64 / (N - 1) as f64;
                        let p = [at(b[0], b[1], i), at(b[2], b[3], j), at(b[4], b[5], k), t];
                        let v = crate::reference::eval_scalar(&ir, p, &params);
                        assert!(!v.is_nan(), "{}: NaN at {p:?}", e.name);
                        if v < 0.0 { neg += 1 } else if v > 0.0 { pos += 1 }
                    }
                }
            }
            assert!(neg > 0 && pos > 0, "{} at t = {t}: {neg} negative, {pos} positive samples", e.name);
        }
    }
}

#[test]
fn suggested_cameras_look_from_outside_the_box() {
    for e in catalog::builtin() {
        let h = &e.header;
        if let Some(eye) = h.eye {
            let b = h.bbox;
            let inside = (0..3).all(|a| b[2 * a] <= eye[a] && eye[a] <= b[2 * a + 1]);
            assert!(!inside, "{}: eye inside the box", e.name);
            assert!(h.target.is_some_and(|t| t != eye), "{}: eye without a distinct target", e.name);
        }
    }
}

#[test]
fn a_full_header_parses() {
    let text = "#@ name: demo\n#@ title: A demo\n# a plain comment\n\n#@ box: -1,1,-2,2,-3,3\n#@ t: 0.5\n\
        #@ eye: 4, 3, 2\n#@ target: 0,0,0\n#@ up: 0,0,1\n#@ fov: 30\n#@ eps: 2^-11\n#@ algebra: raa\n\
        #@ param: a=2\n#@ param: b_2 = -1.5\n#@ degree: 2\n#@ status: reconstruction\n#@ source: here\n\
        #@ notes: none\n#@ animate: 0,6.5\n#@ clip: sphere:2.2\na*x^2 + b_2*y - z # the formula\n";
    let e = parse_iso("dir/demo-file.iso", text).unwrap();
    let h = &e.header;
    assert_eq!(e.name, "demo");
    assert_eq!(e.formula, text);
    assert_eq!(h.title.as_deref(), Some("A demo"));
    assert_eq!(h.bbox, [-1.0, 1.0, -2.0, 2.0, -3.0, 3.0]);
    assert_eq!((h.t, h.fov, h.eps), (Some(0.5), Some(30.0), Some(2f64.powi(-11))));
    assert_eq!((h.eye, h.target, h.up), (Some([4.0, 3.0, 2.0]), Some([0.0; 3]), Some([0.0, 0.0, 1.0])));
    assert_eq!(h.algebra, Some(catalog::Algebra::Raa));
    assert_eq!(h.params, vec![("a".to_string(), 2.0), ("b_2".to_string(), -1.5)]);
    assert_eq!(h.status, Some(Status::Reconstruction));
    assert_eq!(h.animate, Some([0.0, 6.5]));
    assert_eq!(h.clip, Some(Clip::Sphere(2.2)));
    assert!(e.compile().is_ok());

    let bare = parse_iso("some/dir/plain.iso", "x - y\n").unwrap();
    assert_eq!(bare.name, "plain");
    assert_eq!(bare.header, catalog::Header::default());
    assert_eq!(bare.header.bbox, catalog::DEFAULT_BOX);
}

#[test]
fn error_unknown_key() {
    let r = parse_iso("examples/x.iso", "#@ name: x\n#@ colour: red\nx\n");
    assert_eq!(err_text(r), "examples/x.iso:2: unknown key 'colour' (did you mean 'color'?)");
    let r = parse_iso("examples/x.iso", "#@ name: x\n#@ zzzzzz: red\nx\n");
    assert!(err_text(r).starts_with("examples/x.iso:2: unknown key 'zzzzzz' (keys: name, title, box,"));
    let r = parse_iso("examples/x.iso", "#@ bx: -1,1\nx\n");
    assert_eq!(err_text(r), "examples/x.iso:1: unknown key 'bx' (did you mean 'box'?)");
}

#[test]
fn error_bad_box() {
    let r = parse_iso("examples/x.iso", "#@ name: x\n#@ title: X\n#@ box: a,b\nx\n");
    assert_eq!(err_text(r), "examples/x.iso:3: bad box value 'a,b': expected 2 or 6 numbers");
    let r = parse_iso("examples/x.iso", "#@ box: -1,1,2,1,0,1\nx\n");
    assert_eq!(err_text(r), "examples/x.iso:1: bad box value '-1,1,2,1,0,1': empty y range: 2 is not below 1");
}

#[test]
fn error_bad_eps() {
    let r = parse_iso("examples/x.iso", "#@ eps: 0\nx\n");
    assert_eq!(err_text(r), "examples/x.iso:1: bad eps value '0': must be greater than 0");
    let r = parse_iso("examples/x.iso", "\n#@ eps: 2^-x\nx\n");
    assert_eq!(err_text(r), "examples/x.iso:2: bad eps value '2^-x': expected a number such as 0.001, 1e-3 or 2^-11");
}

#[test]
fn error_missing_formula() {
    let r = parse_iso("examples/x.iso", "#@ name: x\n#@ box: -1,1\n");
    assert_eq!(err_text(r), "examples/x.iso:3: missing formula: the file has only a header");
    let r = parse_iso("examples/x.iso", "#@ name: x\n# only comments\n\n");
    assert_eq!(err_text(r), "examples/x.iso:4: missing formula: the file has only a header");
}

#[test]
fn error_unknown_name_suggests_close_names() {
    let e = catalog::lookup("tangel").unwrap_err();
    assert_eq!(e.to_string(), "unknown surface 'tangel'; did you mean 'tangle'?");
    match e {
        CatalogError::UnknownName { suggestions, .. } => assert_eq!(suggestions, vec!["tangle".to_string()]),
        other => panic!("{other:?}"),
    }
    let far = catalog::lookup("zzzzzzzzzzzz").unwrap_err().to_string();
    assert!(far.starts_with("unknown surface 'zzzzzzzzzzzz'; the catalog has: sphere, steiner, "), "{far}");
}

/// Every suite names catalog entries; `all` is the whole catalog in its
/// order; an unknown suite lists the known ones.
#[test]
fn suites_name_catalog_entries() {
    for &s in catalog::SUITES {
        let names = catalog::suite(s).unwrap();
        assert!(!names.is_empty(), "{s}");
        for n in names {
            assert_eq!(catalog::lookup(n).unwrap_or_else(|e| panic!("suite {s}: {e}")).name, n);
        }
    }
    let all: Vec<String> = catalog::builtin().into_iter().map(|e| e.name).collect();
    assert_eq!(catalog::suite("all").unwrap(), all);
    let e = catalog::suite("Knoll").unwrap_err();
    assert_eq!(e, CatalogError::UnknownSuite { name: "Knoll".into() });
    assert_eq!(e.to_string(), "unknown suite 'Knoll': expected knoll, sdf or all");
    assert_eq!(catalog::suite_choices(), "knoll, sdf or all");
}

#[test]
fn other_header_errors() {
    let cases = [
        ("#@ name: x\n#@ name: y\nx\n", "f.iso:2: duplicate key 'name' (first given on line 1)"),
        ("#@ param: a=1\n#@ param: a=2\nx\n", "f.iso:2: duplicate param 'a' (first given on line 1)"),
        ("#@ param: 1a=1\nx\n", "f.iso:1: bad param value '1a=1': '1a' is not a parameter name"),
        ("#@ param: a\nx\n", "f.iso:1: bad param value 'a': expected 'name=value'"),
        ("#@ status: draft\nx\n", "f.iso:1: bad status value 'draft': expected 'published' or 'reconstruction'"),
        ("#@ algebra: fast\nx\n", "f.iso:1: bad algebra value 'fast': expected 'ia', 'raa' or 'auto'"),
        ("#@ fov: 180\nx\n", "f.iso:1: bad fov value '180': expected an angle in degrees between 0 and 180 (exclusive)"),
        ("#@ t: soon\nx\n", "f.iso:1: bad t value 'soon': expected a number"),
        ("#@ eye: 1,2\nx\n", "f.iso:1: bad eye value '1,2': expected 3 numbers 'x,y,z'"),
        ("#@ up: 0,0,0\nx\n", "f.iso:1: bad up value '0,0,0': the up vector must not be zero"),
        ("#@ animate: 2,1\nx\n", "f.iso:1: bad animate value '2,1': expected 't0,t1' with t0 < t1"),
        ("#@ clip: cube:2\nx\n", "f.iso:1: bad clip value 'cube:2': expected 'sphere:R' with a radius R > 0"),
        ("#@ method: march\nx\n", "f.iso:1: bad method value 'march': expected 'sphere' or 'bisect'"),
        ("#@ lipschitz: 0.5\nx\n", "f.iso:1: bad lipschitz value '0.5': expected a Lipschitz bound L >= 1"),
        ("#@ bound: sphere:0,0,0\nx\n", "f.iso:1: bad bound value 'sphere:0,0,0': expected sphere:cx,cy,cz,r with a radius r > 0"),
        ("#@ bound: box:0,1,0,1,1,0\nx\n", "f.iso:1: bad bound value 'box:0,1,0,1,1,0': expected box:x0,x1,y0,y1,z0,z1 with lo < hi on every axis"),
        ("#@ bound: cone:1\nx\n", "f.iso:1: bad bound value 'cone:1': expected sphere:cx,cy,cz,r or box:x0,x1,y0,y1,z0,z1"),
        ("#@ name: a b\nx\n", "f.iso:1: bad name value 'a b': a name uses letters, digits, '-', '_' and '.' only"),
        ("#@ title:\nx\n", "f.iso:1: empty value for key 'title'"),
        ("#@ just words\nx\n", "f.iso:1: malformed header line: expected '#@ key: value'"),
        ("x\n#@ box: -1,1\n", "f.iso:2: header line after the start of the formula (header lines must come first)"),
    ];
    for (text, want) in cases {
        assert_eq!(err_text(parse_iso("f.iso", text)), want, "for {text:?}");
    }
}

#[test]
fn value_helpers() {
    assert_eq!(parse_eps("0.001"), Ok(0.001));
    assert_eq!(parse_eps("1e-3"), Ok(1e-3));
    assert_eq!(parse_eps("2^-11"), Ok(1.0 / 2048.0));
    assert_eq!(parse_eps(" 2 ^ -11 "), Ok(1.0 / 2048.0));
    assert_eq!(parse_eps("-1").unwrap_err(), "must be greater than 0");
    assert_eq!(parse_eps("NaN").unwrap_err(), "must be a finite number");
    assert_eq!(parse_eps("inf").unwrap_err(), "must be a finite number");
    assert!(parse_eps("2^-x").is_err() && parse_eps("").is_err() && parse_eps("0^1").is_err());

    assert_eq!(parse_box("-2,2"), Ok([-2.0, 2.0, -2.0, 2.0, -2.0, 2.0]));
    assert_eq!(parse_box(" -1, 1, -2, 2, 0, 3 "), Ok([-1.0, 1.0, -2.0, 2.0, 0.0, 3.0]));
    assert_eq!(parse_box("1,1").unwrap_err(), "empty x range: 1 is not below 1");
    assert_eq!(parse_box("1,2,3").unwrap_err(), "expected 2 or 6 numbers");
    assert_eq!(parse_box("-inf,1").unwrap_err(), "expected 2 or 6 numbers");

    assert_eq!(parse_vec3("1, -2.5, 3e1"), Ok([1.0, -2.5, 30.0]));
    assert_eq!(parse_vec3("1,2,nan").unwrap_err(), "expected 3 numbers 'x,y,z'");
}

#[test]
fn lookup_normalises_names_and_load_file_reports_io_errors() {
    assert_eq!(catalog::lookup("Klein Bottle").unwrap().name, "klein-bottle");
    assert_eq!(catalog::lookup("icos.csg.iso").unwrap().name, "icos.csg");
    let missing = catalog::load_file("no/such/file.iso").unwrap_err();
    assert!(matches!(&missing, CatalogError::Read { file, .. } if file == "no/such/file.iso"), "{missing:?}");
    assert!(missing.to_string().starts_with("no/such/file.iso: cannot read: "), "{missing}");
}

#[test]
fn sphere_tracing_keys_parse() {
    let text = "#@ method: sphere\n#@ lipschitz: 1.5\n#@ bound: sphere:0,0,-0.1,1.2\nsphere(1)\n";
    let h = parse_iso("s.iso", text).unwrap().header;
    assert_eq!(h.method, Some(catalog::Method::Sphere));
    assert_eq!(h.lipschitz, Some(1.5));
    assert_eq!(h.bound, Some(catalog::Bound::Sphere { center: [0.0, 0.0, -0.1], radius: 1.2 }));
    let h = parse_iso("b.iso", "#@ method: bisect\n#@ bound: box:-1,1,-2,2,-3,3\nx\n").unwrap().header;
    assert_eq!(h.method, Some(catalog::Method::Bisect));
    assert_eq!(h.bound, Some(catalog::Bound::Box([-1.0, 1.0, -2.0, 2.0, -3.0, 3.0])));
}

/// The distance-field scenes ask for sphere tracing, and a declared bound
/// holds every point of the object the grid finds (f <= 0), so the
/// convex-object trick never cuts the object.
#[test]
fn sdf_scenes_use_sphere_tracing_and_their_bounds_hold_the_object() {
    for name in catalog::suite("sdf").unwrap() {
        let e = catalog::lookup(name).unwrap();
        assert_eq!(e.header.method, Some(catalog::Method::Sphere), "{name}");
        let Some(catalog::Bound::Sphere { center: c, radius }) = e.header.bound else { continue };
        let ir = e.compile().unwrap().ir;
        let b = e.header.bbox;
        const N: usize = 41;
        let at = |lo: f64, hi: f64, n: usize| lo + (hi - lo) * n as f64 / (N - 1) as f64;
        for i in 0..N {
            for j in 0..N {
                for k in 0..N {
                    let p = [at(b[0], b[1], i), at(b[2], b[3], j), at(b[4], b[5], k), 0.0];
                    if crate::reference::eval_scalar(&ir, p, &[]) <= 0.0 {
                        let r = ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2) + (p[2] - c[2]).powi(2)).sqrt();
                        assert!(r <= radius, "{name}: inside point {p:?} is outside the bound ({r} > {radius})");
                    }
                }
            }
        }
    }
    assert!(catalog::lookup("jewel").unwrap().header.bound.is_some());
}

/// The module documentation's example: an entry by name, its header and formula.
#[test]
fn an_entry_is_found_by_name_and_compiles() {
    let e = crate::catalog::lookup("tangle").unwrap();
    assert_eq!(e.header.bbox, [-3.0, 3.0, -3.0, 3.0, -3.0, 3.0]);
    assert_eq!(e.compile().unwrap().ir.degree(), Some(4));
}

/// The suites: Knoll's table, the distance-field scenes, every entry.
#[test]
fn suites_name_their_entries() {
    use crate::catalog;
    let knoll = catalog::suite("knoll").unwrap();
    assert_eq!((knoll.len(), knoll[0], knoll[15]), (16, "sphere", "water"));
    assert_eq!(catalog::suite("sdf").unwrap(), ["jewel", "city", "creature"]);
    assert_eq!(catalog::suite("all").unwrap().len(), catalog::builtin().len());
    let e = catalog::suite("knol").unwrap_err();
    assert_eq!(e.to_string(), "unknown suite 'knol': expected knoll, sdf or all");
}
