// Decoding the studio's binary answers (docs/studio.md, "Binary answers"; written by apps/studio/binary_answer.cpp):
//   "MHXB", uint32 version 1, uint32 H, H bytes of JSON header (space-padded to a multiple of 4), then the arrays of
//   header.arrays = [{name, type: 'f32' | 'u32', count}, ...] in order, little-endian, 4 bytes per value.
// The result is the header object with each array stored at its dotted name ("mesh.vertices" -> r.mesh.vertices) as
// a Float32Array / Uint32Array (views on the buffer when the platform is little-endian, copies otherwise), so that
// it has the shape of the JSON answer.
// A patch answer (an editing session's, docs/studio.md "Sessions and deltas") has entries with "patch": M: its data
// is M uint32 value indices then the M new values, applied to a copy of the same array of `previous` (the decoded
// answer it patches: header.patch_of is its revision); an array with M = 0 is previous's own (arrays are never
// modified after decoding).
// A row patch (entries with "rows": K, "width": W, "literal": L, and "ref", "ref_columns": R when the first R values of
// a row are row numbers of the earlier array "ref"): K runs of two uint32 (length, source: the first row of the
// previous array copied, 0xFFFFFFFF for literal rows), then the L literal rows. A copied row's first R values are
// translated: v -> the last new row copied from row v of "ref" when "ref" was row-patched itself (0xFFFFFFFF when
// none was), v otherwise (an edit that renumbers the mesh: every later row shifts).

export class BinaryAnswerError extends Error {}

const littleEndian = new Uint8Array(new Uint32Array([1]).buffer)[0] === 1;

export function decodeBinaryAnswer(buffer, previous = null) {
  if (!(buffer instanceof ArrayBuffer)) throw new BinaryAnswerError('binary answer: expected an ArrayBuffer');
  const dv = new DataView(buffer);
  const magic = buffer.byteLength >= 12 ? String.fromCharCode(...new Uint8Array(buffer, 0, 4)) : '';
  if (magic !== 'MHXB') throw new BinaryAnswerError('binary answer: no MHXB magic');
  const version = dv.getUint32(4, true);
  if (version !== 1) throw new BinaryAnswerError(`binary answer: unknown version ${version}`);
  const h = dv.getUint32(8, true);
  if (h % 4 !== 0 || 12 + h > buffer.byteLength) throw new BinaryAnswerError(`binary answer: header size ${h}`);
  const header = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 12, h)));
  if (!header || !Array.isArray(header.arrays)) throw new BinaryAnswerError('binary answer: header without "arrays"');
  let at = 12 + h;
  const get = (o, path) => { for (const k of path) o = o?.[k]; return o; };
  const rowMaps = new Map(); // name of a row-patched array -> Uint32Array: previous row -> new row
  const seen = new Set(); // the arrays decoded so far (a row patch's ref must be one of them)
  for (const a of header.arrays) {
    const n = a.count;
    const path = String(a.name).split('.');
    if (a.rows !== undefined) {
      const arr = readRowPatch(dv, at, a, get(previous, path), rowMaps, seen);
      seen.add(a.name);
      at += 8 * a.rows + 4 * a.width * a.literal;
      let o = header;
      for (const k of path.slice(0, -1)) o = o[k] ??= {};
      o[path[path.length - 1]] = arr;
      continue;
    }
    if (a.patch !== undefined) {
      const m = a.patch, old = get(previous, path);
      if (!Number.isInteger(m) || m < 0 || at + 8 * m > buffer.byteLength)
        throw new BinaryAnswerError(`binary answer: patch of ${a.name} runs past the end`);
      if (!old || old.length !== n) throw new BinaryAnswerError(`binary answer: patch of ${a.name} without its previous array`);
      let arr = old;
      if (m > 0) {
        arr = a.type === 'enum' ? old.slice() : new old.constructor(old);
        for (let k = 0; k < m; k++) {
          const i = dv.getUint32(at + 4 * k, true), v = at + 4 * (m + k);
          if (i >= n) throw new BinaryAnswerError(`binary answer: patch index ${i} in ${a.name}`);
          if (a.type === 'f32') arr[i] = dv.getFloat32(v, true);
          else if (a.type === 'u32') arr[i] = dv.getUint32(v, true);
          else if (a.type === 'enum') {
            const code = dv.getUint32(v, true);
            if (!Array.isArray(a.names) || code >= a.names.length) throw new BinaryAnswerError(`binary answer: enum code ${code} in ${a.name}`);
            arr[i] = a.names[code];
          } else throw new BinaryAnswerError(`binary answer: array type ${a.type}`);
        }
      }
      at += 8 * m;
      let o = header;
      for (const k of path.slice(0, -1)) o = o[k] ??= {};
      o[path[path.length - 1]] = arr;
      seen.add(a.name);
      continue;
    }
    if (!Number.isInteger(n) || n < 0 || at + 4 * n > buffer.byteLength)
      throw new BinaryAnswerError(`binary answer: array ${a.name} runs past the end`);
    let arr;
    if (a.type === 'f32') {
      if (littleEndian) arr = new Float32Array(buffer, at, n);
      else { arr = new Float32Array(n); for (let i = 0; i < n; i++) arr[i] = dv.getFloat32(at + 4 * i, true); }
    } else if (a.type === 'u32') {
      if (littleEndian) arr = new Uint32Array(buffer, at, n);
      else { arr = new Uint32Array(n); for (let i = 0; i < n; i++) arr[i] = dv.getUint32(at + 4 * i, true); }
    } else if (a.type === 'enum') {
      // Strings from a few names: each value the uint32 index of its string in a.names.
      const names = a.names;
      if (!Array.isArray(names)) throw new BinaryAnswerError(`binary answer: enum array ${a.name} without names`);
      arr = new Array(n);
      for (let i = 0; i < n; i++) {
        const code = dv.getUint32(at + 4 * i, true);
        if (code >= names.length) throw new BinaryAnswerError(`binary answer: enum code ${code} in ${a.name}`);
        arr[i] = names[code];
      }
    } else throw new BinaryAnswerError(`binary answer: array type ${a.type}`);
    at += 4 * n;
    let o = header;
    for (const k of path.slice(0, -1)) o = o[k] ??= {};
    o[path[path.length - 1]] = arr;
    seen.add(a.name);
  }
  if (at !== buffer.byteLength) throw new BinaryAnswerError(`binary answer: ${buffer.byteLength - at} bytes after the last array`);
  return header;
}

