// Unit tests of the binary answer reader (the page's form of /api/mesh; the server's writer is tested in
// tests/unit/test_studio_server.cpp against the JSON answer).
import test from 'node:test';
import assert from 'node:assert/strict';
import { decodeBinaryAnswer, encodeBinaryAnswer, BinaryAnswerError } from '../binary_answer.js';

test('binary answer: header fields kept, arrays at their dotted names as typed arrays', () => {
  const buf = encodeBinaryAnswer({ server_ms: 3.5, report: { quality: { hexes: 1 } } }, [
    { name: 'mesh.vertices', type: 'f32', values: [0, 0.1, -2, 1e6] },
    { name: 'mesh.hexes', type: 'u32', values: [0, 1, 2, 3, 4, 5, 6, 4294967295] },
    { name: 'connection_surfaces.quads', type: 'u32', values: [] },
  ]);
  assert.equal(buf.byteLength % 4, 0);
  const r = decodeBinaryAnswer(buf);
  assert.equal(r.server_ms, 3.5);
  assert.equal(r.report.quality.hexes, 1);
  assert.ok(r.mesh.vertices instanceof Float32Array);
  assert.deepEqual([...r.mesh.vertices], [0, Math.fround(0.1), -2, 1e6]);
  assert.ok(r.mesh.hexes instanceof Uint32Array);
  assert.deepEqual([...r.mesh.hexes], [0, 1, 2, 3, 4, 5, 6, 4294967295]);
  assert.equal(r.connection_surfaces.quads.length, 0);
  assert.deepEqual(r.arrays.map((a) => a.count), [4, 8, 0]);
});

test('binary answer: the bytes are little-endian with a padded header', () => {
  const buf = encodeBinaryAnswer({ a: 1 }, [{ name: 'x', type: 'u32', values: [258] }]);
  const bytes = new Uint8Array(buf);
  assert.deepEqual([...bytes.slice(0, 8)], [0x4d, 0x48, 0x58, 0x42, 1, 0, 0, 0]);
  const h = bytes[8] | (bytes[9] << 8);
  assert.equal(h % 4, 0);
  assert.deepEqual([...bytes.slice(12 + h)], [2, 1, 0, 0]);
});

test('binary answer: truncated, padded or foreign bodies are refused', () => {
  const buf = encodeBinaryAnswer({}, [{ name: 'x', type: 'f32', values: [1, 2] }]);
  assert.throws(() => decodeBinaryAnswer(buf.slice(0, buf.byteLength - 4)), BinaryAnswerError);
  const longer = new Uint8Array(buf.byteLength + 4);
  longer.set(new Uint8Array(buf));
  assert.throws(() => decodeBinaryAnswer(longer.buffer), BinaryAnswerError);
  const foreign = new Uint8Array(buf.slice(0));
  foreign[3] = 0x41;
  assert.throws(() => decodeBinaryAnswer(foreign.buffer), BinaryAnswerError);
  assert.throws(() => decodeBinaryAnswer(new ArrayBuffer(4)), BinaryAnswerError);
});

test('binary answer: an enum array becomes the array of its names at its dotted path', () => {
  const buf = encodeBinaryAnswer({ analysis: { counts: { vertices: 4 } } }, [
    { name: 'analysis.vertex_class', type: 'enum', names: ['joint', 'extremity'], values: [1, 0, 0, 1] },
    { name: 'analysis.edge_kind', type: 'enum', names: ['branch'], values: [] },
  ]);
  const r = decodeBinaryAnswer(buf);
  assert.deepEqual(r.analysis.vertex_class, ['extremity', 'joint', 'joint', 'extremity']);
  assert.deepEqual(r.analysis.edge_kind, []);
  assert.equal(r.analysis.counts.vertices, 4);
  const bad = encodeBinaryAnswer({}, [{ name: 'k', type: 'enum', names: ['a'], values: [1] }]);
  assert.throws(() => decodeBinaryAnswer(bad), BinaryAnswerError);
});

// A patch answer written by hand: header {patch_of, arrays: [...]} with "patch": M entries (M indices, M values).
function patchAnswer(header, entries) {
  let text = JSON.stringify({ ...header, arrays: entries.map((e) => e.entry) });
  while (text.length % 4) text += ' ';
  const words = entries.flatMap((e) => e.words);
  const buf = new ArrayBuffer(12 + text.length + 4 * words.length);
  const dv = new DataView(buf);
  new Uint8Array(buf, 0, 4).set([0x4d, 0x48, 0x58, 0x42]);
  dv.setUint32(4, 1, true);
  dv.setUint32(8, text.length, true);
  new Uint8Array(buf, 12, text.length).set(new TextEncoder().encode(text));
  words.forEach((w, i) => {
    if (typeof w === 'object') dv.setFloat32(12 + text.length + 4 * i, w.f, true);
    else dv.setUint32(12 + text.length + 4 * i, w, true);
  });
  return buf;
}

