//! Compile and frame time of the compiled and the tape field source for one
//! formula: `cargo bench --bench field_sources -- FIELD METHOD ALGEBRA SIZE
//! FORMULA` (FIELD compiled|tape|tape-whole, the last a tape bisected
//! without its per-tile shortening; METHOD bisect|sphere, ALGEBRA ia|raa,
//! FORMULA text or @name). Prints one line: tape ops, pipeline build ms,
//! first frame ms (where lavapipe compiles the shader), second frame ms,
//! unresolved pixels of the second, and the share of the value program a
//! shortened tile keeps. Run it with
//! `MESA_SHADER_CACHE_DISABLE=true` for cold figures, one process per
//! measurement (the README table: scripts/field-crossover.sh).

use isotrace::choice;
use isotrace::ir::Domain;
use isotrace::field::FieldKind;
use isotrace::gpu::{Gpu, Renderer};
use isotrace::render::{BisectOptions, Settings, SphereOptions, Traversal};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).filter(|a| a != "--bench").collect();
    let [field, method, algebra, size, formula] = &args[..] else {
        eprintln!("usage: field_sources FIELD METHOD ALGEBRA SIZE FORMULA");
        return;
    };
    let entry = formula.strip_prefix('@').map(|name| isotrace::catalog::lookup(name).expect("catalog name"));
    let text = entry.as_ref().map_or(formula.clone(), |e| e.formula.clone());
    let f = isotrace::Formula::compile("<bench>", &text).expect("formula");
    let domain = if algebra == "raa" { Domain::Affine } else { Domain::Interval };
    let traversal = match (method.as_str(), &entry) {
        ("sphere", Some(e)) => e.traversal(&f),
        ("sphere", None) => Traversal::Sphere(SphereOptions::default()),
        _ => Traversal::Bisect(BisectOptions::new(domain)),
    };
    let kind = if field.starts_with("tape") { FieldKind::Tape } else { FieldKind::Compiled };
    let gpu = Gpu::new().expect("device");
    let prepared = choice::choose(kind, &f, &[], &traversal).expect("field");
    let ops = match &prepared {
        isotrace::choice::PreparedField::Tape(t) => t.ops,
        _ => isotrace::field::TapeData::new(&f.ir).map_or(0, |t| t.ops),
    };
    let t0 = Instant::now();
    let mut r = Renderer::new(&gpu, prepared.source(&f.ir), traversal).expect("renderer");
    if let Some(o) = r.optimizations_mut() {
        o.tape_shortening = field != "tape-whole";
    }
    let build = t0.elapsed().as_secs_f64() * 1e3;
    let n: u32 = size.parse().expect("size");
    let s = match &entry {
        Some(e) => e.settings(&f, n, n).expect("settings"),
        None => Settings::for_box([-2.0, 2.0, -2.0, 2.0, -2.0, 2.0], n, n),
    };
    let t1 = Instant::now();
    r.render(&s).expect("first frame");
    let first = t1.elapsed().as_secs_f64() * 1e3;
    let t2 = Instant::now();
    let frame = r.render(&s).expect("second frame");
    let second = t2.elapsed().as_secs_f64() * 1e3;
    println!(
        "{field} {method} {algebra} {size} ops {ops} build_ms {build:.0} first_frame_ms {first:.0} cold_total_ms {:.0} frame_ms {second:.0} unresolved {} kept_share {:.3}",
        build + first,
        frame.stats.unresolved,
        frame.stats.field.tape_lists.map_or(1.0, |t| t.kept_share())
    );
}
