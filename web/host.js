// isotrace view: the WebGPU host. It runs a program the server describes
// (src/view/program.rs): layouts and pipelines per stage from the bindings
// each entry point uses, buffers by their size rules, the stages of one
// dispatch in src/gpu/dispatch.rs's order, then the present pass
// (templates/view/present.wgsl). It knows no traversal and no field source.

const view = window.__view;
const B = GPUBufferUsage;

/** The layout entry of a binding: a storage buffer, or a sampled texture of 32-bit texels. */
function layoutEntry(b) {
  if (b.texture) return { texture: { sampleType: b.texture.format.endsWith('uint') ? 'uint' : 'unfilterable-float' } };
  return { buffer: { type: b.read_only ? 'read-only-storage' : 'storage' } };
}

export class Host {
  constructor(device, canvas, presentWgsl) {
    this.device = device;
    this.canvas = canvas;
    this.context = canvas.getContext('webgpu');
    this.context.configure({ device, format: 'rgba8unorm', usage: GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.COPY_SRC, alphaMode: 'opaque' });
    const module = device.createShaderModule({ code: presentWgsl });
    this.present = device.createRenderPipeline({
      layout: 'auto', vertex: { module, entryPoint: 'vs' }, fragment: { module, entryPoint: 'fs', targets: [{ format: 'rgba8unorm' }] },
    });
    this.presentUniforms = null;
    this.lock = Promise.resolve();
  }

  /** A new kernel: module, layouts, pipelines, static buffers. */
  async setProgram(P) {
    const d = this.device;
    const module = d.createShaderModule({ code: P.wgsl });
    const info = await module.getCompilationInfo();
    const errors = info.messages.filter((m) => m.type === 'error');
    if (errors.length) throw new Error('the browser rejected the kernel: ' + errors.map((m) => m.message).join('\n'));
    // Per stage, layouts of only the bindings its entry point uses (the
    // server's `uses`, from naga): WebGPU counts a layout's every binding
    // against the per-stage storage buffer limit.
    const stages = [];
    for (const st of P.stages) {
      const used = (gi, b) => st.uses.some(([g, n]) => g === gi && n === b.binding);
      const layouts = P.groups.map((g, gi) => d.createBindGroupLayout({
        entries: g.filter((b) => used(gi, b)).map((b) => ({ binding: b.binding, visibility: GPUShaderStage.COMPUTE, ...layoutEntry(b) })),
      }));
      const layout = d.createPipelineLayout({ bindGroupLayouts: layouts });
      const pipeline = await d.createComputePipelineAsync({ layout, compute: { module, entryPoint: st.entry } });
      stages.push({ st, layouts, pipeline, used });
    }
    const uniforms = d.createBuffer({ size: P.uniforms.length * 4, usage: B.STORAGE | B.COPY_DST });
    Object.assign(this, { P, stages, uniforms, sized: null, selData: null, sizedSel: null });
    this.data = P.groups.map((g) => new Map(g.filter((b) => b.size.kind === 'data').map((b) => [b.binding, this.dataBuffer(b)])));
    view.programs++;
  }

  /** A data binding's buffer, or its texture's view when `b.texture` (a scene's nodes and parameters). */
  dataBuffer(b) {
    const words = new Uint32Array(b.data);
    if (b.texture) {
      const { width, height, format } = b.texture;
      const tex = this.device.createTexture({ size: [width, height], format, usage: GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST });
      this.device.queue.writeTexture({ texture: tex }, words, { bytesPerRow: width * 16 }, [width, height]);
      return { buf: tex.createView(), count: words.length / 4 };
    }
    const buf = this.device.createBuffer({ size: Math.max(16, words.byteLength), usage: B.STORAGE | B.COPY_DST });
    this.device.queue.writeBuffer(buf, 0, words);
    return { buf, count: words.length };
  }

  /** An edited scene: the field group's data buffers only (no shader, no pipeline). */
  setFieldData(bindings) {
    for (const b of bindings) this.data[1].set(b.binding, this.dataBuffer(b));
    this.sized = null;
  }

  /** The selected scene node's own field buffers (traced alone, same pipelines), or null. */
  setSelection(bindings) {
    this.selData = bindings ? new Map(bindings.map((b) => [b.binding, this.dataBuffer(b)])) : null;
    this.sizedSel = null;
  }

