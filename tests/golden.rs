//! Golden images: small renders of Knoll surfaces compared with committed
//! references (tests/golden/README.md says how they were made).
//!
//! Tolerance: a pixel differs when a channel differs by more than 24/255;
//! at most 1 % of the pixels may differ (silhouette pixels move with
//! floating-point details), and the mean absolute difference must stay
//! below 2/255.

use std::process::Command;

const NAMES: [&str; 6] = ["sphere", "tangle", "mitchell", "barth-sextic", "sq.csg", "cloth"];

#[test]
fn renders_match_the_golden_images() {
    let dir = std::env::temp_dir().join(format!("isotrace-golden-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bless = std::env::var("ISOTRACE_BLESS").is_ok();
    for name in NAMES {
        let reference = format!("tests/golden/{name}.png");
        let out = if bless { std::path::PathBuf::from(&reference) } else { dir.join(format!("{name}.png")) };
        let o = Command::new(env!("CARGO_BIN_EXE_isotrace"))
            .args(["render", &format!("@{name}"), "--size", "128", "-o", out.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(o.status.success(), "{name}: {}", String::from_utf8_lossy(&o.stderr));
        if bless {
            continue;
        }
        let a = image::open(&reference).unwrap().to_rgb8();
        let b = image::open(&out).unwrap().to_rgb8();
        assert_eq!(a.dimensions(), b.dimensions());
        let (mut differing, mut sum) = (0usize, 0u64);
        for (p, q) in a.pixels().zip(b.pixels()) {
            let d = (0..3).map(|c| p.0[c].abs_diff(q.0[c])).max().unwrap_or(0);
            sum += (0..3).map(|c| u64::from(p.0[c].abs_diff(q.0[c]))).sum::<u64>();
            differing += usize::from(d > 24);
        }
        let n = (a.width() * a.height()) as usize;
        let mean = sum as f64 / (3 * n) as f64;
        assert!(differing * 100 <= n, "{name}: {differing} of {n} pixels differ from the golden image (see {})", out.display());
        assert!(mean < 2.0, "{name}: mean difference {mean:.2}/255");
    }
}
