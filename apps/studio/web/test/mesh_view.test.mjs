// Unit tests of the page's mesh helpers (visible faces under clipping, shrink, histogram, colours).
import test from 'node:test';
import assert from 'node:assert/strict';
import * as V from '../mesh_view.js';

// Two unit cubes stacked along x, sharing the face x=1 (VTK order: bottom z=0 then top z=1).
function twoCubes() {
  const vertices = [];
  for (const z of [0, 1]) for (const y of [0, 1]) for (const x of [0, 1, 2]) vertices.push(x, y, z);
  const id = (x, y, z) => z * 6 + y * 3 + x;
  const hex = (x) => [id(x, 0, 0), id(x + 1, 0, 0), id(x + 1, 1, 0), id(x, 1, 0), id(x, 0, 1), id(x + 1, 0, 1),
    id(x + 1, 1, 1), id(x, 1, 1)];
  return { vertices, hexes: [...hex(0), ...hex(1)], sj: [1, -0.2] };
}

function quadNormal(mesh, q) {
  const p = q.map((v) => mesh.vertices.slice(3 * v, 3 * v + 3));
  const a = p[1].map((x, i) => x - p[0][i]), b = p[3].map((x, i) => x - p[0][i]);
  return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
}

test('visible quads: the boundary of all hexes (10 of 12 faces), outward', () => {
  const m = twoCubes();
  assert.equal(V.hexCount(m), 2);
  const r = V.visibleQuads(m);
  assert.equal(r.quads.length, 40);
  assert.deepEqual(r.owner.filter((h) => h === 0).length, 5);
  // Every face points away from the centre of the 2x1x1 box (1, 0.5, 0.5).
  for (let f = 0; f < 10; f++) {
    const q = r.quads.slice(4 * f, 4 * f + 4);
    const c = [0, 1, 2].map((d) => q.reduce((acc, v) => acc + m.vertices[3 * v + d], 0) / 4);
    const n = quadNormal(m, q);
    assert.ok(n[0] * (c[0] - 1) + n[1] * (c[1] - 0.5) + n[2] * (c[2] - 0.5) > 0, `face ${f} points inwards`);
  }
});

test('visible quads with a clip: the kept hex shows all 6 faces (the cut face included)', () => {
  const m = twoCubes();
  const c = V.hexCentroids(m);
  assert.deepEqual([...c], [0.5, 0.5, 0.5, 1.5, 0.5, 0.5]);
  const r = V.visibleQuads(m, (h) => c[3 * h] <= 1);
  assert.equal(r.owner.length, 6);
  assert.ok(r.owner.every((h) => h === 0));
});

test('shrunk quads: every face of every hex, moved towards the hex centre', () => {
  const m = twoCubes();
  const r = V.shrunkQuads(m, 0.5);
  assert.equal(r.owner.length, 12);
  assert.equal(r.positions.length, 12 * 12);
  // Hex 0's corners are at 0.25 / 0.75 in every coordinate.
  for (let i = 0; i < 6 * 12; i++) assert.ok([0.25, 0.75].includes(r.positions[i]), `${r.positions[i]}`);
  const nq = r.positions.length / 12;
  assert.equal(nq, 12);
  const tri = V.quadTriangleIndex(nq), lines = V.quadLineIndex(nq);
  assert.equal(tri.length, 6 * nq);
  assert.deepEqual([...tri.slice(6, 12)], [4, 5, 6, 4, 6, 7]);
  assert.equal(lines.length, 8 * nq);
  assert.deepEqual([...lines.slice(8, 16)], [4, 5, 5, 6, 6, 7, 7, 4]);
  assert.equal(Math.max(...tri), 4 * nq - 1);
});

test('scaled-Jacobian histogram has a <= 0 bin; stats count the inverted', () => {
  const h = V.sjHistogram([-0.1, 0, 0.05, 0.1, 0.95, 1, 1.0000001], 10);
  assert.equal(h.labels[0], '<=0');
  assert.equal(h.counts.length, 11);
  assert.deepEqual(h.counts, [2, 2, 0, 0, 0, 0, 0, 0, 0, 0, 3]);
  const s = V.sjStats([-0.5, 0.5, 1]);
  assert.equal(s.min, -0.5);
  assert.equal(s.inverted, 1);
  assert.ok(Math.abs(s.avg - 1 / 3) < 1e-15);
});

