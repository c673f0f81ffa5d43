//! Criterion bench of the compile path per Knoll surface: formula text →
//! parse → semantic pass → WGSL render shader (IA and RAA) → naga
//! validation. The budget is 5 ms per surface.
//!
//! cargo bench --bench compile

use criterion::{criterion_group, criterion_main, Criterion};
use isotrace::kernel::render_shader;
use isotrace::ir::Domain;
use isotrace::{catalog, validate::validate, Formula};
use std::hint::black_box;

fn compile(c: &mut Criterion) {
    let mut g = c.benchmark_group("compile");
    g.sample_size(20);
    for name in catalog::suite("knoll").expect("the knoll suite") {
        let text = catalog::lookup(name).expect("catalog").formula;
        g.bench_function(name, |b| {
            b.iter(|| {
                let f = Formula::compile("<bench>", black_box(&text)).expect("compiles");
                let domain = isotrace::choose_algebra(&f.ir);
                let wgsl = render_shader(&f.ir, domain);
                validate(&wgsl).expect("validates");
            })
        });
    }
    g.finish();
    let text = catalog::lookup("barth-decic").expect("catalog").formula;
    let f = Formula::compile("<bench>", &text).expect("compiles");
    c.bench_function("emit+validate barth-decic ia", |b| b.iter(|| validate(&render_shader(&f.ir, Domain::Interval)).expect("ok")));
}

criterion_group!(benches, compile);
criterion_main!(benches);
