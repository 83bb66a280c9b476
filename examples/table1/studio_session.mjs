// Drives a design session in the studio page (headless Chromium, playwright-core from apps/studio/web/node_modules,
// as tests/browser/studio.test.mjs does) and logs every step: the operation, the time since the session started,
// the raw mesh shown by the page after it, and for "finish" the final mesh of the page's Finish button (the default
// pipeline, run by the studio's job).
//
//   node examples/table1/studio_session.mjs SESSION.json
//
// SESSION.json: {"skeleton": "..." (or "": start empty), "surface": "...", "save": "...", "log": "...jsonl", "screenshot": "...png",
//                "steps": [STEP, ...]}
// STEP is one page operation (what a user does with the mouse and keys):
//   {"op": "select", "vertices": [..]}            select vertices (the page's selection, as clicks would)
//   {"op": "select_where", "js": "(p, i, s) => bool"} select the vertices for which the predicate holds
//   {"op": "select_by", "js": "(s) => [vertex, ...]"} select the vertices the function names (in that order)
//   {"op": "key", "key": "s"}                     a shortcut (n add, e extrude: a vertex, an edge or a chain of 3+
//                                                 vertices, s split, f fill, c connect, m merge, Delete);
//                                                 "nowait": true goes on without waiting for the raw mesh
//   {"op": "pos", "axis": "x", "value": 1.5}      type a coordinate of the selection's centre (then Enter); with
//                                                 "snap to medial" on, waits for the snap too; "by": d
//                                                 instead of "value" types the shown value + d (a nudge)
//   {"op": "move_each", "js": "(p, i, s) => [x, y, z] or null"} for each vertex the function maps to a new place:
//                                                 select it and type its new coordinates (one move per vertex)
//   {"op": "auto"}                                the "curve skeleton from the domain" button (auto's first guess)
//   {"op": "radius", "value": 0.3}                the radius field + "set" for the selection
//   {"op": "radius_each", "js": "(p, i, s) => r or null"} for each vertex the function gives a radius: select it,
//                                                 type the radius, "set" (one edit per vertex)
//   {"op": "radius_from_domain"}                  the "radius from the domain" button
//   {"op": "brush", "factor": "1.15"|"0.87", "strokes": [[vertex, ...], ...]} radius brush strokes over vertices
//   {"op": "mirror", "axis": ""|"0"|"1"|"2"}      the mirror selector; {"op": "snap", "on": true} snap to medial
//   {"op": "undo", "times": n} / {"op": "redo"}   Ctrl+Z (n times, default 1) / Ctrl+Shift+Z
//   {"op": "finish"}                              the Finish button; waits for the final mesh
//   {"op": "save"}                                the save button (writes the --save target)
//   {"op": "screenshot"}                          a PNG of the page
//   {"op": "dump", "path": "x.json"}              write the page's skeleton (JSON) to a file, to read it (no edit)
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const root = path.resolve(here, '../..');
const { chromium } = await import(path.join(root, 'apps/studio/web/node_modules/playwright-core/index.mjs'));
const cli = process.env.MESOHEX_CLI || path.join(root, 'build/bin/mesohex');
const session = JSON.parse(fs.readFileSync(process.argv[2], 'utf8'));
const CHROMIUM_ARGS = ['--headless', '--no-sandbox', '--disable-gpu', '--use-gl=angle', '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader', '--disable-background-networking', '--disable-component-update', '--no-first-run'];

function startServer() {
  // No skeleton: the page opens empty (then e.g. the "auto" step: the curve skeleton from the domain).
  const args = ['studio', ...(session.skeleton ? [session.skeleton] : []), '--surface', session.surface, '--port', '0',
    '--save', session.save];
  const proc = spawn(cli, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  const url = new Promise((resolve, reject) => {
    let out = '';
    proc.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/mesohex studio: (http:\/\/\S+)/);
      if (m) resolve(m[1]);
    });
    proc.on('exit', (code) => reject(new Error(`studio exited (${code})`)));
  });
  return { proc, url };
}

