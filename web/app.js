// isotrace view: the page's controls, camera and frame loop; web/host.js
// runs the kernels. The server (src/view/) compiles formulas and sends a "program": the
// validated WGSL render kernel, the uniform blocks' fields and offsets, the
// bind groups with the size rule of each buffer, and the stages of one
// dispatch. The host follows that description: it knows no traversal and
// no field source. What it computes itself is what moves every frame: the
// camera (src/render/mod.rs `Camera::frame`), the values that follow it
// (src/gpu/bisect.rs and sphere.rs `block`) and the sliders' uniforms.
// Nothing here creates a pipeline except a new program (a new formula or a
// structural option) and the present pipeline, once.

// frameLog: 'coarse' / 'full' per frame drawn, in order; edits: scene edits
// drawn in full; warning: the CLI's warning about the last full frame;
// newParams: the parameters the server gave a value to.
const view = (window.__view = {
  ready: false, pipelines: 0, programs: 0, frames: 0, lastFrame: null, error: null, diagnostic: '', frameLog: [], edits: 0, warning: '', newParams: [],
});
const $ = (id) => document.getElementById(id);

// ---- Vectors and the CLI's camera model ----------------------------------
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const mul = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const len = (a) => Math.sqrt(dot(a, a));
const norm = (a) => mul(a, 1 / len(a)); // glam: v * (1 / |v|)

/** `Camera::frame`: forward, right, up and tan(fov / 2). */
function cameraFrame(c) {
  const forward = norm(sub(c.target, c.eye));
  const right = norm(cross(forward, c.up));
  return { forward, right, up: cross(right, forward), tan: Math.tan(0.5 * (c.fov * (Math.PI / 180))) };
}

/** Rotates v about the unit axis k by angle a (Rodrigues). */
function rotate(v, k, a) {
  const c = Math.cos(a), s = Math.sin(a);
  return add(add(mul(v, c), mul(cross(k, v), s)), mul(k, dot(k, v) * (1 - c)));
}

// ---- State ----------------------------------------------------------------
let S = null; // the server's last good state (program, view, options, …)
const U = {}; // what the controls edit
let host = null;
let GUI = null;
let Host = null;

async function loadStart() {
  const el = document.getElementById('isotrace-start');
  if (el) return JSON.parse(el.textContent);
  const r = await fetch('/api/start');
  const j = await r.json();
  if (!r.ok) throw new Error(j.error || `HTTP ${r.status}`);
  return j;
}

/** An ES module: inline in the exported page, else from the server. */
async function loadModule(id, url) {
  const el = document.getElementById(id);
  return import(el ? URL.createObjectURL(new Blob([el.textContent], { type: 'text/javascript' })) : url);
}

