// Thin wrappers over the studio server's JSON API (docs/studio.md). Every failure becomes an ApiError carrying the
// server's {code, message, where} and the HTTP status.
import { decodeBinaryAnswer } from '/app/binary_answer.js';

export class ApiError extends Error {
  constructor(status, body) {
    const e = body?.error || {};
    super(e.message || `HTTP ${status}`);
    this.status = status;
    this.code = e.code || 'Unknown';
    this.where = e.where || { kind: 'none' };
  }
}

export const clientId = 'page-' + Math.random().toString(36).slice(2, 10);

// Where the last binary request's time went (ms, from the browser's resource timing): `send` from the fetch call to
// the request leaving, `wait` from then to the answer's first byte (the server's time is in the answer), `download`
// the body, `handover` from the body received to the page having it (arrayBuffer), `decode` decoding it; `bytes` the
// body's size. null fields when the browser gives no timing.
export let lastTiming = null;
function requestTiming(path, received, decoded, bytes) {
  const url = new URL(path, location.href).href;
  const e = performance.getEntriesByName(url).pop();
  performance.clearResourceTimings(); // the buffer holds 250 entries
  if (!e || !e.responseStart) return { send: null, wait: null, download: null, handover: null, decode: decoded - received, bytes };
  return { send: e.requestStart - e.startTime, wait: e.responseStart - e.requestStart, download: e.responseEnd - e.responseStart,
    handover: received - e.responseEnd, decode: decoded - received, bytes };
}

async function call(method, path, body, { signal, type = 'text/plain', expect = 'json', previous = null } = {}) {
  const res = await fetch(path, {
    method,
    body,
    signal,
    headers: { 'Content-Type': type, 'X-Studio-Client': clientId },
  });
  if (!res.ok) {
    let b = null;
    try { b = await res.json(); } catch { /* not JSON */ }
    throw new ApiError(res.status, b);
  }
  if (expect === 'binary') {
    const buffer = await res.arrayBuffer();
    const received = performance.now();
    const answer = decodeBinaryAnswer(buffer, previous);
    lastTiming = requestTiming(path, received, performance.now(), buffer.byteLength);
    return answer;
  }
  return expect === 'text' ? res.text() : res.json();
}

export const session = () => call('GET', '/api/session');
export const mesh = (obj, stage, signal) => call('POST', `/api/mesh?stage=${stage}&format=obj`, obj, { signal });
// The same answer in binary form (float32 / uint32 typed arrays, no meshed_skeleton): what the page draws from.
// `bytes`: the skeleton as skeleton_model.toBinary writes it (format=mhsk).
export const meshBinary = (bytes, stage, signal) =>
  call('POST', `/api/mesh?stage=${stage}&format=mhsk&encoding=binary`, bytes,
    { signal, expect: 'binary', type: 'application/octet-stream' });
// The same within the page's editing session (docs/studio.md, "Sessions and deltas"): the full skeleton as revision
// `revision`, or (meshDelta) an MHSD delta (skeleton_model.toDelta) from revision `base`. A session the server does
// not hold (any more) answers 409 with code SendFullSkeleton.
// `since`: { revision, answer } the session's answer the page holds (decoded), or null: the server then answers only
// what changed since it (a patch answer, decoded against `answer`).
const sinceParam = (since) => (since ? `&since=${since.revision}` : '');
export const meshSession = (bytes, revision, since, signal) =>
  call('POST', `/api/mesh?stage=raw&format=mhsk&encoding=binary&session=${clientId}&revision=${revision}${sinceParam(since)}`,
    bytes, { signal, expect: 'binary', type: 'application/octet-stream', previous: since?.answer });
export const meshDelta = (bytes, base, revision, since, signal) =>
  call('POST', `/api/mesh?stage=raw&format=delta&encoding=binary&session=${clientId}&base=${base}&revision=${revision}${sinceParam(since)}`,
    bytes, { signal, expect: 'binary', type: 'application/octet-stream', previous: since?.answer });
export const analyze = (obj, signal) => call('POST', '/api/analyze?format=obj', obj, { signal });
export const autoSkeleton = () => call('POST', '/api/auto-skeleton', '');
export const importMa = (text) => call('POST', '/api/import?format=ma', text);
export const parse = (text, format) => call('POST', `/api/parse?format=${encodeURIComponent(format)}`, text);
export const serialize = (skeletonJson, format) =>
  call('POST', `/api/serialize?format=${format}`, JSON.stringify(skeletonJson), { type: 'application/json', expect: 'text' });
export const radiusFromDomain = (bytes) =>
  call('POST', '/api/radius-from-domain?format=mhsk', bytes, { type: 'application/octet-stream' });
export const snapMedial = (points) =>
  call('POST', '/api/snap-medial', JSON.stringify({ points }), { type: 'application/json' });
export const save = (text, format) => call('POST', `/api/save?format=${format}`, text, { expect: 'text' });
export const startJob = (bytes) =>
  call('POST', '/api/jobs?format=mhsk', bytes, { type: 'application/octet-stream' });
export const job = (id) => call('GET', `/api/jobs/${id}`);
export const cancelJob = (id) => call('DELETE', `/api/jobs/${id}`).catch(() => null);