const t0 = Date.now();
const logFile = session.log;
function log(entry) {
  const line = JSON.stringify({ t: +((Date.now() - t0) / 1000).toFixed(1), ...entry });
  console.log(line);
  if (logFile) fs.appendFileSync(logFile, line + '\n');
}

async function settled(page) {
  await page.waitForFunction(() => {
    const s = window.studio.state;
    const st = document.getElementById('status').dataset.state;
    if (!window.studio.skeleton().points.length) return true; // empty: nothing to mesh
    // A rejected skeleton (e.g. one vertex, no edge yet) answers 'error' and leaves the last valid mesh shown.
    return (s.meshedVersion === s.version && st === 'ok') || st === 'error';
  }, null, { timeout: 120000 });
  return page.evaluate(() => {
    const s = window.studio.skeleton();
    const m = window.studio.state.meshes.raw?.mesh;
    let min = 2, sum = 0, inv = 0;
    for (const q of m?.sj || []) { min = Math.min(min, q); sum += q; if (q <= 0) inv++; }
    return {
      V: s.points.length, E: s.edges.length, F: s.faces.length,
      status: document.getElementById('status').textContent,
      raw: m ? { hexes: window.studio.hexCount(), sj_min: +min.toFixed(3), sj_avg: +(sum / m.sj.length).toFixed(3), inverted: inv } : null,
    };
  });
}

async function typeInto(page, id, value) {
  await page.fill(`#${id}`, String(value));
  await page.press(`#${id}`, 'Enter');
}

