// Studio latency in the browser: edit -> updated raw mesh on screen, for a 10 k-hex raw mesh (issue 15's target:
// <= 50 ms). Not a test (timings are not pass/fail): run it by hand,
//
//   node bench/studio_page_latency.mjs [--cli build/bin/mesohex] [--edits 30] [--gap 500] [--web-dir DIR]
//                                      [--skeleton FILE] [--vertex N]
//
// Starts `mesohex studio torus.obj --port 0` on the generated torus 128 x 40 (10 240 raw hexes), opens the page in
// Debian's headless Chromium (playwright-core from apps/studio/web/node_modules, WebGL through SwiftShader), waits for
// the first mesh, then makes `edits` edits, each moving one skeleton vertex along x with the position field (as a
// user typing a coordinate; the sign alternates, so the hex count stays). Each edit is timed inside the page, from
// the field's change event to the frame drawn after the status says the mesh is up to date (so it works with any
// version of the page): request, server, transfer, decoding, geometry and the draw call. Prints the median, mean,
// min and max, the page's own split where it gives one (server_ms of the answer), and the load average.
// --uncheck v-skeleton,v-wire,... turns view checkboxes off first (to see what drawing costs).
// --verbose prints each edit: edit -> drawn, and when the answer was drawn (the render call's end, after the edit).
// --web-dir serves another copy of the page (e.g. an older one, for before / after figures).
// --skeleton FILE opens that skeleton instead of the torus (e.g. a tree: build/bench/mesohex_write_tree 2600 5 tree.obj,
// then --vertex 1305, one of its branching points); --vertex N moves vertex N
// (default 0).
import { spawn, execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const root = path.resolve(here, '..');
const arg = (name, fallback) => {
  const i = process.argv.indexOf(name);
  return i >= 0 ? process.argv[i + 1] : fallback;
};
const cli = path.resolve(arg('--cli', path.join(root, 'build/bin/mesohex')));
const edits = Number(arg('--edits', '30'));
const gap = Number(arg('--gap', '500')); // ms of quiet before each edit: a user edits a settled page
const webDir = arg('--web-dir', null);
const uncheck = (arg('--uncheck', '') || '').split(',').filter(Boolean);  // view checkboxes to turn off first
const { chromium } = await import(path.join(root, 'apps/studio/web/node_modules/playwright-core/index.mjs'));

const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'mesohex-studio-latency-'));
const skeletonArg = arg('--skeleton', null);
const torus = skeletonArg ? path.resolve(skeletonArg) : path.join(tmp, 'torus.obj');
if (!skeletonArg) execFileSync(cli, ['generate', 'torus', '-n', '128', '-m', '40', '-o', torus]);
const movedVertex = Number(arg('--vertex', '0'));

const args = ['studio', torus, '--port', '0'];
if (webDir) args.push('--web-dir', path.resolve(webDir));
const proc = spawn(cli, args, { stdio: ['ignore', 'pipe', 'inherit'] });
const url = await new Promise((resolve, reject) => {
  let out = '';
  proc.stdout.on('data', (d) => {
    out += d;
    const m = out.match(/mesohex studio: (http:\/\/\S+)/);
    if (m) resolve(m[1]);
  });
  proc.on('exit', (code) => reject(new Error(`server exited (${code})`)));
});

