// Unit tests of the studio's pure edit operations: exact V/E/F after each edit, undo restores the identical
// skeleton (deep equality), redo re-applies. Run: node --test apps/studio/web/test/
import test from 'node:test';
import assert from 'node:assert/strict';
import * as M from '../skeleton_model.js';

// A branch of 3 vertices on the x axis: 0-1-2, radii 0.1, 0.2, 0.3.
const path3 = () => M.fromJson({ points: [[0, 0, 0], [1, 0, 0], [2, 0, 0]], radii: [0.1, 0.2, 0.3],
  edges: [[0, 1], [1, 2]], faces: [] });
// Two quads side by side in z=0: 0(0,0) 1(1,0) 2(2,0) / 3(0,1) 4(1,1) 5(2,1); faces 0-1-4-3 and 1-2-5-4.
// fromJson appends the 7 sides as edges.
const strip = () => M.fromJson({ points: [[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0]],
  radii: [], edges: [], faces: [[0, 1, 4, 3], [1, 2, 5, 4]] });

// Applies an edit through an UndoStack and checks undo gives back the same skeleton, redo the edited one.
function checkUndoRedo(before, after) {
  const u = new M.UndoStack(before);
  const snapshot = structuredClone(before);
  u.push(after, 'edit');
  assert.deepEqual(u.undo(), snapshot);
  assert.deepEqual(u.current, before);
  assert.equal(u.canUndo(), false);
  assert.deepEqual(u.redo(), after);
  assert.equal(u.canRedo(), false);
}