test('binary answer: a patch answer changes copies of the previous arrays, M = 0 keeps them', () => {
  const previous = decodeBinaryAnswer(encodeBinaryAnswer({}, [
    { name: 'mesh.vertices', type: 'f32', values: [1, 2, 3] },
    { name: 'mesh.hexes', type: 'u32', values: [7, 8] },
    { name: 'analysis.vertex_class', type: 'enum', names: ['Joint', 'Extremity'], values: [0, 1, 0] },
  ]));
  const buf = patchAnswer({ patch_of: 4 }, [
    { entry: { name: 'mesh.vertices', type: 'f32', count: 3, patch: 1 }, words: [1, { f: 2.5 }] },
    { entry: { name: 'mesh.hexes', type: 'u32', count: 2, patch: 0 }, words: [] },
    { entry: { name: 'analysis.vertex_class', type: 'enum', count: 3, patch: 1, names: ['Joint', 'Extremity'] },
      words: [2, 1] },
  ]);
  const r = decodeBinaryAnswer(buf, previous);
  assert.equal(r.patch_of, 4);
  assert.deepEqual([...r.mesh.vertices], [1, 2.5, 3]);
  assert.deepEqual([...previous.mesh.vertices], [1, 2, 3]); // not modified
  assert.equal(r.mesh.hexes, previous.mesh.hexes); // unchanged: the same array
  assert.deepEqual(r.analysis.vertex_class, ['Joint', 'Extremity', 'Extremity']);
  assert.throws(() => decodeBinaryAnswer(buf), BinaryAnswerError); // no previous answer
  const bad = patchAnswer({}, [{ entry: { name: 'mesh.vertices', type: 'f32', count: 3, patch: 1 }, words: [3, { f: 1 }] }]);
  assert.throws(() => decodeBinaryAnswer(bad, previous), BinaryAnswerError); // index out of range
  const other = patchAnswer({}, [{ entry: { name: 'mesh.vertices', type: 'f32', count: 4, patch: 0 }, words: [] }]);
  assert.throws(() => decodeBinaryAnswer(other, previous), BinaryAnswerError); // another length
});

// The row patch of the C++ test StudioSessions.RowPatchOfAnInsertion: vertices A B C D -> A X B C D (runs: base row
// 0, one literal row, base rows 1-3), edges (0 1) (2 3) -> (0 2) (3 4) (one run of both base rows, translated).
test('binary answer: a row patch copies runs of previous rows and translates their row numbers', () => {
  const previous = decodeBinaryAnswer(encodeBinaryAnswer({}, [
    { name: 'mesh.vertices', type: 'f32', values: [1, 0, 0, 2, 0, 0, 3, 0, 0, 4, 0, 0] },
    { name: 'mesh.hexes', type: 'u32', values: [0, 1, 2, 3] },
  ]));
  const NO = 0xffffffff;
  const buf = patchAnswer({ patch_of: 1 }, [
    { entry: { name: 'mesh.vertices', type: 'f32', count: 15, width: 3, rows: 3, literal: 1 },
      words: [1, 0, 1, NO, 3, 1, { f: 9 }, { f: 9 }, { f: 9 }] },
    { entry: { name: 'mesh.hexes', type: 'u32', count: 4, width: 2, rows: 1, literal: 0, ref: 'mesh.vertices',
      ref_columns: 2 }, words: [2, 0] },
  ]);
  const r = decodeBinaryAnswer(buf, previous);
  assert.deepEqual([...r.mesh.vertices], [1, 0, 0, 9, 9, 9, 2, 0, 0, 3, 0, 0, 4, 0, 0]);
  assert.deepEqual([...r.mesh.hexes], [0, 2, 3, 4]);
  assert.deepEqual([...previous.mesh.hexes], [0, 1, 2, 3]); // not modified
  assert.throws(() => decodeBinaryAnswer(buf), BinaryAnswerError); // no previous answer
  const long = patchAnswer({}, [{ entry: { name: 'mesh.vertices', type: 'f32', count: 6, width: 3, rows: 1, literal: 0 },
    words: [2, 3] }]);
  assert.throws(() => decodeBinaryAnswer(long, previous), BinaryAnswerError); // source rows out of range
  // Hostile layouts are BinaryAnswerErrors, never a RangeError from an allocation: a count the runs cannot give
  // (3e12 values from one run of at most 4 rows), a ref to no array of this answer, a width that does not divide the
  // previous array (12 values in rows of 5).
  const huge = patchAnswer({}, [{ entry: { name: 'mesh.vertices', type: 'f32', count: 3e12, width: 3, rows: 1,
    literal: 0 }, words: [1, 0] }]);
  assert.throws(() => decodeBinaryAnswer(huge, previous), BinaryAnswerError);
  const noRef = patchAnswer({}, [{ entry: { name: 'mesh.hexes', type: 'u32', count: 4, width: 2, rows: 1, literal: 0,
    ref: 'mesh.nothing', ref_columns: 2 }, words: [2, 0] }]);
  assert.throws(() => decodeBinaryAnswer(noRef, previous), BinaryAnswerError);
  const ragged = patchAnswer({}, [{ entry: { name: 'mesh.vertices', type: 'f32', count: 10, width: 5, rows: 1,
    literal: 0 }, words: [2, 0] }]);
  assert.throws(() => decodeBinaryAnswer(ragged, previous), BinaryAnswerError);
});