const CHROMIUM_ARGS = ['--headless', '--no-sandbox', '--disable-gpu', '--use-gl=angle', '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader', '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--no-first-run', '--disable-quic'];
const browser = await chromium.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium', args: CHROMIUM_ARGS });
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 760 } });
  await page.goto(url);
  await page.waitForFunction(() => window.studio?.state?.ready, null, { timeout: 60000 });
  const settled = () => page.waitForFunction(() => {
    const s = window.studio.state;
    return s.meshedVersion === s.version && document.getElementById('status').dataset.state === 'ok';
  }, null, { timeout: 60000 });
  await settled();
  for (const id of uncheck) await page.uncheck(`#${id}`);
  const hexes = await page.evaluate(() => window.studio.hexCount());
  const v = movedVertex;
  // Select vertex 0 (by its screen position: the test hook `select` may not exist in an older page).
  await page.evaluate(() => window.studio.frameAll());
  const p = await page.evaluate((i) => window.studio.screenPosition(i), v);
  await page.evaluate((i) => window.studio.select?.([i]), v);
  if (!(await page.evaluate(() => window.studio.state.selV.length === 1))) await page.mouse.click(p.x, p.y);
  const sel = await page.evaluate(() => window.studio.state.selV);
  if (sel.length !== 1) throw new Error(`could not select one vertex (${sel})`);
  const x0 = await page.evaluate((i) => window.studio.skeleton().points[i][0], sel[0]);

  const times = [], servers = [], phases = [];
  for (let k = 0; k < edits; k++) {
    await page.waitForTimeout(gap);
    const x = x0 + (k % 2 === 0 ? 0.02 : 0);
    const r = await page.evaluate((xv) => new Promise((resolve) => {
      const st = window.studio.state;
      const field = document.getElementById('pos-x');
      field.value = String(xv);
      const t0 = performance.now();
      field.dispatchEvent(new Event('change'));
      const version = st.version;
      const poll = () => {
        if (st.meshedVersion >= version && document.getElementById('status').dataset.state === 'ok')
          requestAnimationFrame(() => resolve({ ms: performance.now() - t0, server: st.meshes.raw?.server_ms,
            phases: st.lastPhasesMs }));
        else setTimeout(poll, 0);
      };
      poll();
    }), x);
    times.push(r.ms);
    if (process.argv.includes('--verbose') && r.phases) {
      const p = r.phases, drawn = p.queued + p.roundTrip + p.skeleton + p.mesh + p.render;
      console.log(`edit ${k}: drawn ${r.ms.toFixed(1)} ms; render call ended at ${drawn.toFixed(1)} ms (round trip ${p.roundTrip.toFixed(1)}, server ${r.server?.toFixed(1)})`);
    }
    if (r.server !== undefined) servers.push(r.server);
    if (r.phases) phases.push(r.phases);
    const h = await page.evaluate(() => window.studio.hexCount());
    // The torus keeps its hexes; a tree may re-sample a branch when a branching point moves (a few hexes more or less).
    if (h !== hexes && !skeletonArg) throw new Error(`hex count changed: ${hexes} -> ${h}`);
  }
  const uploads = await page.evaluate(() => window.studio.meshUploads?.() ?? null);
  const stats = (a) => {
    const s = a.slice().sort((x, y) => x - y);
    return { median: s[Math.floor(s.length / 2)], mean: s.reduce((u, w) => u + w, 0) / s.length, min: s[0], max: s[s.length - 1] };
  };
  const f = (o) => Object.entries(o).map(([k, x]) => `${k} ${x.toFixed(1)}`).join(', ');
  console.log(`raw hexes: ${hexes}; edits: ${edits}; load average: ${os.loadavg().map((x) => x.toFixed(2)).join(' ')}`);
  console.log(`edit -> mesh drawn (ms): ${f(stats(times))}`);
  if (servers.length) console.log(`server_ms: ${f(stats(servers))}`);
  if (uploads) console.log(`uploads: ${uploads.deltas} deltas, ${uploads.full} whole skeletons; ${uploads.patches ?? 0} patch answers`);
  if (phases.length)
    for (const k of Object.keys(phases[0])) {
      const values = phases.map((x) => x[k]).filter((x) => typeof x === 'number' && Number.isFinite(x));
      if (values.length) console.log(`page ${k}${k === 'answerKB' ? '' : ' (ms)'}: ${f(stats(values))}`);
    }
} finally {
  await browser.close();
  proc.kill('SIGTERM');
  fs.rmSync(tmp, { recursive: true, force: true });
}