test('fromJson appends missing face sides; toObj writes every edge and 1-based faces', () => {
  const s = strip();
  assert.deepEqual(M.counts(s), { V: 6, E: 7, F: 2 });
  const obj = M.toObj(path3());
  assert.match(obj, /^v 1 0 0$/m);
  assert.match(obj, /^# mesohex radius 3 0.3$/m);
  assert.equal(obj.split('\n').filter((l) => l.startsWith('l ')).length, 2);
  assert.match(M.toObj(strip()), /^f 2 3 6 5$/m);
  assert.throws(() => M.fromJson({ points: [[0, 0, 0]], radii: [1, 2], edges: [] }), M.ModelError);
});

test('toBinary: the MHSK layout (header counts, float64 values, -0 written as 0, uint32 indices)', () => {
  // strip(): V 6, no radii, E 7, F 2, S 8: 32 + 24*6 + 8*7 + 4*2 + 4*8 = 272 bytes.
  const b = M.toBinary(strip());
  assert.equal(b.byteLength, 272);
  const dv = new DataView(b);
  assert.equal(String.fromCharCode(...new Uint8Array(b, 0, 4)), 'MHSK');
  assert.deepEqual([1, 2, 3, 4, 5, 6, 7].map((i) => dv.getUint32(4 * i, true)), [1, 6, 0, 7, 2, 8, 0]);
  assert.equal(dv.getFloat64(32 + 24 * 4 + 8, true), 1);  // vertex 4's y
  assert.deepEqual([0, 1].map((i) => dv.getUint32(32 + 24 * 6 + 8 * 7 + 4 * i, true)), [4, 4]);  // face sizes
  assert.equal(dv.getUint32(272 - 4, true), 4);  // the last corner of face 1-2-5-4
  // path3 with radii and a -0: V 3, R 3, E 2: 32 + 72 + 24 + 16 = 144 bytes.
  const p = path3();
  p.points[0][1] = -0;
  const c = M.toBinary(p);
  assert.equal(c.byteLength, 144);
  assert.ok(Object.is(new DataView(c).getFloat64(32 + 8, true), 0));
  assert.equal(new DataView(c).getFloat64(32 + 72 + 16, true), 0.3);
});

test('operations never modify their input', () => {
  const s = strip();
  const copy = structuredClone(s);
  M.extrudeVertex(s, 0, [0, 0, 1]);
  M.extrudeEdge(s, 0, 1, [0, -1, 0]);
  M.splitEdge(s, 0, 1);
  M.mergeVertices(s, 0, 1);
  M.deleteElements(s, { vertices: [4] });
  M.setRadius(s, [0], 0.5);
  assert.deepEqual(s, copy);
});

test('extrude a vertex into a branch: +1 V, +1 E, radius copied', () => {
  const s = path3();
  const r = M.extrudeVertex(s, 2, [0, 1, 0]);
  assert.deepEqual(M.counts(r.skeleton), { V: 4, E: 3, F: 0 });
  assert.equal(r.vertex, 3);
  assert.deepEqual(r.skeleton.points[3], [2, 1, 0]);
  assert.equal(r.skeleton.radii[3], 0.3);
  assert.deepEqual(r.skeleton.edges[2], [2, 3]);
  checkUndoRedo(s, r.skeleton);
  assert.throws(() => M.extrudeVertex(s, 7, [0, 1, 0]), /vertex 7 does not exist/);
});

test('extrude a leaflet boundary edge into a new quad: +2 V, +3 E, +1 F', () => {
  const s = strip();
  const r = M.extrudeEdge(s, 0, 1, [0, -1, 0]);
  assert.deepEqual(M.counts(r.skeleton), { V: 8, E: 10, F: 3 });
  // The face 0-1-4-3 runs 0->1, so the new quad runs 1->0 (consistent orientation).
  assert.deepEqual(r.skeleton.faces[2], [1, 0, 7, 6]);
  assert.deepEqual(r.skeleton.points[6], [1, -1, 0]);
  assert.deepEqual(r.skeleton.points[7], [0, -1, 0]);
  checkUndoRedo(s, r.skeleton);
  // 1-4 is shared by both faces: not extrudable. 0-2 is not an edge.
  assert.throws(() => M.extrudeEdge(s, 1, 4, [0, 0, 1]), /inside a leaflet/);
  assert.throws(() => M.extrudeEdge(s, 0, 2, [0, 0, 1]), /not an edge/);
  // A branch edge can be extruded into a quad too.
  const b = M.extrudeEdge(path3(), 0, 1, [0, 0, 1]);
  assert.deepEqual(M.counts(b.skeleton), { V: 5, E: 5, F: 1 });
});

test('fill a quad from 4 vertices: orders them into a cycle and adds the missing sides', () => {
  // 4 isolated corners of a unit square given in a crossing order.
  const s = M.fromJson({ points: [[0, 0, 0], [1, 1, 0], [1, 0, 0], [0, 1, 0]], radii: [], edges: [], faces: [] });
  const r = M.fillQuad(s, [0, 1, 2, 3]);
  assert.deepEqual(M.counts(r.skeleton), { V: 4, E: 4, F: 1 });
  const f = r.skeleton.faces[0];
  // Consecutive corners are at distance 1 (sides), never the diagonal sqrt(2).
  for (let i = 0; i < 4; i++) {
    const p = r.skeleton.points[f[i]], q = r.skeleton.points[f[(i + 1) % 4]];
    assert.equal(Math.hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]), 1);
  }
  checkUndoRedo(s, r.skeleton);
  // On the strip, filling 0,1,4,3 again is refused; collinear vertices are refused.
  assert.throws(() => M.fillQuad(strip(), [0, 1, 4, 3]), /exists/);
  const line = M.fromJson({ points: [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]], radii: [], edges: [], faces: [] });
  assert.throws(() => M.fillQuad(line, [0, 1, 2, 3]), /collinear/);
  // Extending the strip: 2, 5 and two new points; existing side 2-5 is reused: +3 edges.
  const s2 = M.addVertex(M.addVertex(strip(), [3, 0, 0]).skeleton, [3, 1, 0]).skeleton;
  const r2 = M.fillQuad(s2, [2, 6, 7, 5]);
  assert.deepEqual(M.counts(r2.skeleton), { V: 8, E: 10, F: 3 });
});

