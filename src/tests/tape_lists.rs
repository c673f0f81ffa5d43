//! Bisection's per-tile shortening of a tape with min and max: each tile
//! runs only the instructions that can reach f over its candidate slabs,
//! and draws the surface the whole tape draws.

use super::common;
use super::tape::{bisect_tape, differences, entry_settings, misses_of_the_reference};

use common::gpu;
use crate::field::tape::features;
use crate::field::TapeData;
use crate::gpu::Renderer;
use crate::ir::Domain;
use crate::render::{BisectOptions, Traversal};
use crate::Formula;

#[test]
fn shortened_tiles_draw_the_whole_tapes_surface() {
    // Sphere and box distances under min and max (with abs and strict
    // square roots), Knoll's icos.csg (a max of eleven terms), and the city
    // of 36 blocks, whose every tile keeps a small part of the tape.
    let balls: Vec<String> = (0..5).map(|i| format!("sqrt((x-{})^2+(y-{})^2+z^2)-0.35", i as f64 - 2.0, (i % 2) as f64 - 0.5)).collect();
    let union = format!("min({}, max(abs(x)-2.5, max(abs(y)-0.2, abs(z+0.8)-0.15)))", balls.iter().skip(1).fold(balls[0].clone(), |a, b| format!("min({a}, {b})")));
    let entry = |name: &str, n: u32| {
        let e = crate::catalog::lookup(name).unwrap();
        let f = e.compile().unwrap();
        let s = entry_settings(&e, &f, n);
        (f, s)
    };
    let cases = [
        (Formula::compile("<union>", &union).unwrap(), common::settings(common::cube(3.0), 64, 64), 1.0, vec![Domain::Interval, Domain::Affine]),
        (entry("icos.csg", 48).0, entry("icos.csg", 48).1, 1.0, vec![Domain::Interval, Domain::Affine]),
        // (The f64 reference of 914 operations a sample is too slow here:
        // the city is compared with its whole tape only.)
        // (Its ground goes on past the box: the tiles beside the box, which
        // kept little more than the ground, are no longer queued since the
        // tile pass encloses only inside the box; the 33 left keep 0.51.)
        (entry("city", 64).0, entry("city", 64).1, 0.6, vec![Domain::Interval]),
    ];
    for (k, (f, s, share, domains)) in cases.iter().enumerate() {
        let data = TapeData::new(&f.ir).unwrap();
        for &domain in domains {
            let whole = bisect_tape(&data, domain, s, false);
            let short = bisect_tape(&data, domain, s, true);
            let (w, t) = (whole.stats.field.tape_lists.unwrap(), short.stats.field.tape_lists.unwrap());
            assert_eq!(w.shortened, 0, "{domain:?}: the optimisation was off");
            assert!(t.tiles > 0 && t.shortened == t.tiles && t.kept_share() < *share, "{domain:?}: {t:?}");
            // The same function inside every tile's candidate slabs: the
            // same surface to within the root finder's tolerance (the
            // enclosures may differ: a dead operand no longer widens them).
            let bad = differences(&whole, &short, 2.0 * s.eps);
            assert!(bad.len() <= 1, "{domain:?}: {} pixels differ: {:?}", bad.len(), &bad[..bad.len().min(6)]);
            let missed = if k < 2 { misses_of_the_reference(f, s, &short, 2000, true) } else { vec![] };
            assert!(missed.is_empty(), "{domain:?} {s:?}: {} pixels: {:?}", missed.len(), &missed[..missed.len().min(8)]);
        }
    }
}