/** POST to the API: JSON or a file; a refusal throws its message. */
async function api(route, body) {
  const r = await fetch('/api/' + route, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
  if (!r.ok) {
    let m = `HTTP ${r.status}`;
    try { m = (await r.json()).error; } catch (_) { /* not JSON */ }
    throw new Error(m);
  }
  return (r.headers.get('Content-Type') || '').startsWith('application/json') ? r.json() : r.blob();
}

// ---- The command line of the current view ----------------------------------
const isScene = () => !!(S && S.scene);

/**
 * The `isotrace render` arguments (without -o) that reproduce the view. A
 * scene's framing (box, and the camera and eps until the user moves them)
 * is left to the server, which frames the edited scene as `render` frames
 * a file; `box`: give the box anyway (a selected node's subtree is traced
 * in the whole scene's box).
 */
function cliArgs({ box = false } = {}) {
  const a = [U.input];
  const csv = (v) => v.map(String).join(',');
  const scene = isScene();
  a.push('--size', `${U.width}x${U.height}`);
  if (!scene || box) a.push(`--box=${csv(U.box)}`);
  if (!scene || U.cameraSet) a.push(`--eye=${csv(U.eye)}`, `--target=${csv(U.target)}`, `--up=${csv(U.up)}`, '--fov', String(U.fov));
  if (!scene || U.epsSet) a.push(`--eps=${U.eps}`);
  if (!isScene()) a.push(`--t=${U.time}`);
  for (const p of U.params) a.push('--param', `${p.name}=${p.value}`);
  if (U.clip > 0) a.push('--clip', `sphere:${U.clip}`);
  a.push('--method', U.method);
  if (U.method === 'bisect') {
    a.push('--algebra', U.algebra, '--max-iter', String(U.max_iter));
    if (U.shadows) a.push('--shadows');
    if (U.layers > 1) a.push('--layers', String(U.layers), '--opacity', String(U.opacity));
    if (!['', '0'].includes(U.iso.trim())) a.push(`--iso=${U.iso.replace(/\s+/g, '')}`);
    if (U.reflect > 0) a.push('--reflect', String(U.reflect), '--reflectivity', String(U.reflectivity));
  } else {
    if (U.shadows) a.push('--shadows');
    if (U.glass) a.push('--glass');
    a.push('--omega', String(U.omega));
    if (U.lipschitzSet) a.push('--lipschitz', String(U.lipschitz));
  }
  a.push('--color', U.color === 'steps' ? `steps:${U.steps_max}` : U.color);
  return a;
}

const shellQuote = (s) => (/^[A-Za-z0-9_@%+=:,./-]+$/.test(s) ? s : `'${s.replace(/'/g, `'\\''`)}'`);
const cliCommand = () => `isotrace render ${cliArgs().map(shellQuote).join(' ')} -o view.png`;

/** Adopts a state from the server (or the exported page). */
function adopt(state) {
  // /api/program answers the program alone; whether a server is there
  // stays what the start said.
  S = { ...state, server: state.server ?? S?.server ?? false };
  const v = state.view, o = state.options;
  Object.assign(U, {
    input: U.input ?? state.args[0], width: v.width, height: v.height, box: v.box, eye: v.eye, target: v.target, up: v.up, fov: v.fov,
    eps: v.eps, time: v.time, max_iter: v.max_iter, clip: v.clip, params: state.params.map((p) => ({ ...p })),
    method: o.method, algebra: o.algebra ?? U.algebra ?? 'auto', shadows: o.shadows, glass: !!o.glass, layers: o.layers ?? 1,
    opacity: o.opacity ?? 0.5, iso: (o.iso?.length ? o.iso : [0]).join(','), reflect: o.reflect ?? 0, reflectivity: o.reflectivity ?? 0.35,
    omega: o.omega ?? 1.2, lipschitz: o.lipschitz ?? 1, color: U.color ?? 'shade', steps_max: U.steps_max ?? 64,
  });
  const c = o.color || 'shade';
  if (!U.colorSet) U.color = c.startsWith('steps') ? 'steps' : c === 'phong' ? 'shade' : c;
}

// ---- Uniforms by field name ---------------------------------------------------
function uniformWords(w, h) {
  const P = S.program, words = new Uint32Array(P.uniforms), f = new Float32Array(words.buffer);
  const at = {};
  for (const x of P.blocks.frame) at['frame.' + x.name] = x.offset / 4;
  for (const x of P.blocks.traversal) at['trav.' + x.name] = (P.blocks.traversal_offset + x.offset) / 4;
  const F = (name, vals) => vals.forEach((v, i) => { f[at[name] + i] = v; });
  const W = (name, vals) => vals.forEach((v, i) => { words[at[name] + i] = v; });
  const cam = { eye: U.eye, target: U.target, up: U.up, fov: U.fov }, cf = cameraFrame(cam), b = U.box;
  F('frame.eye', [...U.eye, 0]);
  F('frame.forward', [...cf.forward, 0]);
  F('frame.right', [...cf.right, 0]);
  F('frame.up', [...cf.up, 0]);
  F('frame.box_min', [b[0], b[2], b[4], 0]);
  F('frame.box_max', [b[1], b[3], b[5], U.clip > 0 ? U.clip : 0]);
  W('frame.size', [w, h]);
  W('frame.tile_origin', [0, 0]);
  W('frame.tile_size', [w, h]);
  F('frame.tan_half_fov', [cf.tan]);
  F('frame.eps', [U.eps]);
  F('frame.time', [U.time]);
  F('frame.params', U.params.map((p) => p.value));
  const follow = P.follow;
  if (P.method === 'bisect') {
    // gpu::bisect::block: the light above and left of the eye, shadow eps 4 × eps.
    if (follow.light) {
      const dist = len(sub(U.eye, U.target));
      F('trav.light', add(U.eye, mul(sub(mul(cf.up, 0.6), mul(cf.right, 0.4)), dist)));
    }
    if (follow.eps_factor) F('trav.light', [f[at['trav.light']], f[at['trav.light'] + 1], f[at['trav.light'] + 2], follow.eps_factor * U.eps]);
    W('trav.max_iter', [U.max_iter]);
    F('trav.opacity', [U.opacity]);
    F('trav.reflectivity', [U.reflectivity]);
    const iso = U.iso.split(',').map(Number).filter((x) => Number.isFinite(x)).slice(0, 8);
    F('trav.iso', iso);
  } else {
    // gpu::sphere::block: the key light, half a pixel, eps-min = eps.
    if (follow.light) F('trav.light', [...norm(sub(sub(mul(cf.up, 0.8), mul(cf.forward, 0.2)), mul(cf.right, 0.7))), 0]);
    F('trav.pixel_radius', [cf.tan / h]);
    if (follow.eps_factor) F('trav.eps_min', [follow.eps_factor * U.eps]);
    F('trav.omega', [U.omega]);
    F('trav.inv_lipschitz', [1 / U.lipschitz]);
  }
  return words;
}

function presentWords(w, h) {
  const P = S.program, fields = P.blocks.present;
  const words = new Uint32Array(Math.max(...fields.map((x) => x.offset + x.size)) / 4);
  const at = Object.fromEntries(fields.map((x) => [x.name, x.offset / 4]));
  words.set([w, h], at.size);
  words.set([U.width, U.height], at.canvas);
  words[at.mode] = { normal: 1, steps: 2 }[U.color] ?? 0;
  words[at.steps_max] = U.steps_max;
  words[at.highlight] = host.selData ? 1 : 0;
  return words;
}

// ---- Frames: coarse while the view moves, full when idle ----------------------
let idleTimer = null, pending = null;

/** Renders a frame now; `readback`: 'stats' or 'pixels'. */
async function render(full, readback = 'stats') {
  const k = full ? 1 : 4, w = Math.max(1, Math.ceil(U.width / k)), h = Math.max(1, Math.ceil(U.height / k));
  if (host.canvas.width !== U.width || host.canvas.height !== U.height) {
    host.canvas.width = U.width;
    host.canvas.height = U.height;
  }
  const out = await host.frame(uniformWords(w, h), w, h, presentWords(w, h), readback);
  view.frames++;
  view.frameLog.push(full ? 'full' : 'coarse');
  view.lastFrame = { ms: out.ms, width: w, height: h, full, work_mean: out.work_mean, unresolved: out.unresolved, hits: out.hits };
  showStats();
  if (readback) showWarning(out.rays);
  return out;
}

/** Resolves once what was drawn so far is on screen (the frame after the next). */
const presented = () => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)));

/** The CLI's warning about a frame (the server's text, filled from this frame's ray statistics, if any). */
function showWarning(rays = { violations: 0, ratio: 0 }) {
  const t = S.warnings?.lipschitz;
  const seen = rays.ratio * U.lipschitz;
  // As the CLI's `{:.3}`.
  view.warning = t && rays.violations > 0 ? t.replaceAll('{violations}', String(rays.violations)).replaceAll('{lipschitz}', String(U.lipschitz)).replaceAll('{seen}', seen.toFixed(3)) : '';
  $('warning').textContent = view.warning;
  const fix = $('lipschitz-fix');
  fix.hidden = !view.warning;
  fix.value = String(Math.ceil(seen * 1000) / 1000);
  fix.textContent = `use --lipschitz ${fix.value}`;
}

function setLipschitz(x) {
  if (!(x >= 1 && Number.isFinite(x))) return; // as SphereOptions::check
  U.lipschitz = x;
  U.lipschitzSet = true;
  gui?.controllersRecursive().forEach((c) => c.updateDisplay());
  moved();
}

function showStats() {
  const f = view.lastFrame;
  if (!f) return;
  const work = S.program.method === 'bisect' ? 'evaluations' : 'steps';
  $('stats').textContent = `${f.full ? 'full' : 'coarse'} ${f.width}×${f.height}: ${f.ms.toFixed(1)} ms` +
    (f.work_mean !== undefined ? `  ·  ${work} per pixel ${f.work_mean.toFixed(1)}  ·  unresolved ${f.unresolved}  ·  hits ${f.hits}` : '') +
    `\npipelines created ${view.pipelines}  ·  programs ${view.programs}` + (view.sceneMs !== undefined ? `  ·  scene layout ${view.sceneMs.toFixed(1)} ms (no compile)` : '');
}

/** The view moved: a coarse frame now, the full one when idle. */
function moved() {
  if (!pending) pending = requestAnimationFrame(() => { pending = null; render(false, null).catch(fail); });
  clearTimeout(idleTimer);
  idleTimer = setTimeout(() => render(true).catch(fail), 180);
}

function fail(e) {
  view.error = String(e && e.message || e);
  $('stats').textContent = 'error: ' + view.error;
}

// ---- Camera controls (mouse and touch) ---------------------------------------
function installCamera(canvas) {
  const pointers = new Map();
  let pinch = null;
  canvas.addEventListener('contextmenu', (e) => e.preventDefault());
  canvas.addEventListener('pointerdown', (e) => { canvas.setPointerCapture(e.pointerId); pointers.set(e.pointerId, { x: e.clientX, y: e.clientY, button: e.button, shift: e.shiftKey }); pinch = null; });
  canvas.addEventListener('pointerup', (e) => { pointers.delete(e.pointerId); pinch = null; });
  canvas.addEventListener('pointercancel', (e) => { pointers.delete(e.pointerId); pinch = null; });
  canvas.addEventListener('pointermove', (e) => {
    const p = pointers.get(e.pointerId);
    if (!p) return;
    U.cameraSet = true;
    const dx = e.clientX - p.x, dy = e.clientY - p.y;
    p.x = e.clientX; p.y = e.clientY;
    if (pointers.size === 2) {
      const [a, b] = [...pointers.values()];
      const d = Math.hypot(a.x - b.x, a.y - b.y);
      if (pinch) zoom(pinch / Math.max(d, 1));
      pinch = d;
      pan(dx / 2, dy / 2);
    } else if (p.button === 2 || p.shift) pan(dx, dy);
    else orbit(dx, dy);
    moved();
  });
  canvas.addEventListener('wheel', (e) => { e.preventDefault(); U.cameraSet = true; zoom(Math.exp(e.deltaY * 0.001)); moved(); }, { passive: false });
}

function orbit(dx, dy) {
  const up = norm(U.up), off = sub(U.eye, U.target);
  let o = rotate(off, up, -dx * 0.01);
  const right = norm(cross(sub([0, 0, 0], o), up));
  const o2 = rotate(o, right, -dy * 0.01);
  if (Math.abs(dot(norm(o2), up)) < 0.995) o = o2; // never over the pole: the up vector would be parallel
  U.eye = add(U.target, o);
}

function pan(dx, dy) {
  const cf = cameraFrame(U), dist = len(sub(U.eye, U.target)), k = 2 * cf.tan * dist / U.height;
  const move = add(mul(cf.right, -dx * k), mul(cf.up, dy * k));
  U.eye = add(U.eye, move);
  U.target = add(U.target, move);
}

function zoom(f) {
  U.eye = add(U.target, mul(sub(U.eye, U.target), f));
}

// ---- Programs: the server compiles ---------------------------------------------
/** Asks the server for the program of the current controls; keeps the last good one on error. */
async function recompile(args = cliArgs(), adjust = () => {}) {
  if (!S.server) return;
  const t0 = performance.now();
  $('compile-info').textContent = ' compiling…';
  try {
    const state = await api('program', { args, scene: S.scene });
    await host.setProgram(state.program);
    const input = U.input;
    adopt(state);
    U.input = input;
    adjust(state);
    showNewParams(state.new_params);
    $('diagnostic').textContent = '';
    view.diagnostic = '';
    $('compile-info').textContent = ` compiled in ${state.compile_ms.toFixed(0)} ms (server), ${(performance.now() - t0).toFixed(0)} ms in all`;
    buildGui();
    await render(true);
  } catch (e) {
    view.diagnostic = String(e.message || e);
    $('diagnostic').textContent = view.diagnostic;
    $('compile-info').textContent = ' kept the last good program';
  }
}

async function compileFormula() {
  const text = $('formula').value, before = U.input;
  // An unchanged formula keeps its origin (@name, FILE.iso and its header).
  U.input = text === S.formula ? before : text;
  // A new formula has its own parameters: the server gives their defaults
  // (a header's, else 1 for a name nothing sets) ...
  const args = cliArgs().filter((a, i, all) => a !== '--param' && all[i - 1] !== '--param');
  // ... and a name that had a slider keeps its value (a uniform: no compile).
  const had = new Map(U.params.map((p) => [p.name, p.value]));
  await recompile(args, (state) => U.params.forEach((p) => { if (state.new_params.includes(p.name) && had.has(p.name)) p.value = had.get(p.name); }));
  if (view.diagnostic) U.input = before;
}

/** Says which parameters the server gave a value to (names the formula uses that nothing set). */
function showNewParams(names) {
  view.newParams = names ?? [];
  const list = U.params.filter((p) => view.newParams.includes(p.name)).map((p) => `${p.name} = ${p.value}`);
  $('params-note').textContent = list.length ? `new parameter${list.length > 1 ? 's' : ''} ${list.join(', ')}: a slider under "parameters" (the CLI line gives --param)` : '';
}

// ---- Scenes: edits change buffers only --------------------------------------------
async function sceneEdited() {
  if (!S.server) return;
  try {
    const r = await api('scene', { args: cliArgs(), scene: S.scene });
    // A node type the kernel was built without needs a new kernel.
    if ((r.features & ~S.scene_features) !== 0) return recompile();
    host.setFieldData(r.buffers);
    followScene(r);
    view.sceneMs = r.layout_ms;
    if (view.selected != null) await select(view.selected, false);
    $('diagnostic').textContent = '';
    // The coarse frame first, on screen, as when the camera moves.
    await render(false, null);
    await presented();
    await render(true);
    view.edits++;
  } catch (e) {
    view.diagnostic = String(e.message || e);
    $('diagnostic').textContent = view.diagnostic;
  }
}

/**
 * What an edit moves with the scene, from the server: the framing `render`
 * gives the edited scene (its box always, so a grown solid is never cut;
 * the camera and eps unless the user set them), and the uniforms (its
 * Lipschitz bound).
 */
function followScene(r) {
  const v = r.view;
  S.program.uniforms = r.uniforms;
  Object.assign(S, { view: v, options: r.options, warnings: r.warnings });
  U.box = v.box;
  if (!U.cameraSet) Object.assign(U, { eye: v.eye, target: v.target, up: v.up, fov: v.fov });
  if (!U.epsSet) U.eps = v.eps;
  U.lipschitz = r.options.lipschitz;
  gui?.controllersRecursive().forEach((c) => c.updateDisplay());
  clipControl?.max(boxDiagonal()).step(boxDiagonal() / 200);
}

const boxDiagonal = () => len(sub([U.box[1], U.box[3], U.box[5]], [U.box[0], U.box[2], U.box[4]]));

// ---- Saving through the CLI's render path -------------------------------------------
async function save(format) {
  try {
    const blob = await api('render', { args: cliArgs(), format, scene: S.scene });
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = `isotrace-view.${format}`;
    a.click();
  } catch (e) {
    $('diagnostic').textContent = String(e.message || e);
  }
}

// ---- Controls (lil-gui) ----------------------------------------------------------
let gui = null, playing = false, clipControl = null;

function buildGui() {
  gui?.destroy();
  gui = new GUI({ container: $('gui'), title: 'isotrace view' });
  const server = S.server, full = () => render(true).catch(fail);
  const structural = (c) => { if (!server) c.disable(); return c.onFinishChange(() => recompile()); };
  const actions = {
    copy: () => { const t = cliCommand(); navigator.clipboard?.writeText(t).catch(() => {}); $('note').textContent = t; },
    reset: () => {
      U.cameraSet = false;
      // A scene's camera is its framing's, from the server (it follows edits).
      if (isScene() && server) return sceneEdited();
      Object.assign(U, { eye: S.view.eye, target: S.view.target, up: S.view.up, fov: S.view.fov });
      full();
    },
    png: () => save('png'), exr: () => save('exr'), play: () => { playing = !playing; if (playing) animate(); },
  };
  gui.add(actions, 'copy').name('copy CLI command');
  gui.add(actions, 'reset').name('reset camera');
  if (server) { gui.add(actions, 'png').name('save PNG (server, full size)'); gui.add(actions, 'exr').name('save EXR (server, full size)'); }
  const v = gui.addFolder('view');
  v.add(U, 'width', [128, 256, 384, 512, 768, 1024]).name('size').onChange((x) => { U.height = x; full(); });
  v.add(U, 'fov', 5, 120, 0.5).onChange(() => { U.cameraSet = true; moved(); });
  const l2 = { get v() { return Math.log2(U.eps); }, set v(x) { U.eps = 2 ** x; } };
  v.add(l2, 'v', -24, 0, 0.25).name('eps (log2)').onChange(() => { U.epsSet = true; moved(); });
  clipControl = v.add(U, 'clip', 0, boxDiagonal(), boxDiagonal() / 200).name('clip sphere (0: off)').onChange(moved);
  if (!isScene()) {
    const p = gui.addFolder('parameters');
    p.add(U, 'time', 0, 2 * Math.PI, 0.01).name('t').listen().onChange(moved);
    p.add(actions, 'play').name('play / pause t');
    U.params.forEach((q, i) => {
      const span = Math.max(1, Math.abs(q.value)) * 2;
      p.add(U.params[i], 'value', q.value - span, q.value + span, span / 500).name(q.name).onChange(moved);
    });
  }
  const m = gui.addFolder('method and colour');
  structural(m.add(U, 'method', isScene() ? ['sphere', 'bisect'] : ['bisect', 'sphere']));
  // A scene's nodes have interval enclosures only.
  if (U.method === 'bisect') structural(m.add(U, 'algebra', isScene() ? ['auto', 'ia'] : ['auto', 'ia', 'raa']));
  const kernelColors = U.method === 'bisect' ? ['gradient', 'depth'] : ['field'];
  m.add(U, 'color', ['shade', 'normal', 'steps', ...kernelColors]).name('colour').onChange((c) => {
    U.colorSet = true;
    if (kernelColors.includes(c) || (S.options.color !== 'shade' && !['shade', 'normal', 'steps'].includes(S.options.color))) recompile(); else full();
  });
  m.add(U, 'steps_max', 1, 1024, 1).name('steps: full scale').onChange(full);
  const mod = gui.addFolder('modalities');
  structural(mod.add(U, 'shadows'));
  if (U.method === 'bisect') {
    structural(mod.add(U, 'layers', 1, 8, 1).name('transparency layers'));
    mod.add(U, 'opacity', 0.05, 1, 0.01).onChange(moved);
    mod.add(U, 'iso').name('isovalues (c,…)').onFinishChange(() => {
      const n = U.iso.split(',').length, had = Math.max(1, (S.options.iso ?? []).length);
      if (n !== had) recompile(); else full();
    });
    structural(mod.add(U, 'reflect', 0, 8, 1).name('reflections'));
    mod.add(U, 'reflectivity', 0, 1, 0.01).onChange(moved);
    mod.add(U, 'max_iter', 16, 4096, 1).name('iteration budget').onChange(moved);
  } else {
    structural(mod.add(U, 'glass'));
    mod.add(U, 'omega', 1, 1.95, 0.01).name('over-relaxation ω').onChange(moved);
    // --lipschitz: f / L is traced (a uniform: no compile).
    mod.add(U, 'lipschitz').min(1).name('Lipschitz bound L').onFinishChange((x) => setLipschitz(x));
  }
  if (isScene()) sceneControls();
}

function sceneControls() {
  const f = gui.addFolder(`scene: ${S.scene.nodes.length} nodes (edits change buffers, no compile)`);
  S.scene.nodes.forEach((node, i) => {
    const g = f.addFolder(`${i}: ${node.type}`).close();
    // Opening a node selects it: it is traced alone and its visible part tinted.
    g.onOpenClose((x) => { if (!x._closed) select(i); else if (view.selected === i) select(null); });
    const edit = (obj, key, name) => { const c = g.add(obj, key).name(name); if (!S.server) c.disable(); c.onFinishChange(sceneEdited); };
    // Numbers, lists of numbers, and the same one level down (a profile,
    // a warp): `warp.rate`, `profile.half[0]`.
    const fields = (obj, prefix) => {
      for (const [k, val] of Object.entries(obj)) {
        if (typeof val === 'number' && !(prefix === '' && (k === 'left' || k === 'right' || k === 'child'))) edit(obj, k, prefix + k);
        else if (Array.isArray(val)) val.forEach((_, j) => { if (typeof val[j] === 'number') edit(val, j, `${prefix}${k}[${j}]`); });
        else if (prefix === '' && val && typeof val === 'object') fields(val, `${k}.`);
      }
    };
    fields(node, '');
  });
}

/** The subtree of node i as a scene of its own. */
function subtree(scene, i) {
  const nodes = [];
  const visit = (k) => {
    const n = { ...scene.nodes[k] };
    if (typeof n.left === 'number') { n.left = visit(n.left); n.right = visit(n.right); }
    nodes.push(n);
    return nodes.length - 1;
  };
  const root = visit(i);
  return { isotrace_scene: 1, nodes, root };
}

/** Selects scene node i (null: none): its buffers from the server, no pipeline; `draw`: a frame after. */
async function select(i, draw = true) {
  view.selected = i;
  if (i === null || !S.server) { host.setSelection(null); return draw ? render(true).catch(fail) : undefined; }
  try {
    const r = await api('scene', { args: cliArgs({ box: true }), scene: subtree(S.scene, i) });
    if (view.selected !== i) return;
    host.setSelection(r.buffers);
    view.selectionReady = i;
    if (draw) await render(true);
  } catch (e) {
    $('diagnostic').textContent = String(e.message || e);
  }
}

function animate() {
  if (!playing) return;
  U.time = (U.time + 0.03) % (2 * Math.PI);
  render(true).then(() => requestAnimationFrame(animate)).catch(fail);
}

// ---- Start -------------------------------------------------------------------------
async function main() {
  try {
    const [start, lil, hostModule] = await Promise.all([loadStart(), loadModule('isotrace-lil-gui', '/lil-gui.esm.min.js'), loadModule('isotrace-host', '/host.js')]);
    GUI = lil.GUI;
    Host = hostModule.Host;
    const q = new URLSearchParams(location.search);
    if (!navigator.gpu) throw new Error('this browser has no WebGPU (navigator.gpu is missing)');
    const adapter = await navigator.gpu.requestAdapter();
    if (!adapter) throw new Error('no WebGPU adapter');
    view.adapter = { fallback: adapter.isFallbackAdapter ?? null, architecture: adapter.info?.architecture ?? '' };
    const device = await adapter.requestDevice({
      requiredLimits: {
        maxStorageBufferBindingSize: adapter.limits.maxStorageBufferBindingSize, maxBufferSize: adapter.limits.maxBufferSize,
        // A scene's stages bind up to 8 storage buffers (the default limit is 8, SwiftShader's 10).
        maxStorageBuffersPerShaderStage: adapter.limits.maxStorageBuffersPerShaderStage,
        // A scene's tile pruned trees are a texture of 8192-texel rows, one row per
        // 8 tiles (8192 rows at 2048²).
        maxTextureDimension2D: adapter.limits.maxTextureDimension2D,
      },
    });
    device.lost.then((i) => fail('the WebGPU device was lost: ' + i.message));
    for (const name of ['createComputePipeline', 'createComputePipelineAsync', 'createRenderPipeline', 'createRenderPipelineAsync']) {
      const f = device[name].bind(device);
      device[name] = (...a) => { view.pipelines++; return f(...a); };
    }
    adopt(start);
    if (q.get('size')) U.width = U.height = Math.min(2048, Math.max(8, Number(q.get('size')) | 0));
    host = new Host(device, $('canvas'), start.present);
    await host.setProgram(start.program);
    $('formula').value = start.formula ?? (start.scene ? '(a scene: edit its nodes below)' : '');
    if (!start.server || start.scene) { $('formula').disabled = true; $('compile').disabled = true; }
    if (!start.server) {
      $('note').textContent = 'A static page (isotrace view --export): the camera, parameters, t, eps, clip sphere, opacity, reflectivity and colours work here. ' +
        'Editing the formula, switching method, algebra or a modality that changes the shader, editing a scene and saving PNG / EXR need the server: isotrace view ' + (start.input ?? '');
    }
    $('compile').onclick = () => compileFormula();
    $('lipschitz-fix').onclick = () => setLipschitz(Number($('lipschitz-fix').value));
    showNewParams(start.new_params);
    $('formula').addEventListener('keydown', (e) => { if (e.key === 'Enter' && e.ctrlKey) compileFormula(); });
    installCamera($('canvas'));
    buildGui();
    await render(true);
    Object.assign(view, {
      ready: true, cliArgs, cliCommand, render, recompile, compileFormula, sceneEdited, select, U, state: () => S, gui: () => gui,
      capture: async () => { const o = await render(true, 'pixels'); return { width: U.width, height: U.height, rgba: Array.from(o.rgba) }; },
    });
  } catch (e) {
    fail(e);
  }
}

main();