test('connect two vertices: +1 E; refused when the edge exists or a == b', () => {
  const s = path3();
  const r = M.connect(s, 0, 2);
  assert.deepEqual(M.counts(r.skeleton), { V: 3, E: 3, F: 0 });
  checkUndoRedo(s, r.skeleton);
  assert.throws(() => M.connect(s, 0, 1), /already an edge/);
  assert.throws(() => M.connect(s, 1, 1), /itself/);
});

test('split a branch edge: +1 V at the middle, +1 E, mean radius', () => {
  const s = path3();
  const r = M.splitEdge(s, 1, 2);
  assert.deepEqual(M.counts(r.skeleton), { V: 4, E: 3, F: 0 });
  assert.deepEqual(r.skeleton.points[3], [1.5, 0, 0]);
  assert.ok(Math.abs(r.skeleton.radii[3] - 0.25) < 1e-15);
  assert.equal(M.findEdge(r.skeleton, 1, 2), -1);
  assert.ok(M.findEdge(r.skeleton, 1, 3) >= 0 && M.findEdge(r.skeleton, 3, 2) >= 0);
  checkUndoRedo(s, r.skeleton);
});

test('split a leaflet edge splits the strip of quads across it: faces stay quads', () => {
  const s = strip();
  // 0-1 is a side of quad 0-1-4-3 only; its opposite side 4-3 is split too: +2 V, 7 + 2 (halves) + 1 (cut) = 10 E.
  const r = M.splitEdge(s, 0, 1);
  assert.deepEqual(M.counts(r.skeleton), { V: 8, E: 10, F: 3 });
  assert.ok(r.skeleton.faces.every((f) => f.length === 4));
  checkUndoRedo(s, r.skeleton);
  // 0-3 crosses both quads (0-3 -> 1-4 -> 2-5): +3 V, +3 halves, +2 cuts = 12 E, 4 F.
  const r2 = M.splitEdge(s, 0, 3);
  assert.deepEqual(M.counts(r2.skeleton), { V: 9, E: 12, F: 4 });
  assert.ok(r2.skeleton.faces.every((f) => f.length === 4));
});

test('merge two vertices: midpoint, loops and duplicate edges dropped, renumbered', () => {
  const s = path3();
  const r = M.mergeVertices(s, 0, 1);
  assert.deepEqual(M.counts(r.skeleton), { V: 2, E: 1, F: 0 });
  assert.deepEqual(r.skeleton.points[0], [0.5, 0, 0]);
  assert.ok(Math.abs(r.skeleton.radii[0] - 0.15) < 1e-15);
  assert.deepEqual(r.skeleton.edges, [[0, 1]]);
  checkUndoRedo(s, r.skeleton);
  // Merging two corners of a quad along its side turns it into a triangle: strip 0+1 -> quad 0-1-4-3 becomes
  // a triangle; V 5, edges: 0-1 loop dropped, 7 - 1 = 6, F 2.
  const q = M.mergeVertices(strip(), 0, 1);
  assert.deepEqual(M.counts(q.skeleton), { V: 5, E: 6, F: 2 });
  assert.equal(q.skeleton.faces[0].length, 3);
  // Merging diagonal corners 0 and 4 of quad 0-1-4-3: the quad degenerates ([0,1,0,3] repeats 0) and is dropped;
  // edges 1-4 and 4-3 become duplicates of 0-1 and 3-0: 7 - 2 = 5 E.
  const d = M.mergeVertices(strip(), 0, 4);
  assert.deepEqual(M.counts(d.skeleton), { V: 5, E: 5, F: 1 });
});

test('delete vertices and edges: incident edges and faces go, the rest is renumbered', () => {
  const s = strip();
  // Vertex 4 is in both faces and on 3 edges (1-4, 4-3, 5-4): 5 V, 4 E, 0 F.
  const r = M.deleteElements(s, { vertices: [4] });
  assert.deepEqual(M.counts(r.skeleton), { V: 5, E: 4, F: 0 });
  assert.deepEqual(r.map, [0, 1, 2, 3, -1, 4]);
  checkUndoRedo(s, r.skeleton);
  // Deleting edge 2-5 removes the second face only.
  const e = M.deleteElements(s, { edges: [[5, 2]] });
  assert.deepEqual(M.counts(e.skeleton), { V: 6, E: 6, F: 1 });
  assert.deepEqual(e.skeleton.faces, [[0, 1, 4, 3]]);
});

