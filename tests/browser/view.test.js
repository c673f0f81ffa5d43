// Browser tests of `isotrace view` in headless Chromium (WebGPU on
// SwiftShader), run by scripts/test.sh after `cargo test`:
//   node tests/browser/view.test.js
// Each case starts `isotrace view … --port 0`, drives the page over the
// DevTools protocol and reads the canvas back with copyTextureToBuffer.
// Pictures are compared with `isotrace render` of the page's own "copy CLI
// command" line (lavapipe), within TOLERANCE. Screenshots and the measured
// frame times go to target/browser-artifacts/.

const { chromium } = require('playwright-core');
const { spawn, execFileSync, spawnSync } = require('child_process');
const fs = require('fs');
const http = require('http');
const path = require('path');
const zlib = require('zlib');

const ROOT = path.resolve(__dirname, '../..');
const BIN = path.join(ROOT, 'target/release/isotrace');
const ART = path.join(ROOT, 'target/browser-artifacts');
const CHROMIUM = process.env.CHROMIUM || '/usr/lib/chromium/chromium';
const FLAGS = ['--enable-unsafe-webgpu', '--enable-features=Vulkan', '--use-vulkan=swiftshader', '--use-angle=swiftshader'];
const SIZE = 128;
// Two float implementations (SwiftShader's, lavapipe's) trace the same
// kernel: a pixel may differ in its last bits or, on a silhouette, hit
// where the other misses. Stated tolerance: at least 99 % of the pixels
// within 8 levels (of 255) in every channel, and a mean difference of at
// most 1 level.
const TOLERANCE = { level: 8, within: 0.99, mean: 1.0 };

fs.mkdirSync(ART, { recursive: true });
const results = [];
const figures = {};