#[test]
fn a_long_csg_tape_is_shortened_per_block_then_per_tile() {
    // 225 boxes of varying heights on a grid, joined by min: about 680 min
    // and max (past the 512 choice slots tiles had), and a derivative
    // program several thousand instructions long, whose tile pass went
    // past the work limit before the block pass.
    let mut boxes = Vec::new();
    for i in 0..15 {
        for j in 0..15 {
            let (cx, cy, h) = (-2.1 + 0.3 * f64::from(i), -2.1 + 0.3 * f64::from(j), 0.1 + 0.05 * f64::from((i * 7 + j * 3) % 11));
            boxes.push(format!("max(abs(x - ({cx:.2})) - 0.1, max(abs(y - ({cy:.2})) - 0.1, abs(z - {h:.2}) - {h:.2}))"));
        }
    }
    // A balanced tree of mins (a chain 225 deep is past the parser's nesting limit).
    fn union(b: &[String]) -> String {
        if b.len() == 1 { b[0].clone() } else { format!("min({}, {})", union(&b[..b.len() / 2]), union(&b[b.len() / 2..])) }
    }
    let f = Formula::compile("<boxes>", &union(&boxes)).unwrap();
    let data = TapeData::new(&f.ir).unwrap();
    assert!(data.words[2][2] > 512, "{} choice slots", data.words[2][2]);
    let mut s = common::settings([-2.5, 2.5, -2.5, 2.5, -0.1, 1.2], 64, 64);
    s.camera.eye = glam::DVec3::new(3.0, -4.0, 3.5);
    s.camera.target = glam::DVec3::new(0.0, 0.0, 0.3);
    let whole = bisect_tape(&data, Domain::Interval, &s, false);
    let short = bisect_tape(&data, Domain::Interval, &s, true);
    let t = short.stats.field.tape_lists.unwrap();
    // The blocks shorten the tape, and every tile with candidate slabs
    // starts from its block's list and keeps about half of the tape (at
    // 64², a tile's frustum crosses a fifth of the boxes; with 512 slots
    // the tiles kept 85 % of a tape this long).
    assert!(t.blocks > 0 && t.blocks_shortened * 2 > t.blocks && t.block_kept_share(data.words[1][3].into()) < 0.95, "{t:?}");
    assert!(t.tiles > 0 && t.shortened == t.tiles && t.kept_share() < 0.6, "{t:?}");
    assert!(short.stats.hits > 500, "{} hits", short.stats.hits);
    assert!(short.stats.unresolved <= 2, "{} unresolved", short.stats.unresolved);
    let bad = differences(&whole, &short, 2.0 * s.eps);
    assert!(bad.len() <= 1, "{} pixels differ: {:?}", bad.len(), &bad[..bad.len().min(6)]);
    let compiled = Renderer::new(gpu(), &f.ir, Traversal::Bisect(BisectOptions::new(Domain::Interval))).unwrap().render(&s).unwrap();
    let bad = differences(&compiled, &short, 2.0 * s.eps);
    assert!(bad.len() <= 2, "{} pixels differ from the compiled field: {:?}", bad.len(), &bad[..bad.len().min(6)]);
}

#[test]
fn a_tape_too_long_for_a_backward_pass_an_entry_is_still_shortened() {
    // 1,000 boxes under a balanced tree of mins: a value program of about
    // 12,000 instructions (8 an iteration) whose backward passes over both
    // programs, one entry an iteration, would alone go past the tile pass's
    // work limit, so that no block and no tile was shortened and every ray
    // ran the whole tape.
    let boxes: Vec<String> = (0..1000u32)
        .map(|i| {
            let (cx, cy, cz) = (f64::from(i * 37 % 41) / 10.0 - 2.0, f64::from(i * 53 % 43) / 10.0 - 2.1, f64::from(i * 7 % 5) / 10.0 - 0.2);
            format!("max(abs(x-({cx:.1}))-.1,abs(y-({cy:.1}))-.1,abs(z-({cz:.1}))-.1)")
        })
        .collect();
    fn union(b: &[String]) -> String {
        if b.len() == 1 { b[0].clone() } else { format!("min({}, {})", union(&b[..b.len() / 2]), union(&b[b.len() / 2..])) }
    }
    let f = Formula::compile("<boxes>", &union(&boxes)).unwrap();
    let data = TapeData::new(&f.ir).unwrap();
    let [_, value, _, deriv] = data.words[0];
    assert!(features::unroll(data.features) >= 8, "{value} value instructions");
    assert!(2 * (value + deriv) > crate::field::limits::TAPE_TILE_PASS_BUNDLE_LIMIT, "{value} + {deriv} instructions");
    let s = common::settings(common::cube(2.5), 64, 64);
    let short = bisect_tape(&data, Domain::Interval, &s, true);
    let t = short.stats.field.tape_lists.unwrap();
    // At 64² a tile's candidate slabs pass within reach of most boxes of
    // the plate: each keeps about nine tenths of the tape (the 60 KB
    // `random` family keeps a third at 512²).
    assert!(t.blocks_shortened > 0 && t.block_kept_share(data.words[1][3].into()) < 0.97, "{t:?}");
    assert!(t.tiles > 0 && t.shortened == t.tiles && t.kept_share() < 0.95, "{t:?}");
    assert!(short.stats.hits > 300 && short.stats.unresolved == 0, "{:?}", short.stats);
    let whole = bisect_tape(&data, Domain::Interval, &s, false);
    let bad = differences(&whole, &short, 2.0 * s.eps);
    assert!(bad.len() <= 1, "{} pixels differ: {:?}", bad.len(), &bad[..bad.len().min(6)]);
}
