//! The benchmark bookkeeping: shard selection, the report formats, the
//! image comparison and the contact sheet.

use crate::batch::Shard;
use crate::bench::*;
use crate::render::{Frame, PixelOut, Stats, Status};

fn names(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

#[test]
fn shards_partition_the_jobs() {
    let all = jobs(&names(&["a", "b", "c"]), &names(&["ia", "raa"]));
    assert_eq!(all.len(), 6);
    assert_eq!(all[1], Job { index: 1, surface: "a".into(), algebra: "raa".into() });
    let mut seen: Vec<usize> = Vec::new();
    for i in 0..4 {
        let part = shard(&all, Shard::new(i, 4).unwrap());
        assert!(part.iter().all(|j| j.index % 4 == i));
        seen.extend(part.iter().map(|j| j.index));
    }
    seen.sort();
    assert_eq!(seen, (0..6).collect::<Vec<_>>());
    assert_eq!(shard(&all, Shard::ALL), all);
}

#[test]
fn shard_syntax() {
    assert_eq!(Shard::parse("2/5"), Ok(Shard { index: 2, count: 5 }));
    assert_eq!(Shard::parse(" 0 / 1 "), Ok(Shard::ALL));
    for bad in ["5/5", "1/0", "a/2", "3", "-1/2"] {
        assert_eq!(Shard::parse(bad).unwrap_err().to_string(), format!("'{bad}': expected i/n with 0 <= i < n, e.g. 0/4"));
    }
}

fn measure(ms: f64, evals: f64) -> Measure {
    let stats = Stats { gpu_ms: ms, wall_ms: ms + 1.0, pixels: 100, hits: 25, evals_mean: evals, evals_p99: 9, evals_max: 12, bisect: crate::render::BisectStats { d_max: 11, evals_lower_bound: 4.0 }, ..Default::default() };
    Measure::from_runs(&[stats.clone(), Stats { gpu_ms: ms * 3.0, ..stats.clone() }, Stats { gpu_ms: ms * 0.5, ..stats }], 0.01, "ia")
}

fn results() -> Vec<JobResult> {
    vec![
        JobResult { index: 0, surface: "sphere".into(), degree: "2".into(), algebra: "ia".into(), outcome: Outcome::Ok(measure(10.0, 6.0)) },
        JobResult { index: 1, surface: "sphere".into(), degree: "2".into(), algebra: "raa".into(), outcome: Outcome::Failed { error: "GPU error during render dispatch: lost".into() } },
    ]
}

#[test]
fn measure_takes_the_median_and_the_bound_ratio() {
    let m = measure(10.0, 6.0);
    assert_eq!(m.gpu_ms, 10.0);
    assert_eq!(m.fps, 100.0);
    assert_eq!(m.ratio, 1.5);
    assert_eq!(m.hit_fraction, 0.25);
}

#[test]
fn text_table_has_one_row_per_surface_and_lists_failures() {
    let t = table_text(&results(), &names(&["ia", "raa"]));
    let expected = "surface          degree           ia (ms / evals/px)      raa (ms / evals/px)\n\
                    sphere           2                 10.0 ms / 6.00 ev                   FAILED\n\
                    FAILED sphere raa: GPU error during render dispatch: lost\n";
    assert_eq!(t, expected);
}

#[test]
fn markdown_and_json_carry_every_job() {
    let md = markdown(&results(), &names(&["ia", "raa"]), "test machine");
    assert!(md.starts_with("Machine: test machine\n"));
    assert!(md.contains("| sphere | 2 | 10.0 | 100.0 | 6.00 | FAILED | | |"));
    assert!(md.contains("| sphere | ia | ia | 10.0 | 11.0 | 6.00 | 9 | 12 | 4.00 | 1.50 | 25.0 % | 0 | 11 | - |"));
    let v = serde_json::to_value(results()).unwrap();
    assert_eq!(v[0]["surface"], "sphere");
    assert_eq!(v[0]["gpu_ms"], 10.0);
    assert_eq!(v[0]["ratio"], 1.5);
    assert_eq!(v[1]["error"], "GPU error during render dispatch: lost");
}

/// Names and errors of a report that `bench --merge` read from a file:
/// control characters visible, one line, and in Markdown `|` escaped so a
/// cell stays one cell. A row whose algebra is no column is left out of
/// the grid.
#[test]
fn text_from_a_report_is_escaped_in_the_table_and_the_markdown() {
    let mut rows = results();
    rows[0].surface = "a|b\x1b[2J".into();
    rows[1].surface = "a|b\x1b[2J".into();
    rows[1].outcome = Outcome::Failed { error: "bad\x07 news".into() };
    rows.push(JobResult { algebra: "other".into(), ..rows[0].clone() });
    let t = table_text(&rows, &names(&["ia", "raa"]));
    assert!(t.lines().nth(1).unwrap().starts_with("a|b\u{241b}[2J          2 ") && t.ends_with("FAILED a|b\u{241b}[2J raa: bad\u{2407} news\n"), "{t}");
    let md = markdown(&rows, &names(&["ia", "raa"]), "gpu\x1b]0;x\x07\nMachine: forged");
    assert!(md.starts_with("Machine: gpu\u{241b}]0;x\u{2407}\u{240a}Machine: forged\n\n"), "{md}");
    assert!(md.contains("\n| a\\|b\u{241b}[2J | 2 | 10.0 |") && md.contains("| a\\|b\u{241b}[2J | raa | FAILED: bad\u{2407} news |"), "{md}");
    assert!(!t.contains('\x1b') && !md.contains('\x1b'), "{md}");
    // The grid has no column for it (and does not panic); the details list it.
    assert_eq!(t.lines().count(), 3);
    assert!(md.contains("| a\\|b\u{241b}[2J | other | ia |"), "{md}");
}

fn frame(colors: &[[f32; 4]]) -> Frame {
    let pixels = colors
        .iter()
        .map(|c| PixelOut { color: *c, normal: [0.0; 3], depth: 1.0, evals: 1, level: 0, iso: 0, status: if c[3] > 0.0 { Status::Hit } else { Status::Miss } })
        .collect();
    Frame { width: colors.len() as u32, height: 1, pixels, stats: Stats::default() }
}

#[test]
fn image_comparison_counts_colour_and_coverage_changes() {
    let a = frame(&[[0.5, 0.5, 0.5, 1.0], [0.2, 0.2, 0.2, 1.0], [0.1, 0.1, 0.1, 0.0], [0.9, 0.9, 0.9, 1.0]]);
    let mut b = a.clone();
    assert_eq!(differing_fraction(&a, &b), 0.0);
    b.pixels[0].color[0] = 0.505; // within tolerance
    assert_eq!(differing_fraction(&a, &b), 0.0);
    b.pixels[1].color[1] = 0.6; // visibly different
    b.pixels[2].status = Status::Hit; // coverage changed
    assert_eq!(differing_fraction(&a, &b), 0.5);
}

#[test]
fn contact_sheet_lays_out_a_labelled_grid() {
    let img = |v: u8| (2u32, 2u32, vec![v; 12]);
    let images: Vec<(String, u32, u32, Vec<u8>)> = (0..5).map(|k| { let (w, h, d) = img(100 + k as u8); (format!("s{k}"), w, h, d) }).collect();
    let (w, h, rgb) = contact_sheet(&images, 32, 4);
    assert_eq!((w, h), (128, 2 * (32 + 20)));
    assert_eq!(rgb.len(), (w * h * 3) as usize);
    // Cell 4 (second row, first column) is filled with its image's value.
    let at = |x: u32, y: u32| rgb[((y * w + x) * 3) as usize];
    assert_eq!(at(5, 52 + 5), 104);
    assert_eq!(at(32 + 5, 5), 101);
    // Labels are drawn in light grey below the cells.
    assert!((0..128).any(|x| (32..52).any(|y| at(x, y) == 235)));
}

#[test]
fn utc_now_is_iso_8601() {
    let d = utc_now();
    assert_eq!(d.len(), 20);
    assert!(d.ends_with('Z') && d.as_bytes()[10] == b'T');
    assert!(d.as_str() > "2024");
}
