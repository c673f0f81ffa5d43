//! Measures each traversal optimisation on the Knoll suite (each surface
//! seen as its `.iso` header describes it): GPU time and
//! inclusion evaluations per pixel with every switch on, and with each one
//! off, alternating the variants run by run so machine load hits all alike.
//!
//! cargo bench --bench optimizations [-- SIZE [REPEAT [NAME...]]]

use isotrace::catalog;
use isotrace::gpu::Renderer;
use isotrace::render::Optimizations;
use isotrace::gpu::Gpu;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    let size: u32 = args.first().and_then(|s| s.parse().ok()).unwrap_or(512);
    let repeat: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(2);
    let names: Vec<String> = if args.len() > 2 {
        args[2..].to_vec()
    } else {
        catalog::suite("knoll").expect("the knoll suite").into_iter().map(String::from).collect()
    };
    let gpu = Gpu::new().expect("GPU");
    let md: u32 = std::env::var("MONO_DEPTH").ok().and_then(|v| v.parse().ok()).unwrap_or(Optimizations::default().monotone_depth);
    let variants: [(&str, Optimizations); 4] = [
        ("all", Optimizations { monotone_depth: md, ..Default::default() }),
        ("no-tile", Optimizations { tile_culling: false, ..Default::default() }),
        ("no-mono", Optimizations { monotone: false, ..Default::default() }),
        ("none", Optimizations { tile_culling: false, monotone: false, ..Default::default() }),
    ];
    println!("{size}x{size}, median of {repeat}; ms / evals per pixel");
    println!("{:<14} {:>18} {:>18} {:>18} {:>18}", "surface", variants[0].0, variants[1].0, variants[2].0, variants[3].0);
    for name in names {
        let e = catalog::lookup(&name).expect("catalog name");
        let f = e.compile().expect("compiles");
        let s = e.settings(&f, size, size).unwrap_or_else(|err| panic!("{name}: {err}"));
        let mut r = Renderer::bisect(&gpu, &f.ir, isotrace::choose_algebra(&f.ir)).expect("renderer");
        let mut times = vec![Vec::new(); variants.len()];
        let mut evals = vec![0.0; variants.len()];
        for run in 0..=repeat {
            for (k, (_, o)) in variants.iter().enumerate() {
                *r.optimizations_mut().expect("bisection") = *o;
                let fr = r.render(&s).expect("render");
                if run > 0 {
                    times[k].push(fr.stats.gpu_ms);
                }
                evals[k] = fr.stats.evals_mean;
            }
        }
        let cells: Vec<String> = times
            .iter_mut()
            .zip(&evals)
            .map(|(t, e)| {
                t.sort_by(f64::total_cmp);
                format!("{:.1} / {:.2}", t[t.len() / 2], e)
            })
            .collect();
        println!("{:<14} {:>18} {:>18} {:>18} {:>18}", name, cells[0], cells[1], cells[2], cells[3]);
    }
}
