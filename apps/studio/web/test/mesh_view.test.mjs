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
  const tri = V.quadTriangleIndex(nq);
  assert.equal(tri.length, 6 * nq);
  assert.deepEqual([...tri.slice(6, 12)], [4, 5, 6, 4, 6, 7]);
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

// Back-face culling with inverted hexes: the quads of an inverted hex come a second time, reversed. Two cubes, hex 1
// inverted (sj -0.2): of the 10 boundary quads 5 are hex 1's, so 6 x 10 + 6 x 5 = 90 indices, the last 30 being
// hex 1's quads as a,c,b / a,d,c.
test('triangle index: inverted hexes drawn from both sides (reversed copies after the others)', () => {
  const m = twoCubes();
  const r = V.visibleQuads(m);
  const nq = r.owner.length;
  assert.equal(nq, 10);
  const idx = V.quadTriangleIndex(nq, (q) => !(m.sj[r.owner[q]] > 0));
  assert.equal(idx.length, 90);
  assert.deepEqual([...idx.slice(0, 60)], [...V.quadTriangleIndex(nq)]);
  const flipped = [];
  for (let i = 60; i < 90; i += 6) {
    const b = idx[i];
    assert.equal(b % 4, 0);
    assert.deepEqual([...idx.slice(i, i + 6)], [b, b + 2, b + 1, b, b + 3, b + 2]);
    flipped.push(b / 4);
  }
  assert.deepEqual(flipped, [...Array(nq).keys()].filter((q) => r.owner[q] === 1));
  assert.equal(V.quadTriangleIndex(nq, () => false).length, 60);
});

// The fragment-shader wireframe: along each triangle edge that is a side of its quad one corner coordinate is 0 or 1 at
// both ends (so the interpolated distance to that side is 0 along it); along the diagonal a-c none is. 3 quads:
// 6 triangles, 18 triangle edges = 12 sides (4 per quad, each once) + 6 diagonal edges (each quad's twice).
test('quad corner coordinates: 0 or 1 along the 4 sides of each quad, never along its diagonal', () => {
  const nq = 3;
  const uv = V.quadCornerCoords(nq), tri = V.quadTriangleIndex(nq);
  assert.equal(uv.length, 8 * nq);
  assert.deepEqual([...uv.slice(8, 16)], [0, 0, 1, 0, 1, 1, 0, 1]);
  let sides = 0, diagonals = 0;
  const sideKeys = new Set();
  for (let t = 0; t < tri.length; t += 3)
    for (let k = 0; k < 3; k++) {
      const i = tri[t + k], j = tri[t + (k + 1) % 3];
      assert.equal(i >> 2, j >> 2, 'a triangle stays in its quad');
      const onSide = [0, 1].some((d) => uv[2 * i + d] === uv[2 * j + d] && (uv[2 * i + d] === 0 || uv[2 * i + d] === 1));
      const isSide = ((i - j) & 3) !== 2; // corners 0-2 / 1-3 are the diagonals
      assert.equal(onSide, isSide, `edge ${i}-${j}`);
      if (isSide) { sides++; sideKeys.add(`${Math.min(i, j)}-${Math.max(i, j)}`); } else diagonals++;
    }
  assert.equal(sides, 12);
  assert.equal(sideKeys.size, 12);
  assert.equal(diagonals, 6);
});

// Normals per quad: the two-cube box's 10 boundary quads are axis-aligned unit squares, so each normal is a unit axis
// vector pointing away from the box's centre (1, 0.5, 0.5): -x 1, +x 1, -y 2, +y 2, -z 2, +z 2 (2 cubes per side
// face), the same at the 4 corners. A warped quad gets the cross product of its diagonals; a degenerate one 0 0 0.
test('quad normals: outward unit axes on the box, diagonals cross product when warped, zero when degenerate', () => {
  const m = twoCubes();
  const r = V.visibleQuads(m);
  const pos = r.quads.flatMap((v) => m.vertices.slice(3 * v, 3 * v + 3));
  const n = V.quadNormals(pos);
  assert.equal(n.length, 10 * 12);
  const count = {};
  for (let q = 0; q < 10; q++) {
    const c = [0, 1, 2].map((d) => (pos[12 * q + d] + pos[12 * q + 3 + d] + pos[12 * q + 6 + d] + pos[12 * q + 9 + d]) / 4);
    const nq = [...n.slice(12 * q, 12 * q + 3)];
    for (let k = 1; k < 4; k++) assert.deepEqual([...n.slice(12 * q + 3 * k, 12 * q + 3 * k + 3)], nq);
    const axis = nq.findIndex((x) => x !== 0);
    assert.equal(nq.filter((x) => x !== 0).length, 1);
    assert.equal(Math.abs(nq[axis]), 1);
    assert.ok(nq[axis] * (c[axis] - [1, 0.5, 0.5][axis]) > 0, `quad ${q} points inwards`);
    const key = `${nq[axis] > 0 ? '+' : '-'}${'xyz'[axis]}`;
    count[key] = (count[key] || 0) + 1;
  }
  assert.deepEqual(count, { '-x': 1, '+x': 1, '-y': 2, '+y': 2, '-z': 2, '+z': 2 });
  // (c - a) x (d - b) = (1, 1, 1) x (-1, 1, 0) = (-1, -1, 2), over its length sqrt(6).
  const warped = V.quadNormals([0, 0, 0, 1, 0, 0, 1, 1, 1, 0, 1, 0]);
  const s6 = Math.sqrt(6);
  [-1 / s6, -1 / s6, 2 / s6].forEach((x, i) => assert.ok(Math.abs(warped[i] - x) < 1e-7, `${warped[i]}`));
  assert.deepEqual([...V.quadNormals([0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0])], new Array(12).fill(0));
});
