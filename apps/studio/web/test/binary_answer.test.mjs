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
