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
  for (const a of header.arrays) {
    const n = a.count;
    const path = String(a.name).split('.');
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
  }
  if (at !== buffer.byteLength) throw new BinaryAnswerError(`binary answer: ${buffer.byteLength - at} bytes after the last array`);
  return header;
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
