//! Criterion bench of editing a scene (issue 13's editing figure): one
//! primitive's parameters changed on the 11,110-primitive aggregate of
//! Zanni et al.'s Fig. 16 (level 3, sharp unions: the smooth variant's
//! frames are dominated by overflow tiles, see the README). "in place" is what an editor
//! does per change: `Linear::set_primitive` (rows, ABV, ball) and
//! `Renderer::edit_field` (two buffer writes); "rebuild" linearises the
//! edited scene and uploads new buffers (`Linear::new`, `field_data`,
//! `set_field`). Neither creates a shader or a pipeline; the next frame is
//! measured apart ("frame after edit", 256², warm).
//!
//! cargo bench --bench scene_edit

use criterion::{criterion_group, criterion_main, Criterion};
use isotrace::gpu::{Gpu, Renderer};
use isotrace::render::{Settings, SphereOptions, Traversal};
use isotrace::scene::generate::{generate, Blending, Kind};
use isotrace::scene::linear::Linear;
use isotrace::scene::{Node, Scene};
use std::hint::black_box;

fn edit(c: &mut Criterion) {
    let scene = generate(Kind::Aggregate, 3, Blending::Sharp, 1).expect("generates");
    let mut lin = Linear::new(&scene).expect("linearises");
    let gpu = Gpu::new().expect("a device");
    let o = SphereOptions::default();
    let data = lin.field_data();
    let mut r = Renderer::new(&gpu, &data, Traversal::Sphere(o)).expect("renderer");
    let s = Settings::for_box([-1.3, 1.3, -1.3, 1.3, -1.3, 1.3], 256, 256);
    let j = lin.primitives.len() / 2;
    let Node::Primitive(p) = &scene.nodes()[lin.order[lin.primitives[j] as usize]] else { unreachable!("a primitive") };
    let mut g = c.benchmark_group("scene edit, 11110 primitives");
    g.sample_size(20);
    let mut step = 0u32;
    g.bench_function("in place (set_primitive + edit_field)", |b| {
        b.iter(|| {
            step += 1;
            let mut q = p.clone();
            q.transform.translate[0] += 1e-3 * (step % 7) as f64;
            let patch = lin.set_primitive(j, black_box(&q)).expect("same type");
            r.edit_field(&patch).expect("fits");
            gpu.device.poll(wgpu::PollType::Wait { submission_index: None, timeout: None }).expect("poll");
        })
    });
    g.bench_function("rebuild (Linear::new + field_data + set_field)", |b| {
        b.iter(|| {
            let mut nodes = scene.nodes().to_vec();
            let mut q = p.clone();
            q.transform.translate[0] += 1e-3;
            nodes[lin.order[lin.primitives[j] as usize]] = Node::Primitive(q);
            let edited = Scene::new(nodes, scene.root()).expect("valid");
            let l = Linear::new(&edited).expect("linearises");
            r.set_field(&l.field_data()).expect("same kernel");
        })
    });
    g.sample_size(10);
    g.bench_function("frame after edit (256², warm)", |b| b.iter(|| r.render(black_box(&s)).expect("renders")));
    g.finish();
}

criterion_group!(benches, edit);
criterion_main!(benches);