test('colours: valence 3 red, 5 green, >= 6 blue; SJ <= 0 is distinct from SJ just above 0', () => {
  assert.deepEqual(V.valenceColor(3), [0.9, 0.1, 0.1]);
  assert.deepEqual(V.valenceColor(5), [0.1, 0.75, 0.1]);
  assert.deepEqual(V.valenceColor(6), V.valenceColor(8));
  assert.ok(V.valenceColor(6)[2] > 0.9);
  assert.notDeepEqual(V.sjColor(0), V.sjColor(0.01));
  assert.deepEqual(V.sjColor(-1), V.sjColor(0));
  assert.deepEqual(V.bounds([0, 0, 0, 3, 4, 0]), { min: [0, 0, 0], max: [3, 4, 0], diagonal: 5 });
});

// An n x n x n block of unit cubes (VTK order), as typed arrays like the binary answer's.
function block(n) {
  const vertices = [];
  for (let z = 0; z <= n; z++) for (let y = 0; y <= n; y++) for (let x = 0; x <= n; x++) vertices.push(x, y, z);
  const id = (x, y, z) => (z * (n + 1) + y) * (n + 1) + x;
  const hexes = [];
  for (let z = 0; z < n; z++) for (let y = 0; y < n; y++) for (let x = 0; x < n; x++)
    hexes.push(id(x, y, z), id(x + 1, y, z), id(x + 1, y + 1, z), id(x, y + 1, z),
      id(x, y, z + 1), id(x + 1, y, z + 1), id(x + 1, y + 1, z + 1), id(x, y + 1, z + 1));
  return { vertices: new Float32Array(vertices), hexes: new Uint32Array(hexes) };
}

test('peel layers: a 5x5x5 block has 98 hexes in layer 0, 26 in layer 1, 1 in layer 2', () => {
  const m = block(5);
  const layers = V.hexLayers(m);
  assert.equal(layers.length, 125);
  const count = (k) => layers.filter((x) => x === k).length;
  // layer k: the shell of the (5-2k)^3 block: 125-27 = 98, 27-1 = 26, 1.
  assert.equal(count(0), 98);
  assert.equal(count(1), 26);
  assert.equal(count(2), 1);
  // The centre hex (2, 2, 2) is the deepest; a corner hex is on the boundary.
  assert.equal(layers[2 * 25 + 2 * 5 + 2], 2);
  assert.equal(layers[0], 0);
  // Peeling 1 layer leaves the 3x3x3 core: its boundary is 6 x 9 = 54 quads.
  const shown = V.visibleQuads(m, (h) => layers[h] >= 1);
  assert.equal(shown.owner.length, 54);
});

test('peel layers: every hex of two cubes touches the boundary', () => {
  assert.deepEqual([...V.hexLayers(twoCubes())], [0, 0]);
});

// Two cubes sharing a face: a 2 x 1 x 1 box, 10 boundary quads (visibleQuads, 40 quad sides) on 12 vertices, so
// 12 - E + 10 = 2 gives E = 20 edges, each drawn once.
test('quad edge lines: each edge of the drawn quads once', () => {
  const m = twoCubes();
  const r = V.visibleQuads(m);
  assert.equal(r.quads.length, 40);
  const lines = V.quadEdgeLineIndex(r.quads);
  assert.equal(lines.length, 2 * 20);
  const seen = new Set();
  for (let i = 0; i < lines.length; i += 2) {
    const a = r.quads[lines[i]], b = r.quads[lines[i + 1]];
    const key = `${Math.min(a, b)}-${Math.max(a, b)}`;
    assert.ok(!seen.has(key), key);
    seen.add(key);
  }
  assert.equal(seen.size, 20);
});
