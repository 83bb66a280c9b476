// End-to-end test of the studio page in headless Chromium (Debian's /usr/bin/chromium, WebGL through SwiftShader),
// driven by playwright-core from apps/studio/web/node_modules (no browser download).
//
// Starts `mesohex studio data/tiny/tripod.obj --port 0`, reads the URL from its stdout, loads the page, checks the
// canvas is not blank, loads a skeleton through the file input, extrudes a vertex, moves it, undoes both, and checks
// each time that the raw mesh was updated and the hex count shown matches the mesh received; then checks the mesh
// drawn (binary answer) against the JSON API, peels, and makes keyboard edits (connect, split, merge, delete)
// and a chain extrusion, with exact V / E / F, each undone to the identical skeleton. Writes a screenshot.
//
// Environment (set by CTest, see tests/browser/CMakeLists.txt): MESOHEX_CLI = the mesohex binary,
// STUDIO_SCREENSHOT = where to write the screenshot (default: a temporary directory), CHROMIUM (default
// /usr/bin/chromium).
import test from 'node:test';
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const root = path.resolve(here, '../..');
const { chromium } = await import(path.join(root, 'apps/studio/web/node_modules/playwright-core/index.mjs'));

const cli = process.env.MESOHEX_CLI || path.join(root, 'build/bin/mesohex');
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'mesohex-studio-test-'));
const screenshot = process.env.STUDIO_SCREENSHOT || path.join(tmp, 'studio.png');

const CHROMIUM_ARGS = ['--headless', '--no-sandbox', '--disable-gpu', '--use-gl=angle', '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader', '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--no-first-run', '--disable-quic'];

// An L-shaped branch with radii: 0 (0,0,0) - 1 (0,0,1) - 2 (0,0,2) - 3 (1,0,2) - 4 (2,0,2). 5 V, 4 E.
const L_OBJ = `# L-shaped branch
v 0 0 0
v 0 0 1
v 0 0 2
v 1 0 2
v 2 0 2
# mesohex radius 1 0.3
# mesohex radius 2 0.3
# mesohex radius 3 0.3
# mesohex radius 4 0.3
# mesohex radius 5 0.3
l 1 2 3 4 5
`;

// OBJ text of a skeleton as the page writes it (vertices, radius comments, edges, faces; 1-based).
function toObj(s) {
  const out = s.points.map((p) => `v ${p.join(' ')}`);
  s.radii.forEach((r, i) => out.push(`# mesohex radius ${i + 1} ${r}`));
  s.edges.forEach((e) => out.push(`l ${e[0] + 1} ${e[1] + 1}`));
  s.faces.forEach((f) => out.push(`f ${f.map((v) => v + 1).join(' ')}`));
  return out.join('\n') + '\n';
}

function startServer() {
  const proc = spawn(cli, ['studio', path.join(root, 'data/tiny/tripod.obj'), '--port', '0'],
    { stdio: ['ignore', 'pipe', 'pipe'] });
  let err = '';
  proc.stderr.on('data', (d) => { err += d; });
  const url = new Promise((resolve, reject) => {
    let out = '';
    const timer = setTimeout(() => reject(new Error(`no URL from the server in 15 s; stderr: ${err}`)), 15000);
    proc.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/mesohex studio: (http:\/\/\S+)/);
      if (m) { clearTimeout(timer); resolve(m[1]); }
    });
    proc.on('exit', (code) => { clearTimeout(timer); reject(new Error(`server exited (${code}): ${err}`)); });
  });
  return { proc, url };
}

// Waits until the raw mesh shown is the one of the current skeleton (no pending or failed request).
async function meshSettled(page) {
  await page.waitForFunction(() => {
    const s = window.studio.state;
    return s.meshedVersion === s.version && document.getElementById('status').dataset.state === 'ok';
  }, null, { timeout: 15000 });
  return page.evaluate(() => ({
    shown: document.getElementById('hexcount').textContent,
    hexes: window.studio.hexCount(),
    predicted: window.studio.state.analysis?.predicted?.hexes,
    requests: window.studio.state.meshRequests,
    vertices: window.studio.state.meshes.raw.mesh.vertices.length / 3,
    maxX: Math.max(...window.studio.state.meshes.raw.mesh.vertices.filter((x, i) => i % 3 === 0)),
    skeleton: window.studio.skeleton(),
  }));
}

// Fraction of canvas pixels that differ from the background colour (#1d2026).
function nonBackgroundFraction(page) {
  return page.evaluate(async () => {
    window.studio.renderNow();
    const src = document.getElementById('canvas');
    const img = new Image();
    img.src = src.toDataURL('image/png');
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.width; c.height = img.height;
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    let other = 0;
    for (let i = 0; i < d.length; i += 4)
      if (Math.abs(d[i] - 0x1d) + Math.abs(d[i + 1] - 0x20) + Math.abs(d[i + 2] - 0x26) > 24) other++;
    return other / (d.length / 4);
  });
}

