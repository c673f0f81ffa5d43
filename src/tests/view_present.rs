//! The viewer's present shader (`templates/view/present.wgsl`) decodes a
//! pixel record as the CLI does: its 8-bit sRGB colour equals
//! `output::srgb8` of `record::convert` (colour, normals, work heat map),
//! on the device, for records of every status.

use crate::gpu::Gpu;
use crate::layout::{PRESENT_COLOR, PRESENT_NORMAL, PRESENT_STEPS};
use crate::render::record::{convert, Head, Record, Tail};
use crate::view::present::RECORDS;

/// Records with every status, random colours, normals, work.
fn records(n: usize) -> Vec<[u32; 4]> {
    let mut x = 0x2545_f491_u64;
    let mut next = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x as u32
    };
    (0..n).map(|_| [next(), next(), 0, next() & 0x1fff_ffff]).collect()
}

#[test]
fn present_decodes_records_like_the_cli() {
    let gpu = match Gpu::new() {
        Ok(g) => g,
        Err(e) => panic!("no device: {e}"),
    };
    let present = crate::view::present_shader().expect("the present shader validates");
    // The test's own buffers after the present pass's bindings, in its group.
    let table = crate::view::present::group();
    let last = table.bindings.iter().map(|b| b.binding).max().expect("bindings");
    let (g, input_at, decoded_at, mode_at) = (table.group, RECORDS.binding, last + 1, last + 2);
    let wgsl = format!(
        "{present}\n@group({g}) @binding({decoded_at}) var<storage, read_write> decoded: array<u32>;\n\
         @group({g}) @binding({mode_at}) var<storage, read> mode: array<u32>;\n\
         @compute @workgroup_size(64) fn decode_test(@builtin(global_invocation_id) id: vec3<u32>) {{\n\
             if (id.x >= arrayLength(&decoded)) {{ return; }}\n\
             let c = vec3<u32>(srgb8(present_linear(record_at(id.x, arrayLength(&decoded)), mode[0], mode[1])));\n\
             decoded[id.x] = c.x | (c.y << 8u) | (c.z << 16u);\n\
         }}\n"
    );
    crate::validate::validate(&wgsl).expect("validates");
    let pipeline = &gpu.pipelines("present test", &wgsl, crate::gpu::Author::Isotrace, &["decode_test"]).expect("pipeline")[0];
    let recs = records(4096);
    let steps_max = 300u32;
    for mode in [PRESENT_COLOR, PRESENT_NORMAL, PRESENT_STEPS] {
        // The kernel's two planes: heads (colour, work), then tails (normal, depth).
        let planes: Vec<u32> = recs.iter().flat_map(|r| [r[0], r[3]]).chain(recs.iter().flat_map(|r| [r[1], r[2]])).collect();
        let input = gpu.storage("records", bytemuck::cast_slice(&planes)).unwrap();
        let modes = gpu.storage("mode", bytemuck::cast_slice(&[mode, steps_max, 0, 0])).unwrap();
        let out = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: recs.len() as u64 * 4,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let layout = pipeline.get_bind_group_layout(g);
        let entries = [(input_at, &input), (decoded_at, &out), (mode_at, &modes)].map(|(b, buf)| wgpu::BindGroupEntry { binding: b, resource: buf.as_entire_binding() });
        let group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout: &layout, entries: &entries });
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(g, &group, &[]);
            pass.dispatch_workgroups(recs.len().div_ceil(64) as u32, 1, 1);
        }
        let staging = gpu.read_buffer(&mut enc, &out, recs.len() as u64 * 4);
        gpu.queue.submit([enc.finish()]);
        let bytes = gpu.map_read(&staging).unwrap();
        let got: &[u32] = bytemuck::cast_slice(&bytes);
        let mut off = 0;
        for (r, g) in recs.iter().zip(got) {
            let rec = Record::new(Head::from_words([r[0], r[3]]), &Tail::from_words([r[1], r[2]]));
            let mut frame = crate::render::Frame { width: 1, height: 1, pixels: vec![convert(&rec)], stats: Default::default() };
            let cli_mode = match mode {
                PRESENT_NORMAL => crate::output::ColorMode::Normal,
                PRESENT_STEPS => crate::output::ColorMode::Steps { max: Some(steps_max) },
                _ => crate::output::ColorMode::Shade,
            };
            crate::output::recolor(&mut frame, cli_mode);
            let want = crate::output::frame_rgb8(&frame);
            let have = [(g & 255) as u8, (g >> 8 & 255) as u8, (g >> 16 & 255) as u8];
            let d = want.iter().zip(have).map(|(a, b)| (*a as i32 - b as i32).abs()).max().unwrap();
            // The stored colour is exact; normals and the heat map go through
            // pow() on the device, which may round one level differently.
            let allowed = if mode == PRESENT_COLOR { 0 } else { 1 };
            assert!(d <= allowed, "mode {mode}: record {r:08x?}: CLI {want:?}, present {have:?}");
            off += usize::from(d > 0);
        }
        eprintln!("mode {mode}: {off} of {} records one level off", recs.len());
    }
}