  /** Scratch buffers and bind groups for a w × h frame (kept while the size stays). */
  resources(w, h, sel = false) {
    const cached = sel ? this.sizedSel : this.sized;
    if (cached && cached.w === w && cached.h === h) return cached;
    const data = [this.data[0], sel ? this.selData : this.data[1], this.data[2]];
    const d = this.device;
    const tiles = Math.ceil(w / 8) * Math.ceil(h / 8);
    const r = { w, h, tiles, buffers: [new Map(), new Map(), new Map()], textures: new Map() };
    const bytes = (s) => ({ uniforms: this.P.uniforms.length * 4, per_pixel: s.bytes * w * h, per_tile: s.bytes * tiles, fixed: s.bytes }[s.kind]);
    // A scratch texture has as many rows as its size rule's bytes need; the
    // buffer a stage copies into it covers those whole rows.
    const rows = (b) => Math.max(1, Math.ceil(bytes(b.size) / (b.texture.width * 4)));
    const copyBytes = new Map();
    for (const st of this.P.stages) {
      if (!st.copy) continue;
      const t = this.P.groups[st.copy.group].find((b) => b.binding === st.copy.to);
      copyBytes.set(`${st.copy.group}:${st.copy.from}`, rows(t) * t.texture.width * 4);
    }
    this.P.groups.forEach((g, gi) => {
      for (const b of g) {
        let buf;
        if (b.size.kind === 'uniforms') buf = this.uniforms;
        else if (b.size.kind === 'data') buf = data[gi].get(b.binding).buf;
        else if (b.texture) {
          const tex = d.createTexture({ size: [b.texture.width, rows(b)], format: b.texture.format, usage: GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST });
          r.textures.set(`${gi}:${b.binding}`, tex);
          buf = tex.createView();
        } else {
          const size = Math.max(16, bytes(b.size), copyBytes.get(`${gi}:${b.binding}`) ?? 0);
          buf = d.createBuffer({ size, usage: B.STORAGE | B.COPY_SRC | B.COPY_DST });
        }
        r.buffers[gi].set(b.binding, buf);
      }
    });
    r.stageGroups = this.stages.map((s) => this.P.groups.map((g, gi) => d.createBindGroup({
      layout: s.layouts[gi],
      entries: g.filter((b) => s.used(gi, b)).map((b) => ({ binding: b.binding, resource: b.texture ? r.buffers[gi].get(b.binding) : { buffer: r.buffers[gi].get(b.binding) } })),
    })));
    r.args = d.createBuffer({ size: 16, usage: B.INDIRECT | B.COPY_DST });
    r.records = r.buffers[2].get(this.P.records);
    r.data = data[1];
    if (sel) this.sizedSel = r; else this.sized = r;
    return r;
  }

  /** Workgroups of a stage for a w × h frame. */
  groups(g, r) {
    const c = Math.ceil;
    switch (g.kind) {
      case 'items': { const n = c((r.data.get(g.binding)?.count ?? 0) / g.per_group) || 1; return [Math.min(n, 65535), c(n / 65535), 1]; }
      case 'tiles': return [c(r.tiles / g.per_group), 1, 1];
      case 'blocks': return [c(r.w / g.side), c(r.h / g.side), g.layers];
      case 'pixel_tiles': return [c(r.w / 8), c(c(r.h / 8) / g.tiles_per_group), 1];
      default: return null;
    }
  }

  /** The stages of one dispatch into `set`'s buffers, as src/gpu/dispatch.rs runs them. */
  encodeStages(enc, set) {
    this.P.groups.forEach((g, gi) => g.filter((b) => b.clear).forEach((b) => enc.clearBuffer(set.buffers[gi].get(b.binding))));
    this.stages.forEach(({ st, pipeline }, si) => {
      const ind = st.groups.kind === 'indirect';
      if (ind) {
        const list = set.buffers[2].get(st.groups.binding);
        enc.copyBufferToBuffer(list, 0, set.args, 0, 12);
      }
      const pass = enc.beginComputePass();
      set.stageGroups[si].forEach((g, i) => pass.setBindGroup(i, g));
      pass.setPipeline(pipeline);
      if (ind) pass.dispatchWorkgroupsIndirect(set.args, 0);
      else pass.dispatchWorkgroups(...this.groups(st.groups, set));
      pass.end();
      if (st.copy) {
        const tex = set.textures.get(`${st.copy.group}:${st.copy.to}`);
        const buffer = set.buffers[st.copy.group].get(st.copy.from);
        enc.copyBufferToTexture({ buffer, bytesPerRow: tex.width * 4 }, { texture: tex }, [tex.width, tex.height]);
      }
    });
    for (const st of this.P.stages) {
      if (st.groups.kind === 'indirect') this.device.queue.writeBuffer(set.buffers[2].get(st.groups.binding), 0, new Uint32Array([0, 1, 1, 0]));
    }
  }