test('studio page: load, extrude, move, undo with a live raw mesh (headless Chromium)', { timeout: 110000 }, async (t) => {
  const t0 = Date.now();
  const phase = (name) => t.diagnostic(`${name}: ${((Date.now() - t0) / 1000).toFixed(1)} s`);
  assert.ok(fs.existsSync(cli), `mesohex binary not found at ${cli}`);
  const server = startServer();
  let browser = null;
  try {
    const url = await server.url;
    assert.match(url, /^http:\/\/127\.0\.0\.1:\d+\/$/);
    browser = await chromium.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium', args: CHROMIUM_ARGS });
    const page = await browser.newPage({ viewport: { width: 1280, height: 760 } });
    const pageErrors = [];
    page.on('pageerror', (e) => pageErrors.push(e.message));
    await page.goto(url);
    // The page loads three.js (1.3 MB) from the studio: allow for a loaded machine.
    await page.waitForFunction(() => window.studio?.state?.ready, null, { timeout: 35000 });
    phase('page ready');

    // WebGL through SwiftShader.
    const gl = await page.evaluate(() => {
      const c = document.createElement('canvas');
      const g = c.getContext('webgl2') || c.getContext('webgl');
      return g ? String(g.getParameter(g.VERSION)) : null;
    });
    assert.ok(gl && /WebGL/.test(gl), `no WebGL context: ${gl}`);

    // The session's skeleton (tripod: 17 vertices, 16 edges) and its raw mesh are on screen.
    const first = await meshSettled(page);
    phase('first raw mesh');
    assert.equal(first.skeleton.points.length, 17);
    assert.equal(first.skeleton.edges.length, 16);
    assert.ok(first.hexes > 0);
    assert.equal(Number(first.shown), first.hexes);
    assert.equal(first.predicted, first.hexes, 'the analysis predicts the raw hex count');
    const filled = await nonBackgroundFraction(page);
    assert.ok(filled > 0.02, `canvas is blank (${filled} of the pixels drawn)`);

    // Load another skeleton through the file input.
    const lpath = path.join(tmp, 'l_shape.obj');
    fs.writeFileSync(lpath, L_OBJ);
    await page.setInputFiles('#file', lpath);
    await page.waitForFunction(() => window.studio.skeleton().points.length === 5, null, { timeout: 10000 });
    const loaded = await meshSettled(page);
    phase('skeleton loaded and meshed');
    assert.deepEqual(loaded.skeleton.edges, [[0, 1], [1, 2], [2, 3], [3, 4]]);
    assert.deepEqual(loaded.skeleton.radii, [0.3, 0.3, 0.3, 0.3, 0.3]);
    assert.equal(Number(loaded.shown), loaded.hexes);
    assert.ok(loaded.hexes > 0);
    assert.ok(loaded.requests > first.requests);
    assert.ok(await page.evaluate(() => document.getElementById('counts').textContent.startsWith('5 vertices, 4 edges')));

    // Extrude vertex 4 (the end of the L, at x = 2): a new vertex one mean edge length further along +x.
    const p4 = await page.evaluate(() => window.studio.screenPosition(4));
    await page.mouse.click(p4.x, p4.y);
    assert.deepEqual(await page.evaluate(() => window.studio.state.selV), [4]);
    await page.keyboard.press('e');
    const extruded = await meshSettled(page);
    assert.equal(extruded.skeleton.points.length, 6);
    assert.deepEqual(extruded.skeleton.points[5], [3, 0, 2]);
    assert.deepEqual(extruded.skeleton.edges[4], [4, 5]);
    assert.ok(extruded.hexes > loaded.hexes, `extruding adds hexes (${loaded.hexes} -> ${extruded.hexes})`);
    assert.equal(Number(extruded.shown), extruded.hexes);
    assert.ok(extruded.maxX > loaded.maxX + 0.5, 'the mesh reaches the new branch');

    // Move the new vertex (selected after the extrusion) to x = 4 with the position field.
    assert.deepEqual(await page.evaluate(() => window.studio.state.selV), [5]);
    await page.fill('#pos-x', '4');
    await page.press('#pos-x', 'Enter');
    await page.waitForFunction(() => window.studio.skeleton().points[5]?.[0] === 4, null, { timeout: 5000 });
    const moved = await meshSettled(page);
    assert.deepEqual(moved.skeleton.points[5], [4, 0, 2]);
    assert.ok(moved.maxX > extruded.maxX + 0.5, `the mesh follows the move (${extruded.maxX} -> ${moved.maxX})`);
    assert.equal(Number(moved.shown), moved.hexes);

    // Frames: the page draws on demand, no animation loop (a software renderer pays for every frame): none while idle,
    // and a move draws its mesh in one frame (two when the answer comes after the redraw's wait for it, meshWaitMs).
    const idleFrames = await page.evaluate(async () => {
      const n0 = window.studio.state.framesDrawn;
      await new Promise((r) => setTimeout(r, 600));
      return window.studio.state.framesDrawn - n0;
    });
    assert.equal(idleFrames, 0, 'no frame drawn while idle');
    const framesBefore = await page.evaluate(() => window.studio.state.framesDrawn);
    await page.fill('#pos-x', '3.5');
    await page.press('#pos-x', 'Enter');
    await page.waitForFunction(() => window.studio.skeleton().points[5]?.[0] === 3.5, null, { timeout: 5000 });
    await meshSettled(page);
    await page.waitForTimeout(300);
    const editFrames = await page.evaluate(() => window.studio.state.framesDrawn) - framesBefore;
    assert.ok(editFrames >= 1 && editFrames <= 2, `frames drawn for one move: ${editFrames}`);
    await page.keyboard.press('Control+z');
    assert.deepEqual((await meshSettled(page)).skeleton, moved.skeleton);

    // Screenshot of the edited state (the docs' picture comes from here).
    await page.evaluate(() => window.studio.renderNow());
    fs.mkdirSync(path.dirname(screenshot), { recursive: true });
    await page.screenshot({ path: screenshot });
    assert.ok(fs.statSync(screenshot).size > 10000);

    // Undo the move, then the extrusion: the loaded skeleton and its mesh come back; redo re-applies the extrusion.
    await page.mouse.move(5, 5);
    await page.keyboard.press('Control+z');
    const undoMove = await meshSettled(page);
    assert.deepEqual(undoMove.skeleton, extruded.skeleton);
    assert.equal(undoMove.maxX, extruded.maxX);
    await page.keyboard.press('Control+z');
    const undoExtrude = await meshSettled(page);
    assert.deepEqual(undoExtrude.skeleton, loaded.skeleton);
    assert.equal(undoExtrude.hexes, loaded.hexes);
    assert.equal(Number(undoExtrude.shown), loaded.hexes);
    await page.keyboard.press('Control+Shift+z');
    const redo = await meshSettled(page);
    assert.deepEqual(redo.skeleton, extruded.skeleton);
    assert.equal(redo.hexes, extruded.hexes);

    // An invalid edit is shown on the element and the last valid mesh stays: moving vertex 5 onto vertex 4 makes
    // edge 4 (4-5) zero-length, which the analysis rejects (422, where = skeleton_edge 4).
    await page.evaluate(() => window.studio.frameAll()); // the whole skeleton in view (no domain: its bounds)
    const p5 = await page.evaluate(() => window.studio.screenPosition(5));
    await page.mouse.click(p5.x, p5.y);
    assert.deepEqual(await page.evaluate(() => window.studio.state.selV), [5]);
    await page.fill('#pos-x', '2');
    await page.press('#pos-x', 'Enter');
    await page.waitForFunction(() => document.getElementById('status').dataset.state === 'error', null, { timeout: 10000 });
    const rejected = await page.evaluate(() => ({
      label: document.getElementById('errorlabel').hidden ? null : document.getElementById('errorlabel').textContent,
      where: window.studio.state.error?.where,
      hexes: window.studio.hexCount(),
      shown: document.getElementById('hexcount').textContent,
      point: window.studio.skeleton().points[5],
    }));
    assert.deepEqual(rejected.point, [2, 0, 2]);
    assert.deepEqual(rejected.where, { kind: 'skeleton_edge', index: 4 });
    assert.match(rejected.label, /^edge 4: .*zero length/);
    assert.equal(rejected.hexes, redo.hexes, 'the last valid mesh stays on screen');
    assert.equal(Number(rejected.shown), redo.hexes);
    // Undo: valid again, the error is gone.
    await page.keyboard.press('Control+z');
    const back = await meshSettled(page);
    phase('done');
    assert.deepEqual(back.skeleton, redo.skeleton);
    assert.equal(await page.evaluate(() => document.getElementById('errorlabel').hidden), true);

    // The page draws from the binary answer (float32 / uint32): the same mesh as the JSON API gives for the same
    // skeleton (indices exact, coordinates and scaled Jacobians to float32 rounding).
    const shown = await page.evaluate(() => {
      const m = window.studio.state.meshes.raw.mesh;
      return { binary: m.vertices instanceof Float32Array && m.hexes instanceof Uint32Array,
        vertices: Array.from(m.vertices), hexes: Array.from(m.hexes), sj: Array.from(m.sj),
        boundary: Array.from(m.boundary_quads), owners: Array.from(m.boundary_hexes) };
    });
    assert.ok(shown.binary, 'the page asks for the binary answer');
    const json = await (await fetch(new URL('/api/mesh?stage=raw', url), { method: 'POST', body: toObj(back.skeleton) })).json();
    assert.deepEqual(shown.hexes, json.mesh.hexes);
    assert.deepEqual(shown.boundary, json.mesh.boundary_quads);
    assert.deepEqual(shown.owners, json.mesh.boundary_hexes);
    assert.equal(shown.vertices.length, json.mesh.vertices.length);
    shown.vertices.forEach((x, i) => assert.equal(x, Math.fround(json.mesh.vertices[i])));
    shown.sj.forEach((x, i) => assert.equal(x, Math.fround(json.mesh.sj[i])));

    // The moves and their undo went up as deltas (MHSD) and came back as patch answers: the mesh compared just now
    // was built that way (docs/studio.md, "Sessions and deltas").
    const uploads = await page.evaluate(() => window.studio.meshUploads());
    assert.ok(uploads.deltas >= 3 && uploads.patches >= 3, JSON.stringify(uploads));
    // A session the server no longer holds (here: a base revision it never had): the delta gets 409 and the page
    // sends the whole skeleton at once; the mesh is the same as the undo gave.
    await page.evaluate(() => window.studio.spoilSession());
    await page.keyboard.press('Control+Shift+z'); // redo the rejected move: a delta, 409, then the whole skeleton
    await page.waitForFunction(() => document.getElementById('status').dataset.state === 'error', null, { timeout: 10000 });
    await page.keyboard.press('Control+z');
    const recovered = await meshSettled(page);
    assert.deepEqual(recovered.skeleton, back.skeleton);
    assert.equal(recovered.maxX, back.maxX);
    const after = await page.evaluate(() => window.studio.meshUploads());
    assert.equal(after.full, uploads.full + 1, JSON.stringify([uploads, after]));
    assert.equal(after.deltas, uploads.deltas + 1, JSON.stringify([uploads, after]));

    // Peel 1 layer: every hex of this raw mesh (one hex across each branch) touches the boundary, so none is left.
    await page.fill('#v-peel', '1');
    await page.dispatchEvent('#v-peel', 'input');
    assert.equal(await page.evaluate(() => Math.min(...window.studio.state.meshes.raw.layers)), 0);
    assert.equal(await page.evaluate(() => document.getElementById('v-peel-val').textContent), '1');
    await page.fill('#v-peel', '0');
    await page.dispatchEvent('#v-peel', 'input');

    // Keyboard edits on the 6-vertex path 0-1-2-3-4-5 (exact V / E / F after each; Ctrl+Z gives back the identical
    // skeleton and its mesh).
    const base = back.skeleton;
    const select = async (...vs) => {
      await page.keyboard.press('Escape');
      for (const [k, v] of vs.entries()) {
        const p = await page.evaluate((i) => window.studio.screenPosition(i), v);
        if (k > 0) await page.keyboard.down('Shift');
        await page.mouse.click(p.x, p.y);
        if (k > 0) await page.keyboard.up('Shift');
      }
      assert.deepEqual(await page.evaluate(() => window.studio.state.selV), vs);
      await page.mouse.move(5, 5);
    };
    const counts = () => page.evaluate(() => {
      const s = window.studio.skeleton();
      return { V: s.points.length, E: s.edges.length, F: s.faces.length };
    });
    const answered = (before) => page.waitForFunction((n) => {
      const s = window.studio.state;
      return s.meshRequests > n && document.getElementById('status').dataset.state !== 'stale';
    }, before, { timeout: 15000 });
    const undoToBase = async () => {
      await page.keyboard.press('Control+z');
      const u = await meshSettled(page);
      assert.deepEqual(u.skeleton, base);
      assert.equal(u.hexes, redo.hexes);
    };
    for (const [keys, sel, expected] of [
      ['c', [0, 5], { V: 6, E: 6, F: 0 }], // connect the ends: a loop
      ['s', [1, 2], { V: 7, E: 6, F: 0 }], // split edge 1-2 at its middle
      ['m', [4, 5], { V: 5, E: 4, F: 0 }], // merge the last two vertices
      ['Delete', [3], { V: 5, E: 3, F: 0 }], // delete a vertex with its 2 edges
      ['e', [1, 2, 3], { V: 9, E: 10, F: 2 }], // extrude the chain 1-2-3 into a strip: 3 copies, 3 rungs, 2 sides, 2 quads
    ]) {
      await select(...sel);
      const n = await page.evaluate(() => window.studio.state.meshRequests);
      await page.keyboard.press(keys);
      assert.deepEqual(await counts(), expected, `${keys} on ${sel}`);
      await answered(n);
      await undoToBase();
    }
    assert.deepEqual(pageErrors, []);
  } finally {
    if (browser) await browser.close();
    server.proc.kill('SIGTERM');
  }
});