test('move vertices and set / brush radii', () => {
  const s = path3();
  const m = M.translateVertices(s, [0, 2], [0, 0, 1]);
  assert.deepEqual(m.skeleton.points, [[0, 0, 1], [1, 0, 0], [2, 0, 1]]);
  checkUndoRedo(s, m.skeleton);
  const r = M.setRadius(s, [1], 0.5);
  assert.deepEqual(r.skeleton.radii, [0.1, 0.5, 0.3]);
  checkUndoRedo(s, r.skeleton);
  // Without radii: every vertex gets the value (all-or-nothing).
  const n = M.setRadius(strip(), [0], 0.2);
  assert.deepEqual(n.skeleton.radii, [0.2, 0.2, 0.2, 0.2, 0.2, 0.2]);
  assert.throws(() => M.setRadius(s, [0], 0), /> 0/);
  const b = M.brushRadius(s, [0, 1], [1, 0.5], 2);
  assert.deepEqual(b.skeleton.radii, [0.2, 0.30000000000000004, 0.3]);
  checkUndoRedo(s, b.skeleton);
  const all = M.setAllRadii(s, [1, 2, 3]);
  assert.deepEqual(all.skeleton.radii, [1, 2, 3]);
  assert.throws(() => M.setAllRadii(s, [1, 2]), /2 radii for 3/);
});

test('mirror editing across x = 0 applies each edit to the mirror partner', () => {
  // A spine on the plane (0 and 1) and a symmetric pair of arms: 2 at x=+1, 3 at x=-1, joined to 1.
  const s = M.fromJson({ points: [[0, 0, 0], [0, 1, 0], [1, 1, 0], [-1, 1, 0]], radii: [],
    edges: [[0, 1], [1, 2], [1, 3]], faces: [] });
  const plane = { axis: 0, c: 0 };
  assert.equal(M.mirrorPartner(s, 2, plane, 1e-6), 3);
  assert.equal(M.mirrorPartner(s, 0, plane, 1e-6), 0);
  // Extruding arm 2 outwards extrudes arm 3 outwards too: +2 V, +2 E.
  const e = M.applyEdit(s, 'extrudeVertex', { vertex: 2, offset: [1, 0, 0] }, plane);
  assert.deepEqual(M.counts(e.skeleton), { V: 6, E: 5, F: 0 });
  assert.deepEqual(e.skeleton.points.slice(4), [[2, 1, 0], [-2, 1, 0]]);
  checkUndoRedo(s, e.skeleton);
  // Extruding a vertex on the plane sideways gives both sides; straight up gives one.
  assert.equal(M.applyEdit(s, 'extrudeVertex', { vertex: 0, offset: [1, 0, 0] }, plane).skeleton.points.length, 6);
  assert.equal(M.applyEdit(s, 'extrudeVertex', { vertex: 0, offset: [0, -1, 0] }, plane).skeleton.points.length, 5);
  // Moving 2 up and outwards moves 3 up and outwards; a vertex on the plane stays on it.
  const mv = M.applyEdit(s, 'move', { vertices: [2, 1], offset: [0.5, 0.25, 0] }, plane);
  assert.deepEqual(mv.skeleton.points, [[0, 0, 0], [0, 1.25, 0], [1.5, 1.25, 0], [-1.5, 1.25, 0]]);
  // Delete 2 deletes 3; radius on 2 sets 3.
  assert.deepEqual(M.counts(M.applyEdit(s, 'delete', { vertices: [2] }, plane).skeleton), { V: 2, E: 1, F: 0 });
  assert.deepEqual(M.applyEdit(s, 'radius', { vertices: [2], r: 0.4 }, plane).skeleton.radii, [0.4, 0.4, 0.4, 0.4]);
  // Without a plane only the selection changes.
  assert.deepEqual(M.counts(M.applyEdit(s, 'delete', { vertices: [2] }).skeleton), { V: 3, E: 2, F: 0 });
  // Connect 0-2 also connects 0-3; split 1-2 also splits 1-3.
  assert.deepEqual(M.counts(M.applyEdit(s, 'connect', { a: 0, b: 2 }, plane).skeleton), { V: 4, E: 5, F: 0 });
  assert.deepEqual(M.counts(M.applyEdit(s, 'split', { a: 1, b: 2 }, plane).skeleton), { V: 6, E: 5, F: 0 });
});