  /** One frame: the stages as src/gpu/dispatch.rs runs them, then the present pass. */
  frame(uniformWords, w, h, present, readback) {
    const run = async () => {
      const d = this.device, r = this.resources(w, h);
      d.queue.writeBuffer(this.uniforms, 0, uniformWords);
      if (this.presentUniforms?.size !== present.byteLength) this.presentUniforms = d.createBuffer({ size: present.byteLength, usage: B.UNIFORM | B.COPY_DST });
      d.queue.writeBuffer(this.presentUniforms, 0, present);
      const enc = d.createCommandEncoder();
      const sets = [r];
      if (this.selData) sets.push(this.resources(w, h, true));
      for (const set of sets) this.encodeStages(enc, set);
      // The present pass's bindings as the program lists them (src/view/present.rs).
      const sources = { records: r.records, uniforms: this.presentUniforms, selection: sets[sets.length - 1].records };
      const { group, bindings } = this.P.present;
      const presentGroup = d.createBindGroup({
        layout: this.present.getBindGroupLayout(group),
        entries: bindings.map(({ binding, source }) => ({ binding, resource: { buffer: sources[source] } })),
      });
      const texture = this.context.getCurrentTexture();
      const rp = enc.beginRenderPass({ colorAttachments: [{ view: texture.createView(), loadOp: 'clear', storeOp: 'store', clearValue: [0, 0, 0, 1] }] });
      rp.setPipeline(this.present);
      rp.setBindGroup(group, presentGroup);
      rp.draw(3);
      rp.end();
      let stats = null, pixels = null, rays = null;
      if (readback) {
        // The records' head plane (templates/shared/pixels.wgsl): all the statistics read.
        stats = d.createBuffer({ size: w * h * 8, usage: B.MAP_READ | B.COPY_DST });
        enc.copyBufferToBuffer(r.records, 0, stats, 0, w * h * 8);
        // Sphere tracing's per-ray statistics words, for the Lipschitz warning.
        if (this.P.ray_stats != null) {
          rays = d.createBuffer({ size: w * h * 4, usage: B.MAP_READ | B.COPY_DST });
          enc.copyBufferToBuffer(r.buffers[2].get(this.P.ray_stats), 0, rays, 0, w * h * 4);
        }
        if (readback === 'pixels') {
          const cw = this.canvas.width, ch = this.canvas.height, row = Math.ceil(cw * 4 / 256) * 256;
          pixels = { buf: d.createBuffer({ size: row * ch, usage: B.MAP_READ | B.COPY_DST }), row, cw, ch };
          enc.copyTextureToBuffer({ texture }, { buffer: pixels.buf, bytesPerRow: row }, [cw, ch]);
        }
      }
      const t0 = performance.now();
      d.queue.submit([enc.finish()]);
      await d.queue.onSubmittedWorkDone();
      const out = { ms: performance.now() - t0, w, h };
      if (stats) {
        await stats.mapAsync(GPUMapMode.READ);
        Object.assign(out, recordStats(new Uint32Array(stats.getMappedRange())));
        stats.destroy();
      }
      if (rays) {
        await rays.mapAsync(GPUMapMode.READ);
        out.rays = rayStats(new Uint32Array(rays.getMappedRange()));
        rays.destroy();
      }
      if (pixels) {
        await pixels.buf.mapAsync(GPUMapMode.READ);
        const src = new Uint8Array(pixels.buf.getMappedRange()), rgba = new Uint8Array(pixels.cw * pixels.ch * 4);
        for (let y = 0; y < pixels.ch; y++) rgba.set(src.subarray(y * pixels.row, y * pixels.row + pixels.cw * 4), y * pixels.cw * 4);
        pixels.buf.destroy();
        out.rgba = rgba;
      }
      return out;
    };
    const p = this.lock.then(run);
    this.lock = p.catch(() => {});
    return p;
  }
}

/** Work per pixel, hits and unresolved pixels of a frame's record heads (colour, work: src/render/record.rs). */
function recordStats(words) {
  let work = 0, hits = 0, unresolved = 0;
  const n = words.length / 2;
  for (let i = 0; i < n; i++) {
    work += words[2 * i + 1] & 0xffff;
    const s = words[2 * i] >>> 30;
    if (s === 1) hits++;
    if (s === 2) unresolved++;
  }
  return { work_mean: work / Math.max(n, 1), hits, unresolved };
}


/**
 * Sphere tracing's per-ray statistics words summed as src/render/record.rs
 * `RayStats::add` does: fallbacks (low 16 bits), rays that saw a Lipschitz
 * violation (bit 31) and the largest rate of change of f / L seen (bits
 * 16-30, a half float without its sign).
 */
function rayStats(words) {
  let fallbacks = 0, violations = 0, ratio = 0;
  for (const w of words) {
    fallbacks += w & 0xffff;
    violations += w >>> 31;
    ratio = Math.max(ratio, halfToFloat((w >>> 16) & 0x7fff));
  }
  return { fallbacks, violations, ratio };
}

/** An IEEE half float's value (finite, non-negative; +inf saturated). */
function halfToFloat(h) {
  const exp = (h >> 10) & 0x1f, man = h & 0x3ff;
  if (exp === 0) return man * 2 ** -24;
  if (exp === 31) return Infinity;
  return (1 + man / 1024) * 2 ** (exp - 15);
}