function check(name, ok, detail = '') {
  results.push({ name, ok, detail });
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${name}${detail ? ' — ' + detail : ''}`);
}

/** Starts `isotrace view INPUT --port 0` and resolves with its URL. */
function startServer(input) {
  return new Promise((resolve, reject) => {
    const proc = spawn(BIN, ['view', input, '--port', '0'], { stdio: ['ignore', 'pipe', 'inherit'] });
    let out = '';
    proc.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/isotrace view: (\S+)/);
      if (m) resolve({ url: m[1], proc });
    });
    proc.on('exit', (code) => reject(new Error(`isotrace view ${input} exited with ${code}`)));
  });
}

/** An 8-bit RGB / RGBA PNG (what isotrace writes) decoded to RGB. */
function decodePng(buf) {
  let pos = 8, width = 0, height = 0, ctype = 2;
  const idat = [];
  while (pos < buf.length) {
    const n = buf.readUInt32BE(pos), type = buf.toString('ascii', pos + 4, pos + 8), data = buf.subarray(pos + 8, pos + 8 + n);
    if (type === 'IHDR') { width = data.readUInt32BE(0); height = data.readUInt32BE(4); ctype = data[9]; }
    if (type === 'IDAT') idat.push(data);
    pos += 12 + n;
  }
  const bpp = ctype === 6 ? 4 : 3, stride = width * bpp, raw = zlib.inflateSync(Buffer.concat(idat));
  const out = Buffer.alloc(height * stride);
  for (let y = 0; y < height; y++) {
    const f = raw[y * (stride + 1)], line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    for (let x = 0; x < stride; x++) {
      const a = x >= bpp ? out[y * stride + x - bpp] : 0, b = y > 0 ? out[(y - 1) * stride + x] : 0, c = x >= bpp && y > 0 ? out[(y - 1) * stride + x - bpp] : 0;
      const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
      const pred = [0, a, b, (a + b) >> 1, pa <= pb && pa <= pc ? a : pb <= pc ? b : c][f];
      out[y * stride + x] = (line[x] + pred) & 255;
    }
  }
  const rgb = Buffer.alloc(width * height * 3);
  for (let i = 0; i < width * height; i++) for (let k = 0; k < 3; k++) rgb[3 * i + k] = out[bpp * i + k];
  return { width, height, rgb };
}

/** `isotrace render` of the page's own CLI line. */
function cliRender(args, name) {
  const file = path.join(ART, `${name}-cli.png`);
  execFileSync(BIN, ['render', ...args, '-o', file, '--force'], { stdio: ['ignore', 'ignore', 'inherit'] });
  return decodePng(fs.readFileSync(file));
}

function compare(cap, png) {
  if (cap.width !== png.width || cap.height !== png.height) return { ok: false, detail: `sizes ${cap.width}x${cap.height} and ${png.width}x${png.height}` };
  let sum = 0, within = 0, max = 0;
  const n = cap.width * cap.height;
  for (let i = 0; i < n; i++) {
    let m = 0;
    for (let k = 0; k < 3; k++) { const d = Math.abs(cap.rgba[4 * i + k] - png.rgb[3 * i + k]); sum += d; m = Math.max(m, d); }
    if (m <= TOLERANCE.level) within++;
    max = Math.max(max, m);
  }
  const mean = sum / (3 * n), frac = within / n;
  return { ok: frac >= TOLERANCE.within && mean <= TOLERANCE.mean, mean, frac, max, detail: `${(100 * frac).toFixed(2)} % within ${TOLERANCE.level} levels, mean ${mean.toFixed(3)}, max ${max}` };
}

const differs = (a, b) => a.rgba.some((v, i) => v !== b.rgba[i]);
const same = (a, b) => !differs(a, b);

async function openPage(browser, url, name) {
  const page = await browser.newPage({ viewport: { width: 1100, height: 760 } });
  page.on('pageerror', (e) => console.log(`[${name}] page error: ${e.message}`));
  const t0 = Date.now();
  // The server's URL carries the session token in its query.
  await page.goto(`${url}${url.includes('?') ? '&' : '?'}size=${SIZE}`);
  // SwiftShader compiles the page's kernel on the CPU: the formula leaves'
  // (three tape interpreters inside the scene's) takes minutes.
  await page.waitForFunction(() => window.__view && (window.__view.ready || window.__view.error), null, { timeout: 240000 });
  const state = await page.evaluate(() => ({ error: __view.error, adapter: __view.adapter, frame: __view.lastFrame, pipelines: __view.pipelines }));
  check(`${name}: page loads, finds an adapter and renders`, !state.error && !!state.frame, state.error || `${Date.now() - t0} ms, adapter ${JSON.stringify(state.adapter)}`);
  return page;
}

const capture = (page) => page.evaluate(() => __view.capture());
const cliArgs = (page) => page.evaluate(() => __view.cliArgs());
const pipelines = (page) => page.evaluate(() => __view.pipelines);

async function matchesCli(page, name) {
  const cap = await capture(page);
  const c = compare(cap, cliRender(await cliArgs(page), name));
  check(`${name}: pixels match isotrace render of the same view`, c.ok, c.detail);
  figures[name] = c.detail;
  await page.screenshot({ path: path.join(ART, `${name}.png`) });
  return cap;
}

/** Median frame time of full frames at `size`². */
async function frameTime(page, name, size) {
  const ms = await page.evaluate(async (s) => {
    __view.U.width = __view.U.height = s;
    const t = [];
    for (let i = 0; i < 4; i++) t.push((await __view.render(true, null)).ms);
    t.sort((a, b) => a - b);
    return t[1];
  }, size);
  figures[`frame_ms_${name}_${size}`] = Number(ms.toFixed(1));
  console.log(`     frame time ${name} ${size}x${size}: ${ms.toFixed(1)} ms`);
}

async function sphereCase(browser) {
  const { url, proc } = await startServer('@sphere');
  try {
    const page = await openPage(browser, url, 'sphere');
    await matchesCli(page, 'sphere');
    await frameTime(page, 'sphere', 256);
    await page.close();
  } finally { proc.kill(); }
}

async function torusCase(browser) {
  const { url, proc } = await startServer('tests/browser/torus-ia.iso');
  try {
    const page = await openPage(browser, url, 'torus');
    await page.evaluate(async () => { __view.U.shadows = true; await __view.recompile(); });
    const args = await cliArgs(page);
    check('torus: shadows are on in the CLI line', args.includes('--shadows'), args.join(' '));
    const before = await matchesCli(page, 'torus-shadows');
    // A parameter slider: uniforms only.
    const p0 = await pipelines(page);
    await page.evaluate(() => __view.gui().controllersRecursive().find((c) => c._name === 'r').setValue(0.5));
    await page.waitForTimeout(600);
    const moved = await capture(page);
    const p1 = await pipelines(page);
    check('slider r: the picture changes', differs(before, moved));
    check('slider r: no pipeline created', p1 === p0, `${p0} → ${p1}`);
    await matchesCli(page, 'torus-r');
    await frameTime(page, 'torus-shadows', 256);
    await page.evaluate(() => { __view.U.width = __view.U.height = 128; });
    // The formula editor: another surface.
    const programs = await page.evaluate(() => __view.programs);
    await page.fill('#formula', 'x^2 + 2*y^2 + z^2 - 1');
    await page.click('#compile');
    await page.waitForFunction((n) => __view.programs > n || __view.diagnostic, programs, { timeout: 100000 });
    const edited = await capture(page);
    check('formula edit: the picture changes', differs(moved, edited) && !(await page.evaluate(() => __view.diagnostic)));
    await matchesCli(page, 'formula-edit');
    // A bad formula: the CLI's diagnostic, the last picture kept.
    await page.fill('#formula', 'x^2 + (');
    await page.click('#compile');
    await page.waitForFunction(() => __view.diagnostic, null, { timeout: 60000 });
    const shown = await page.textContent('#diagnostic');
    const cli = spawnSync(BIN, ['check', 'x^2 + ('], { encoding: 'utf8' }).stderr;
    check('bad formula: the page shows the CLI diagnostic with its caret', shown.trim() === cli.trim() && shown.includes('^'), JSON.stringify(shown.split('\n').slice(0, 4)));
    const kept = await capture(page);
    check('bad formula: the last picture is kept', same(edited, kept));
    await page.screenshot({ path: path.join(ART, 'bad-formula.png') });
    await page.close();
  } finally { proc.kill(); }
}

async function sceneCase(browser) {
  const { url, proc } = await startServer('examples/blobs.scene.json');
  try {
    const page = await openPage(browser, url, 'scene');
    const before = await matchesCli(page, 'scene-blobs');
    const p0 = await pipelines(page);
    await page.evaluate(() => {
      const c = __view.gui().controllersRecursive().find((c) => c._name === 'radius');
      c.setValue(c.getValue() * 1.4);
      c._callOnFinishChange();
    });
    await page.waitForFunction(() => __view.sceneMs !== undefined, null, { timeout: 60000 });
    await page.waitForTimeout(300);
    const after = await capture(page);
    const p1 = await pipelines(page);
    check('scene edit: the picture changes', differs(before, after), `layout ${(await page.evaluate(() => __view.sceneMs)).toFixed(2)} ms`);
    check('scene edit: no pipeline created', p1 === p0, `${p0} → ${p1}`);
    await page.screenshot({ path: path.join(ART, 'scene-edit.png') });
    // Selecting a node (opening its folder) traces it alone and tints it.
    await page.evaluate(() => __view.gui().foldersRecursive().find((f) => f._title.startsWith('0: ')).open());
    await page.waitForFunction(() => __view.selectionReady === 0 || __view.error, null, { timeout: 60000, polling: 250 });
    const selected = await capture(page);
    const p2 = await pipelines(page);
    check('scene selection: the primitive is highlighted', differs(after, selected));
    check('scene selection: no pipeline created', p2 === p0, `${p0} → ${p2}`);
    await page.screenshot({ path: path.join(ART, 'scene-selection.png') });
    await frameTime(page, 'scene-blobs', 128);
    await page.close();
  } finally { proc.kill(); }
}

// A scene bisected on its interval enclosures: the page's kernel with the
// scene's interval interpreter, compiled by Chromium's WGSL compiler, draws
// what lavapipe draws.
async function sceneBisectCase(browser) {
  const { url, proc } = await startServer('examples/blobs.scene.json');
  try {
    const page = await openPage(browser, url, 'scene-bisect');
    await page.evaluate(async () => { __view.U.method = 'bisect'; await __view.recompile(); });
    check('scene bisect: the page compiles the bisection kernel', !(await page.evaluate(() => __view.error)) && (await cliArgs(page)).includes('bisect'));
    await matchesCli(page, 'scene-blobs-bisect');
    await page.close();
  } finally { proc.kill(); }
}

// Formula leaves: the page's kernel runs the tape interpreter inside the
// scene interpreter (Chromium's WGSL compile of both), bisects by default (a
// leaf without a Lipschitz bound) and draws what isotrace render draws.
async function sceneLeavesCase(browser) {
  const { url, proc } = await startServer('examples/knoll-leaves.scene.json');
  try {
    const page = await openPage(browser, url, 'scene-leaves');
    check('scene leaves: the page starts bisecting', !(await page.evaluate(() => __view.error)) && (await page.evaluate(() => __view.U.method)) === 'bisect');
    await matchesCli(page, 'scene-knoll-leaves');
    await page.close();
  } finally { proc.kill(); }
}

// The procedural nodes (twists, a bend, chamfer and round joins, density
// fields summed): the page's kernel with those features, compiled by
// Chromium's WGSL compiler, draws what lavapipe draws.
async function proceduralCase(browser) {
  const { url, proc } = await startServer('examples/procedural.scene.json');
  try {
    const page = await openPage(browser, url, 'procedural');
    const before = await matchesCli(page, 'scene-procedural');
    // A warp's rate (a field one level down, `warp.rate`) is edited like any
    // number: the scene is laid out again, no pipeline is created.
    const p0 = await pipelines(page);
    await page.evaluate(() => {
      const c = __view.gui().controllersRecursive().find((c) => c._name === 'warp.rate');
      c.setValue(c.getValue() * 2.0);
      c._callOnFinishChange();
    });
    await page.waitForFunction(() => __view.sceneMs !== undefined, null, { timeout: 60000 });
    await page.waitForTimeout(300);
    const after = await capture(page);
    check('procedural: editing warp.rate changes the picture', differs(before, after));
    check('procedural: no pipeline created', (await pipelines(page)) === p0);
    await page.close();
  } finally { proc.kill(); }
}

// A sum of 40 same-shaped terms: its compiled kernel is a loop over a table
// of the terms' constants (src/codegen/reroll/), a texture in the field
// group that the page binds like a tape's.
async function rerollCase(browser) {
  const { url, proc } = await startServer('tests/browser/sum-reroll.iso');
  try {
    const page = await openPage(browser, url, 'reroll');
    const wgsl = execFileSync(BIN, ['wgsl', 'tests/browser/sum-reroll.iso']).toString();
    check('reroll: the kernel reads a table', wgsl.includes('field_table('));
    await matchesCli(page, 'reroll-sum');
    await page.close();
  } finally { proc.kill(); }
}

// A union bisected as a tape: the page runs the block pass, the tile pass
// and the per-pixel pass over the per-tile lists (fields/tape_tiles.wgsl).
async function tapeCase(browser) {
  const { url, proc } = await startServer('tests/browser/csg-tape.iso');
  try {
    const page = await openPage(browser, url, 'tape');
    const wgsl = execFileSync(BIN, ['wgsl', 'tests/browser/csg-tape.iso', '--field', 'tape']).toString();
    check('tape: the kernel shortens the tape per block', wgsl.includes('fn tape_blocks_x('));
    await matchesCli(page, 'tape-csg');
    await page.close();
  } finally { proc.kill(); }
}

// A scene edit that grows the solid (node 0's half width 1.7 → 2.72): the
// page frames the edited scene as `render` frames the edited file (nothing
// cut off by the old box), and draws a coarse frame before the full one, as
// when the camera moves.
async function growCase(browser) {
  const { url, proc } = await startServer('examples/procedural.scene.json');
  try {
    const page = await openPage(browser, url, 'grow');
    const box0 = await page.evaluate(() => __view.U.box.slice());
    const edits = await page.evaluate(() => { __view.frameLog = []; return __view.edits; });
    await page.evaluate(() => {
      const c = __view.gui().foldersRecursive().find((f) => f._title === '0: box').controllers.find((c) => c._name === 'half[0]');
      c.setValue(2.72);
      c._callOnFinishChange();
    });
    await page.waitForFunction((n) => __view.edits > n || __view.diagnostic, edits, { timeout: 120000 });
    const log = await page.evaluate(() => __view.frameLog.slice());
    check('scene edit: a coarse frame is drawn before the full one', log.length === 2 && log[0] === 'coarse' && log[1] === 'full', JSON.stringify(log));
    const box1 = await page.evaluate(() => __view.U.box.slice());
    check('grown scene: the box holds the grown solid', box1[0] < -2.72 && box1[1] > 2.72, `x ${box0[0].toFixed(2)},${box0[1].toFixed(2)} → ${box1[0].toFixed(2)},${box1[1].toFixed(2)}`);
    const file = path.join(ART, 'procedural-grown.scene.json');
    fs.writeFileSync(file, JSON.stringify(await page.evaluate(() => __view.state().scene)));
    const c = compare(await capture(page), cliRender([file, '--size', String(SIZE)], 'grow'));
    check('grown scene: pixels match isotrace render of the edited scene file', c.ok, c.detail);
    figures.grow = c.detail;
    await page.screenshot({ path: path.join(ART, 'grow.png') });
    await page.close();
  } finally { proc.kill(); }
}

// The CLI's warning of a formula that is not a distance bound, sphere
// traced: the page shows the same text (its numbers from its own frame),
// and the Lipschitz bound it advises, given in the page, ends it.
async function lipschitzCase(browser) {
  const formula = 'x^2+y^2-z^2-0.1';
  const { url, proc } = await startServer(formula);
  try {
    const page = await openPage(browser, url, 'lipschitz');
    await page.evaluate(async () => { __view.U.method = 'sphere'; await __view.recompile(); });
    const shown = (await page.textContent('#warning')).trim();
    const file = path.join(ART, 'lipschitz-cli.png');
    const cli = spawnSync(BIN, ['render', ...(await cliArgs(page)), '-o', file, '--force'], { encoding: 'utf8' }).stderr.split('\n').find((l) => l.includes('changed faster')) || '';
    // Pixel counts and rates from two float implementations: the same
    // text, the counts within 5 %, the rates within 0.02.
    const nums = (t) => (t.match(/\d+(\.\d+)?/g) || []).map(Number);
    const [a, b] = [nums(shown), nums(cli)];
    const close = a.length === b.length && a.length > 2 && Math.abs(a[0] - b[0]) <= 0.05 * b[0] && a.slice(2).every((x, i) => Math.abs(x - b[i + 2]) <= 0.02);
    check('lipschitz: the page shows the CLI warning', !!cli && shown.replace(/\d+(\.\d+)?/g, '#') === cli.replace(/\d+(\.\d+)?/g, '#') && close, `page: ${shown.slice(0, 60)}…  numbers ${a} vs CLI ${b}`);
    const before = await capture(page);
    const frames = await page.evaluate(() => __view.frames);
    await page.click('#lipschitz-fix');
    await page.waitForFunction((n) => __view.frames > n + 1 && __view.lastFrame.full, frames, { timeout: 60000 });
    const args = await cliArgs(page);
    const i = args.indexOf('--lipschitz');
    check('lipschitz: the advised bound is in the CLI line', i > 0 && Math.abs(Number(args[i + 1]) - b[2]) <= 0.02, args.slice(i, i + 2).join(' '));
    check('lipschitz: the warning is gone', (await page.textContent('#warning')).trim() === '' && await page.isHidden('#lipschitz-fix'));
    const fixed = await matchesCli(page, 'lipschitz-fixed');
    check('lipschitz: the picture changes', differs(before, fixed));
    await page.close();
  } finally { proc.kill(); }
}

// A formula typed in the editor with a name nothing gives a value: it gets
// 1 and a slider, as `--param r=1` in the CLI line.
async function newParamCase(browser) {
  const { url, proc } = await startServer('@sphere');
  try {
    const page = await openPage(browser, url, 'new-param');
    const programs = await page.evaluate(() => __view.programs);
    await page.fill('#formula', 'x^2+y^2+z^2-r^2');
    await page.click('#compile');
    await page.waitForFunction((n) => __view.programs > n || __view.diagnostic, programs, { timeout: 100000 });
    const state = await page.evaluate(() => ({ diagnostic: __view.diagnostic, names: __view.newParams, note: document.getElementById('params-note').textContent }));
    check('new parameter: compiled with r = 1, and the page says so', !state.diagnostic && JSON.stringify(state.names) === '["r"]' && state.note.startsWith('new parameter r = 1'), state.diagnostic || state.note);
    const args = await cliArgs(page);
    check('new parameter: the CLI line gives --param r=1', args.join(' ').includes('--param r=1'), args.join(' '));
    const one = await matchesCli(page, 'new-param');
    await page.evaluate(() => __view.gui().controllersRecursive().find((c) => c._name === 'r').setValue(0.6));
    const moved = await matchesCli(page, 'new-param-r');
    check('new parameter: its slider changes the picture', differs(one, moved) && (await cliArgs(page)).includes('r=0.6'));
    await page.close();
  } finally { proc.kill(); }
}

async function exportCase(browser) {
  const file = path.join(ART, 'export-sphere.html');
  execFileSync(BIN, ['view', '@sphere', '--export', file], { stdio: ['ignore', 'ignore', 'inherit'] });
  const html = fs.readFileSync(file);
  const server = http.createServer((req, res) => { res.writeHead(200, { 'Content-Type': 'text/html' }); res.end(html); });
  await new Promise((r) => server.listen(0, '127.0.0.1', r));
  try {
    const page = await openPage(browser, `http://127.0.0.1:${server.address().port}/`, 'export');
    const note = await page.textContent('#note');
    check('export: the page says what needs the server', note.includes('need the server'));
    await matchesCli(page, 'export-sphere');
  } finally { server.close(); }
}

(async () => {
  const t0 = Date.now();
  const browser = await chromium.launch({ executablePath: CHROMIUM, args: FLAGS });
  try {
    // CASES=scene,export runs only those (for debugging).
    const only = (process.env.CASES || '').split(',').filter(Boolean);
    for (const c of [sphereCase, torusCase, sceneCase, sceneBisectCase, sceneLeavesCase, proceduralCase, growCase, lipschitzCase, newParamCase, rerollCase, tapeCase, exportCase].filter((c) => !only.length || only.some((o) => c.name.startsWith(o)))) {
      try { await c(browser); } catch (e) { check(c.name, false, e.stack || String(e)); }
    }
  } finally { await browser.close(); }
  figures.seconds = Math.round((Date.now() - t0) / 1000);
  fs.writeFileSync(path.join(ART, 'figures.json'), JSON.stringify({ tolerance: TOLERANCE, size: SIZE, figures, results }, null, 1));
  const failed = results.filter((r) => !r.ok);
  console.log(`browser tests: ${results.length - failed.length} passed, ${failed.length} failed, ${figures.seconds} s`);
  process.exit(failed.length ? 1 : 0);
})();