async function step(page, s) {
  switch (s.op) {
    case 'select': await page.evaluate((vs) => window.studio.select(vs), s.vertices); return null;
    case 'select_where':
      await page.evaluate((js) => {
        const f = eval(js); // the session file's own predicate
        const sk = window.studio.skeleton();
        window.studio.select(sk.points.map((p, i) => (f(p, i, sk) ? i : -1)).filter((i) => i >= 0));
      }, s.js);
      return { selected: await page.evaluate(() => window.studio.state.selV.length) };
    case 'select_by':
      await page.evaluate((js) => window.studio.select(eval(js)(window.studio.skeleton())), s.js);
      return { selected: await page.evaluate(() => window.studio.state.selV) };
    case 'key':
      await page.mouse.move(5, 5);
      await page.keyboard.press(s.key);
      if (s.nowait) return page.evaluate(() => ({ V: window.studio.skeleton().points.length }));
      break;
    case 'pos': {
      const v = await page.evaluate(() => window.studio.state.version);
      const snap = await page.evaluate(() => document.getElementById('snap').checked);
      const cur = parseFloat(await page.inputValue(`#pos-${s.axis}`));
      if (s.by !== undefined) s.value = +(cur + s.by).toPrecision(8);
      if (cur === +s.value) break; // already there: nothing to type (the page would make no edit)
      await typeInto(page, `pos-${s.axis}`, s.value);
      // A move is one step, its snap to the medial position a second one.
      await page.waitForFunction(([n, k]) => window.studio.state.version >= n + k, [v, snap ? 2 : 1], { timeout: 120000 });
      break;
    }
    case 'auto': {
      const v = await page.evaluate(() => window.studio.state.version);
      await page.click('#btn-auto');
      await page.waitForFunction((n) => window.studio.state.version > n, v, { timeout: 300000 });
      break;
    }
    case 'move_each': {
      const targets = await page.evaluate((js) => {
        const f = eval(js);
        const sk = window.studio.skeleton();
        return sk.points.map((p, i) => [i, f(p, i, sk)]).filter(([, q]) => q);
      }, s.js);
      for (const [v, q] of targets) {
        await page.evaluate((i) => window.studio.select([i]), v);
        for (const [d, k] of ['x', 'y', 'z'].entries()) {
          const cur = await page.evaluate(([i, dd]) => window.studio.skeleton().points[i][dd], [v, d]);
          // No wait between the typed coordinates: the page coalesces the edits into one raw-mesh request.
          if (Math.abs(cur - q[d]) > 1e-9) await typeInto(page, `pos-${k}`, q[d]);
        }
      }
      return { moved: targets.length, ...(await settled(page)) };
    }
    case 'radius': await page.fill('#radius', String(s.value)); await page.click('#btn-radius'); break;
    case 'radius_each': {
      const targets = await page.evaluate((js) => {
        const f = eval(js);
        const sk = window.studio.skeleton();
        return sk.points.map((p, i) => [i, f(p, i, sk)]).filter(([, r]) => r);
      }, s.js);
      for (const [v, r] of targets) {
        await page.evaluate((i) => window.studio.select([i]), v);
        await page.fill('#radius', String(+r.toPrecision(6)));
        await page.click('#btn-radius');
      }
      return { set: targets.length, ...(await settled(page)) };
    }
    case 'radius_from_domain': {
      const v = await page.evaluate(() => window.studio.state.version);
      await page.click('#btn-radius-domain');
      await page.waitForFunction((n) => window.studio.state.version > n, v, { timeout: 120000 });
      break;
    }
    case 'brush': {
      await page.selectOption('#brush-dir', s.factor);
      await page.check('#brush');
      for (const stroke of s.strokes) {
        const pts = [];
        for (const v of stroke) pts.push(await page.evaluate((i) => window.studio.screenPosition(i), v));
        await page.mouse.move(pts[0].x, pts[0].y);
        await page.mouse.down();
        for (const p of pts) await page.mouse.move(p.x, p.y, { steps: 2 });
        await page.mouse.up();
        await settled(page);
      }
      await page.uncheck('#brush');
      break;
    }
    case 'mirror': await page.selectOption('#mirror', s.axis); return null;
    case 'snap': if (s.on) await page.check('#snap'); else await page.uncheck('#snap'); return null;
    case 'undo':
      await page.mouse.move(5, 5);
      for (let k = 0; k < (s.times || 1); k++) await page.keyboard.press('Control+z');
      break;
    case 'redo': await page.mouse.move(5, 5); await page.keyboard.press('Control+Shift+z'); break;
    case 'finish': {
      await settled(page);
      await page.click('#btn-finish');
      await page.waitForFunction(() => window.studio.state.meshes.final || /failed|cancelled|:/.test(document.getElementById('jobinfo').textContent.replace(/^job \d+:/, '')),
        null, { timeout: 600000 });
      return page.evaluate(() => {
        const r = window.studio.state.meshes.final?.report;
        if (!r) return { error: document.getElementById('jobinfo').textContent };
        return { final: { hexes: r.quality.hexes, sj_min: +r.quality.sj_min.toFixed(3), sj_avg: +r.quality.sj_avg.toFixed(3),
          inverted: r.quality.inverted, hausdorff_pct: +(100 * r.hausdorff.relative_max).toFixed(2) } };
      });
    }
    case 'save':
      await page.click('#btn-save');
      await page.waitForFunction(() => /saved to/.test(document.getElementById('toast').textContent), null, { timeout: 10000 });
      return { saved: session.save };
    case 'screenshot':
      await page.evaluate(() => window.studio.renderNow());
      await page.screenshot({ path: s.path || session.screenshot });
      return { screenshot: s.path || session.screenshot };
    case 'dump':
      fs.writeFileSync(s.path, JSON.stringify(await page.evaluate(() => window.studio.skeleton())));
      return { dumped: s.path };
    default: throw new Error(`unknown step ${s.op}`);
  }
  return settled(page);
}

const server = startServer();
let browser = null;
try {
  const url = await server.url;
  browser = await chromium.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium', args: CHROMIUM_ARGS });
  const page = await browser.newPage({ viewport: { width: session.width || 1280, height: session.height || 760 } });
  page.on('pageerror', (e) => log({ pageerror: e.message }));
  await page.goto(url);
  await page.waitForFunction(() => window.studio?.state?.ready, null, { timeout: 60000 });
  for (const [k, v] of Object.entries(session.view || {})) {
    if (typeof v === 'boolean') await page.setChecked(`#${k}`, v);
    else await page.selectOption(`#${k}`, v);
  }
  log({ op: 'open', skeleton: session.skeleton, ...(await settled(page)) });
  for (const s of session.steps) {
    const r = await step(page, s);
    log({ ...s, ...(r || {}) });
  }
} finally {
  if (browser) await browser.close();
  server.proc.kill('SIGTERM');
}