test('mirror fill, edge extrusion and merge', () => {
  // Two squares side by side in z=0, mirror images across x=0: left 0..3 (x<0), right 4..7 (x>0), no edges.
  const s = M.fromJson({ points: [[-2, 0, 0], [-1, 0, 0], [-1, 1, 0], [-2, 1, 0], [2, 0, 0], [1, 0, 0], [1, 1, 0],
    [2, 1, 0]], radii: [], edges: [], faces: [] });
  const plane = { axis: 0, c: 0 };
  const f = M.applyEdit(s, 'fill', { vertices: [4, 5, 6, 7] }, plane);
  assert.deepEqual(M.counts(f.skeleton), { V: 8, E: 8, F: 2 });
  const x = M.applyEdit(f.skeleton, 'extrudeEdge', { a: 4, b: 5, offset: [0, -1, 0] }, plane);
  assert.deepEqual(M.counts(x.skeleton), { V: 12, E: 14, F: 4 });
  // Merge 4 and 5 (right) also merges 0 and 1 (left): two triangles-or-dropped faces, 6 V.
  const m = M.applyEdit(f.skeleton, 'merge', { keep: 5, remove: 4 }, plane);
  assert.deepEqual(M.counts(m.skeleton), { V: 6, E: 6, F: 2 });
  assert.ok(m.skeleton.faces.every((g) => g.length === 3));
  checkUndoRedo(f.skeleton, m.skeleton);
});

test('UndoStack: unbounded, a new edit clears redo', () => {
  let s = path3();
  const u = new M.UndoStack(s);
  const states = [structuredClone(s)];
  for (let i = 0; i < 200; i++) {
    s = M.extrudeVertex(s, s.points.length - 1, [0, 0, 1]).skeleton;
    u.push(s);
    states.push(structuredClone(s));
  }
  for (let i = 199; i >= 0; i--) assert.deepEqual(u.undo(), states[i]);
  assert.equal(u.undo(), null);
  assert.deepEqual(u.redo(), states[1]);
  u.push(M.connect(u.current, 0, 2).skeleton);
  assert.equal(u.canRedo(), false);
  assert.equal(u.redo(), null);
  assert.deepEqual(u.undo(), states[1]);
});

test('extrude a chain into a strip: an open path of branch edges, a closed loop, a leaflet border', () => {
  // The path 0-1-2: +3 V, 3 rungs + 2 new sides = +5 E, +2 F; quads follow the walk from the first selected end,
  // 2->1->0.
  const s = path3();
  const r = M.extrudeChain(s, [2, 0, 1], [0, 0, 1]);
  assert.deepEqual(M.counts(r.skeleton), { V: 6, E: 7, F: 2 });
  assert.deepEqual(r.vertices, [3, 4, 5]); // copies of 2, 0, 1 in the selection's order
  assert.deepEqual(r.skeleton.points[4], [0, 0, 1]);
  assert.deepEqual(r.skeleton.radii, [0.1, 0.2, 0.3, 0.3, 0.1, 0.2]);
  assert.deepEqual(r.skeleton.faces, [[2, 1, 5, 3], [1, 0, 4, 5]]);
  checkUndoRedo(s, r.skeleton);
  // A closed loop of 4 branch edges (a square): a closed band of 4 quads, +4 V, +8 E.
  const loop = M.fromJson({ points: [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], radii: [],
    edges: [[0, 1], [1, 2], [2, 3], [3, 0]], faces: [] });
  const band = M.extrudeChain(loop, [0, 1, 2, 3], [0, 0, 2]);
  assert.deepEqual(M.counts(band.skeleton), { V: 8, E: 12, F: 4 });
  assert.equal(band.skeleton.edges.filter(([a, b]) => a >= 4 && b >= 4).length, 4);
  // The strip's border 0-1-2 (faces 0-1-4-3 and 1-2-5-4 run 0->1->2): the new quads run against it (1->0, 2->1).
  const st = strip();
  const grown = M.extrudeChain(st, [0, 1, 2], [0, -1, 0]);
  assert.deepEqual(M.counts(grown.skeleton), { V: 9, E: 12, F: 4 });
  assert.deepEqual(grown.skeleton.faces.slice(2), [[1, 0, 6, 7], [2, 1, 7, 8]]);
  // Refused: a vertex without a selected edge, a vertex on three selected edges, an edge inside the leaflet.
  assert.throws(() => M.extrudeChain(s, [0, 2], [0, 0, 1]), /no edge to another selected vertex/);
  const star = M.fromJson({ points: [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], radii: [], edges: [[0, 1], [0, 2], [0, 3]], faces: [] });
  assert.throws(() => M.extrudeChain(star, [0, 1, 2, 3], [1, 1, 1]), /3 selected edges/);
  assert.throws(() => M.extrudeChain(st, [1, 4], [0, 0, 1]), /inside a leaflet/);
});

