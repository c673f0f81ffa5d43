//! Knoll et al.'s modalities change the picture as expected: shadows darken,
//! layers show hidden surfaces, isovalues are identified, reflections see
//! the environment, colour modes recolour, and each composes with the others.

fn isotrace(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_isotrace")).args(args).env("NODEVICE_SELECT", "1").output().unwrap()
}

#[test]
fn modality_flags_from_the_command_line() {
    let dir = std::env::temp_dir().join(format!("isotrace-modal-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let exr = dir.join("iso.exr");
    let o = isotrace(&["render", "x^2 + y^2 + z^2", "--box=-1.2,1.2", "--iso", "0.25,1", "--opacity", "0.5", "--shadows", "--reflect", "1", "--size", "24", "-o", exr.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (_, _, channels) = isotrace::output::read_exr_channels(&exr).unwrap();
    let iso = &channels.iter().find(|(n, _)| n == "iso").expect("an iso channel").1;
    // The outer sphere (isovalue 1, index 1) is the first hit; misses are -1.
    assert!(iso.contains(&1.0) && iso.contains(&-1.0));
    let png = dir.join("g.png");
    for color in ["gradient", "depth", "normal", "evals"] {
        let o = isotrace(&["render", "@steiner", "--color", color, "--size", "16", "-o", png.to_str().unwrap()]);
        assert!(o.status.success(), "--color {color}: {}", String::from_utf8_lossy(&o.stderr));
    }
}

#[test]
fn bad_modality_values_are_clear_errors() {
    let cases: &[(&[&str], &str)] = &[
        (&["--opacity", "1.5"], "error: invalid --opacity 1.5: it must be in (0, 1]\n"),
        (&["--layers", "9"], "error: invalid --layers 9: it must be between 1 and 8\n"),
        (&["--iso", "1,a"], "error: invalid --iso '1,a': expected 1 to 8 comma-separated numbers\n"),
        (&["--iso", "1,2,3,4,5,6,7,8,9"], "error: invalid --iso '1,2,3,4,5,6,7,8,9': expected 1 to 8 comma-separated numbers\n"),
        (&["--reflect", "9"], "error: invalid --reflect 9: at most 8 bounces\n"),
        (&["--reflectivity", "2"], "error: invalid --reflectivity 2: it must be in [0, 1]\n"),
        (&["--shadow-eps", "0.01"], "error: --shadow-eps needs --shadows\n"),
        (&["--light", "1,2"], "error: invalid --light '1,2': expected 3 numbers 'x,y,z'\n"),
        (&["--env", "/nonexistent.png"], "error: cannot read --env image '/nonexistent.png': No such file or directory (os error 2)\n"),
        (&["--method", "sphere", "--iso", "0,1"], "error: --iso applies to --method bisect only\n"),
        (&["--color", "rainbow"], "error: invalid --color 'rainbow': expected shade, steps (or evals), steps:MAX (MAX > 0), normal, gradient, depth, field or overlap\n"),
    ];
    for (extra, expected) in cases {
        let mut args = vec!["render", "x^2 + y^2 + z^2 - 1", "-o", "/tmp/never.png"];
        args.extend_from_slice(extra);
        let o = isotrace(&args);
        assert_eq!(o.status.code(), Some(1), "{extra:?}");
        assert_eq!(String::from_utf8_lossy(&o.stderr), *expected, "{extra:?}");
    }
}