const NO_ROW = 0xffffffff;

function readRowPatch(dv, at, a, old, rowMaps, seen) {
  const { count: n, width: w, rows: k, literal: lit } = a;
  const r = a.ref !== undefined ? a.ref_columns : 0;
  const reals = a.type === 'f32';
  const fail = (what) => { throw new BinaryAnswerError(`binary answer: row patch of ${a.name}: ${what}`); };
  if (!reals && a.type !== 'u32') fail(`type ${a.type}`);
  if (![n, w, k, lit, r].every((x) => Number.isInteger(x) && x >= 0) || w === 0 || n % w || r > w || (reals && r))
    fail('layout');
  if (at + 8 * k + 4 * w * lit > dv.byteLength) fail('runs past the end');
  if (!old || !(reals ? old instanceof Float32Array : old instanceof Uint32Array)) fail('no previous array');
  if (r && !rowMaps.has(a.ref) && !seen.has(a.ref)) fail(`ref ${a.ref}`);
  const ref = r ? rowMaps.get(a.ref) : undefined; // undefined: row numbers stay as they are
  if (old.length % w) fail('previous array not whole rows');
  const oldRows = old.length / w;
  // Each run copies at most oldRows rows, literal rows are given: more rows cannot be (checked before allocating).
  if (n / w > lit + k * oldRows) fail('more rows than the runs can give');
  const map = new Uint32Array(oldRows).fill(NO_ROW);
  const arr = reals ? new Float32Array(n) : new Uint32Array(n);
  let row = 0, literal = 0;
  const literalAt = at + 8 * k;
  for (let run = 0; run < k; run++) {
    const len = dv.getUint32(at + 8 * run, true), src = dv.getUint32(at + 8 * run + 4, true);
    if (len > n / w - row) fail('runs longer than the array');
    if (src === NO_ROW) {
      if (literal + len > lit) fail('more literal rows than given');
      const from = literalAt + 4 * w * literal;
      for (let x = 0; x < len * w; x++)
        arr[row * w + x] = reals ? dv.getFloat32(from + 4 * x, true) : dv.getUint32(from + 4 * x, true);
      literal += len;
      row += len;
      continue;
    }
    if (src + len > oldRows) fail('source row out of range');
    arr.set(old.subarray(src * w, (src + len) * w), row * w);
    for (let j = 0; j < len; j++) {
      map[src + j] = row + j;
      if (ref)
        for (let c = 0; c < r; c++) {
          const i = (row + j) * w + c, v = arr[i];
          arr[i] = v < ref.length ? ref[v] : NO_ROW;
        }
    }
    row += len;
  }
  if (row !== n / w || literal !== lit) fail('rows do not add up');
  rowMaps.set(a.name, map);
  return arr;
}

// The encoder, for tests and scripts (the server writes the same bytes): header object + [{name, type, values}]
// (an enum array: {name, type: 'enum', names, values: codes}).
export function encodeBinaryAnswer(header, arrays) {
  const list = arrays.map((a) => ({ name: a.name, type: a.type, count: a.values.length,
    ...(a.type === 'enum' ? { names: a.names } : {}) }));
  let text = JSON.stringify({ ...header, arrays: list });
  let bytes = new TextEncoder().encode(text);
  while (bytes.length % 4) { text += ' '; bytes = new TextEncoder().encode(text); }
  const total = 12 + bytes.length + 4 * list.reduce((s, a) => s + a.count, 0);
  const buf = new ArrayBuffer(total);
  const dv = new DataView(buf);
  new Uint8Array(buf, 0, 4).set([0x4d, 0x48, 0x58, 0x42]);
  dv.setUint32(4, 1, true);
  dv.setUint32(8, bytes.length, true);
  new Uint8Array(buf, 12, bytes.length).set(bytes);
  let at = 12 + bytes.length;
  for (const a of arrays)
    for (const x of a.values) {
      if (a.type === 'f32') dv.setFloat32(at, x, true); else dv.setUint32(at, x, true);
      at += 4;
    }
  return buf;
}