test('extrude a chain with mirror editing: the mirrored chain is extruded too', () => {
  // Two branch edges mirrored across x = 0: 0(-2,0,0)-1(-1,0,0) and 2(2,0,0)-3(1,0,0).
  const s = M.fromJson({ points: [[-2, 0, 0], [-1, 0, 0], [2, 0, 0], [1, 0, 0]], radii: [], edges: [[0, 1], [2, 3]], faces: [] });
  const r = M.applyEdit(s, 'extrudeChain', { vertices: [0, 1], offset: [-0.5, 1, 0] }, { axis: 0, c: 0 });
  assert.deepEqual(M.counts(r.skeleton), { V: 8, E: 8, F: 2 });
  assert.deepEqual(r.created, [4, 5, 6, 7]);
  assert.deepEqual(r.skeleton.points[6], [2.5, 1, 0]);
});

test('toDelta: the MHSD layout (moved vertices only, radii when present); null when the topology differs', () => {
  const base = M.fromJson({ points: [[0, 0, 0], [1, 0, 0], [2, 0, 0]], radii: [0.5, 0.5, 0.5], edges: [[0, 1], [1, 2]], faces: [] });
  const moved = M.setRadius(M.moveVertices(base, [1], [[1, -0, 0.25]]).skeleton, [2], 0.75).skeleton;
  const buf = M.toDelta(base, moved);
  const dv = new DataView(buf);
  assert.equal(String.fromCharCode(...new Uint8Array(buf, 0, 4)), 'MHSD');
  assert.deepEqual([1, 2, 3, 4].map((i) => dv.getUint32(4 * i, true)), [1, 3, 2, 1]); // version, V, K, radii
  assert.equal(buf.byteLength, 20 + 2 * (4 + 24 + 8));
  assert.deepEqual([dv.getUint32(20, true), dv.getUint32(24, true)], [1, 2]);
  assert.deepEqual([0, 1, 2].map((k) => dv.getFloat64(28 + 8 * k, true)), [1, 0, 0.25]);
  assert.ok(!Object.is(dv.getFloat64(36, true), -0)); // -0 written as 0
  assert.deepEqual([dv.getFloat64(76, true), dv.getFloat64(84, true)], [0.5, 0.75]);
  assert.equal(M.toDelta(base, base).byteLength, 20); // nothing changed
  assert.equal(M.toDelta(null, base), null);
  assert.equal(M.toDelta(base, M.extrudeVertex(base, 2, [0, 1, 0]).skeleton), null);
  assert.equal(M.toDelta(base, { ...M.clone(base), edges: [[0, 1], [0, 2]] }), null);
  assert.equal(M.toDelta(base, { ...M.clone(base), radii: [] }), null);
});
