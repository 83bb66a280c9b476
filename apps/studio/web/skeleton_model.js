// The studio's skeleton model and every edit operation, as pure functions over plain arrays.
//
// A skeleton is {points: [[x,y,z],...], radii: [] or [r per point], edges: [[a,b],...], faces: [[a,b,c,d],...]}
// with 0-based indices (the Skeleton JSON of docs/studio.md). Radii are all-or-nothing, as in the file formats.
// Every operation takes a skeleton and returns a NEW skeleton (the input is never modified), so undo / redo is a
// stack of states (UndoStack) and "undo restores the identical skeleton" holds by construction.
// Operations throw ModelError with a message naming the element when they cannot apply.

export class ModelError extends Error {}

const EPS = 1e-9;

export function emptySkeleton() {
  return { points: [], radii: [], edges: [], faces: [] };
}

// A deep copy of a Skeleton JSON (from the server or a file), validated; missing fields become empty.
export function fromJson(json) {
  if (!json) return emptySkeleton();
  const s = {
    points: (json.points || []).map((p) => [Number(p[0]), Number(p[1]), Number(p[2])]),
    radii: (json.radii || []).map(Number),
    edges: (json.edges || []).map((e) => [e[0] | 0, e[1] | 0]),
    faces: (json.faces || []).map((f) => f.map((i) => i | 0)),
  };
  if (s.radii.length !== 0 && s.radii.length !== s.points.length)
    throw new ModelError(`skeleton has ${s.radii.length} radii for ${s.points.length} vertices`);
  const n = s.points.length;
  for (const e of s.edges)
    if (!(e[0] >= 0 && e[0] < n && e[1] >= 0 && e[1] < n)) throw new ModelError(`edge ${e} names a missing vertex`);
  return withFaceSides(s);
}

export function clone(s) {
  return {
    points: s.points.map((p) => p.slice()),
    radii: s.radii.slice(),
    edges: s.edges.map((e) => e.slice()),
    faces: s.faces.map((f) => f.slice()),
  };
}

export function counts(s) {
  return { V: s.points.length, E: s.edges.length, F: s.faces.length };
}

// OBJ text as the server reads it (docs/formats.md): v lines, radius comments, every edge as `l a b`, then faces.
export function toObj(s) {
  const num = (x) => (Object.is(x, -0) ? '0' : String(x));
  const out = ['# mesohex studio skeleton'];
  for (const p of s.points) out.push(`v ${num(p[0])} ${num(p[1])} ${num(p[2])}`);
  s.radii.forEach((r, i) => out.push(`# mesohex radius ${i + 1} ${num(r)}`));
  for (const e of s.edges) out.push(`l ${e[0] + 1} ${e[1] + 1}`);
  for (const f of s.faces) out.push('f ' + f.map((i) => i + 1).join(' '));
  return out.join('\n') + '\n';
}

// The binary skeleton the server reads with format=mhsk (docs/formats.md, "Binary skeleton"; the same skeleton as
// toObj's text, about a quarter of its size, no number printing or parsing): little-endian, "MHSK", uint32 version 1,
// V, R (0 or V), E, F, S (sum of face sizes), 0; float64 points[3V], radii[R]; uint32 edges[2E], face sizes[F],
// face vertices[S]. -0 is written as 0, as toObj prints it, so both uploads give the server the same numbers.
export function toBinary(s) {
  const V = s.points.length, R = s.radii.length, E = s.edges.length, F = s.faces.length;
  let S = 0;
  for (const f of s.faces) S += f.length;
  const buffer = new ArrayBuffer(32 + 24 * V + 8 * R + 8 * E + 4 * F + 4 * S);
  const dv = new DataView(buffer);
  'MHSK'.split('').forEach((c, i) => dv.setUint8(i, c.charCodeAt(0)));
  [1, V, R, E, F, S, 0].forEach((x, i) => dv.setUint32(4 + 4 * i, x, true));
  let at = 32;
  const f64 = (x) => { dv.setFloat64(at, x === 0 ? 0 : x, true); at += 8; };
  const u32 = (x) => { dv.setUint32(at, x, true); at += 4; };
  for (const p of s.points) { f64(p[0]); f64(p[1]); f64(p[2]); }
  for (const r of s.radii) f64(r);
  for (const e of s.edges) { u32(e[0]); u32(e[1]); }
  for (const f of s.faces) u32(f.length);
  for (const f of s.faces) for (const v of f) u32(v);
  return buffer;
}

// The MHSD delta from `base` to `s` (docs/formats.md): the vertices whose position or radius changed, with their new
// values, for a server session holding `base` (/api/mesh?format=delta). null when the two differ in anything else
// (vertex count, radii present or not, edges, faces): then the whole skeleton goes (toBinary).
export function toDelta(base, s) {
  const V = s.points.length;
  if (!base || base.points.length !== V || base.radii.length !== s.radii.length || base.edges.length !== s.edges.length ||
    base.faces.length !== s.faces.length) return null;
  for (let i = 0; i < s.edges.length; i++) {
    const a = base.edges[i], b = s.edges[i];
    if (a[0] !== b[0] || a[1] !== b[1]) return null;
  }
  for (let i = 0; i < s.faces.length; i++) {
    const a = base.faces[i], b = s.faces[i];
    if (a.length !== b.length) return null;
    for (let k = 0; k < a.length; k++) if (a[k] !== b[k]) return null;
  }
  const radii = s.radii.length > 0;
  const moved = [];
  for (let v = 0; v < V; v++) {
    const p = base.points[v], q = s.points[v];
    if (p[0] !== q[0] || p[1] !== q[1] || p[2] !== q[2] || (radii && base.radii[v] !== s.radii[v])) moved.push(v);
  }
  const K = moved.length;
  const buffer = new ArrayBuffer(20 + 4 * K + 24 * K + (radii ? 8 * K : 0));
  const dv = new DataView(buffer);
  'MHSD'.split('').forEach((c, i) => dv.setUint8(i, c.charCodeAt(0)));
  [1, V, K, radii ? 1 : 0].forEach((x, i) => dv.setUint32(4 + 4 * i, x, true));
  let at = 20;
  const f64 = (x) => { dv.setFloat64(at, x === 0 ? 0 : x, true); at += 8; };
  for (const v of moved) { dv.setUint32(at, v, true); at += 4; }
  for (const v of moved) { const q = s.points[v]; f64(q[0]); f64(q[1]); f64(q[2]); }
  if (radii) for (const v of moved) f64(s.radii[v]);
  return buffer;
}

// ---- queries ----

export function edgeKey(a, b) {
  return a < b ? `${a},${b}` : `${b},${a}`;
}

export function findEdge(s, a, b) {
  const k = edgeKey(a, b);
  return s.edges.findIndex((e) => edgeKey(e[0], e[1]) === k);
}

// Indices of the faces that have a-b as a side.
export function facesOfEdge(s, a, b) {
  const out = [];
  s.faces.forEach((f, fi) => {
    for (let i = 0; i < f.length; i++) {
      const u = f[i], v = f[(i + 1) % f.length];
      if ((u === a && v === b) || (u === b && v === a)) { out.push(fi); break; }
    }
  });
  return out;
}

export function neighbours(s, v) {
  const out = [];
  for (const e of s.edges) {
    if (e[0] === v) out.push(e[1]);
    else if (e[1] === v) out.push(e[0]);
  }
  return out;
}

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const scale = (a, k) => [a[0] * k, a[1] * k, a[2] * k];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);

function checkVertex(s, v, what = 'vertex') {
  if (!Number.isInteger(v) || v < 0 || v >= s.points.length) throw new ModelError(`${what} ${v} does not exist`);
}

function checkPoint(p) {
  if (!Array.isArray(p) || p.length !== 3 || !p.every(Number.isFinite))
    throw new ModelError(`not a finite 3D point: ${JSON.stringify(p)}`);
}

// Every side of every face is an edge (appended in face order when missing).
function withFaceSides(s) {
  const have = new Set(s.edges.map((e) => edgeKey(e[0], e[1])));
  for (const f of s.faces)
    for (let i = 0; i < f.length; i++) {
      const a = f[i], b = f[(i + 1) % f.length];
      const k = edgeKey(a, b);
      if (!have.has(k)) { have.add(k); s.edges.push([a, b]); }
    }
  return s;
}

// ---- operations (each returns a new skeleton; some also return the indices they created) ----

// A new isolated vertex (radius r, or the mean radius when the skeleton has radii and r is not given).
export function addVertex(s, p, r) {
  checkPoint(p);
  const t = clone(s);
  t.points.push(p.slice());
  if (t.radii.length || (r !== undefined && s.points.length === 0)) t.radii.push(r ?? meanRadius(s));
  return { skeleton: t, vertex: t.points.length - 1 };
}

function meanRadius(s) {
  return s.radii.length ? s.radii.reduce((a, b) => a + b, 0) / s.radii.length : 1;
}

// Extrude vertex v into a branch: a new vertex at v + offset joined to v by an edge (radius copied from v).
export function extrudeVertex(s, v, offset) {
  checkVertex(s, v);
  checkPoint(offset);
  const t = clone(s);
  t.points.push(add(s.points[v], offset));
  if (t.radii.length) t.radii.push(s.radii[v]);
  const w = t.points.length - 1;
  t.edges.push([v, w]);
  return { skeleton: t, vertex: w };
}

// Extrude the edge a-b (a leaflet boundary edge, or a branch edge) into a new quad a, b, b+offset, a+offset.
// An edge shared by two faces (leaflet interior) cannot be extruded.
export function extrudeEdge(s, a, b, offset) {
  checkVertex(s, a);
  checkVertex(s, b);
  checkPoint(offset);
  if (findEdge(s, a, b) < 0) throw new ModelError(`${a}-${b} is not an edge`);
  const nf = facesOfEdge(s, a, b);
  if (nf.length >= 2) throw new ModelError(`edge ${a}-${b} is inside a leaflet (${nf.length} faces): not extrudable`);
  const t = clone(s);
  // Keep the new quad's orientation consistent with the face it extends: that face runs a->b, the new one b->a.
  let [u, v] = [a, b];
  if (nf.length === 1) {
    const f = s.faces[nf[0]];
    const i = f.indexOf(a);
    if (f[(i + 1) % f.length] === b) [u, v] = [b, a];
  }
  const u2 = t.points.push(add(s.points[u], offset)) - 1;
  const v2 = t.points.push(add(s.points[v], offset)) - 1;
  if (t.radii.length) t.radii.push(s.radii[u], s.radii[v]);
  t.edges.push([v, v2], [v2, u2], [u2, u]);
  t.faces.push([u, v, v2, u2]);
  return { skeleton: t, vertices: [u2, v2] };
}

// The edges among the vertices vs (both ends in vs) ordered along their chains: a path or a closed loop (every vertex
// on at most 2 of them). Returns [[u, v], ...] with each chain walked in one direction, or throws.
export function chainEdges(s, vs) {
  const inSel = new Set(vs);
  const adj = new Map(vs.map((v) => [v, []]));
  for (const [a, b] of s.edges)
    if (a !== b && inSel.has(a) && inSel.has(b)) { adj.get(a).push(b); adj.get(b).push(a); }
  for (const v of vs) {
    if (adj.get(v).length === 0) throw new ModelError(`vertex ${v} has no edge to another selected vertex`);
    if (adj.get(v).length > 2) throw new ModelError(`vertex ${v} has ${adj.get(v).length} selected edges: not a chain`);
  }
  const out = [];
  const used = new Set();
  // Open chains from their ends first, then the closed loops.
  const starts = [...vs.filter((v) => adj.get(v).length === 1), ...vs];
  for (const v0 of starts) {
    let u = v0;
    for (;;) {
      const w = adj.get(u).find((x) => !used.has(edgeKey(u, x)));
      if (w === undefined) break;
      used.add(edgeKey(u, w));
      out.push([u, w]);
      u = w;
    }
  }
  return out;
}

// Extrude a chain of edges (a path or a closed loop of branch edges or leaflet boundary edges: the selected vertices
// vs and the edges among them) into a strip of quads: each vertex gets a copy at p + offset (radius copied), each edge
// a quad. Quads follow the walk of the chain, turned to agree with the face an edge already borders.
export function extrudeChain(s, vs, offset) {
  vs.forEach((v) => checkVertex(s, v));
  checkPoint(offset);
  if (new Set(vs).size !== vs.length || vs.length < 2) throw new ModelError('extrude a chain: select 2 or more vertices');
  const chain = chainEdges(s, vs);
  for (const [a, b] of chain)
    if (facesOfEdge(s, a, b).length >= 2) throw new ModelError(`edge ${a}-${b} is inside a leaflet: not extrudable`);
  // Turn the whole walk when its first edge that borders a face runs along that face (the new quad runs against it).
  const faced = chain.find(([a, b]) => facesOfEdge(s, a, b).length === 1);
  let flip = false;
  if (faced) {
    const f = s.faces[facesOfEdge(s, faced[0], faced[1])[0]];
    const i = f.indexOf(faced[0]);
    flip = f[(i + 1) % f.length] === faced[1];
  }
  const t = clone(s);
  const copy = new Map();
  for (const v of vs) {
    copy.set(v, t.points.push(add(s.points[v], offset)) - 1);
    if (t.radii.length) t.radii.push(s.radii[v]);
  }
  for (const v of vs) t.edges.push([v, copy.get(v)]);
  for (const [a, b] of chain) {
    const [u, v] = flip ? [b, a] : [a, b];
    t.edges.push([copy.get(u), copy.get(v)]);
    t.faces.push([u, v, copy.get(v), copy.get(u)]);
  }
  return { skeleton: t, vertices: vs.map((v) => copy.get(v)) };
}

// Order 4 vertices into a quad cycle: along existing edges when they form a path/cycle, else by angle around their
// centroid in their best plane.
export function quadOrder(s, vs) {
  if (vs.length !== 4 || new Set(vs).size !== 4) throw new ModelError('fill needs 4 distinct vertices');
  vs.forEach((v) => checkVertex(s, v));
  const c = scale(vs.reduce((acc, v) => add(acc, s.points[v]), [0, 0, 0]), 0.25);
  const d = vs.map((v) => sub(s.points[v], c));
  // Plane normal: the largest cross product of the diagonals' candidates.
  let n = [0, 0, 0];
  for (let i = 0; i < 4; i++)
    for (let j = i + 1; j < 4; j++) {
      const x = cross(d[i], d[j]);
      if (dot(x, x) > dot(n, n)) n = dot(x, n) < 0 ? scale(x, -1) : x;
    }
  if (dot(n, n) < EPS * EPS) throw new ModelError('the 4 vertices are collinear: no quad');
  const e1 = d.find((x) => dot(x, x) > EPS) || [1, 0, 0];
  const e2 = cross(n, e1);
  const ang = vs.map((v, i) => Math.atan2(dot(d[i], e2), dot(d[i], e1)));
  const byAngle = vs.map((v, i) => i).sort((i, j) => ang[i] - ang[j]).map((i) => vs[i]);
  // Prefer the cyclic order that uses the most existing edges among the three possible ones.
  const cands = [byAngle, [vs[0], vs[1], vs[2], vs[3]], [vs[0], vs[1], vs[3], vs[2]], [vs[0], vs[2], vs[1], vs[3]]];
  const score = (q) => q.reduce((acc, v, i) => acc + (findEdge(s, v, q[(i + 1) % 4]) >= 0 ? 1 : 0), 0);
  let best = cands[0];
  for (const q of cands.slice(1)) if (score(q) > score(best)) best = q;
  return best;
}

// Fill a quad face from 4 vertices (missing sides become edges). Refused when that face already exists or a side
// would get a third face.
export function fillQuad(s, vs) {
  const q = quadOrder(s, vs);
  const key = [...q].sort((a, b) => a - b).join(',');
  if (s.faces.some((f) => [...f].sort((a, b) => a - b).join(',') === key)) throw new ModelError('that face exists');
  for (let i = 0; i < 4; i++)
    if (facesOfEdge(s, q[i], q[(i + 1) % 4]).length >= 2)
      throw new ModelError(`edge ${q[i]}-${q[(i + 1) % 4]} already has two faces`);
  const t = clone(s);
  t.faces.push(q);
  return { skeleton: withFaceSides(t), face: t.faces.length - 1 };
}

// Connect two vertices with an edge.
export function connect(s, a, b) {
  checkVertex(s, a);
  checkVertex(s, b);
  if (a === b) throw new ModelError('cannot connect a vertex to itself');
  if (findEdge(s, a, b) >= 0) throw new ModelError(`${a}-${b} is already an edge`);
  const t = clone(s);
  t.edges.push([a, b]);
  return { skeleton: t, edge: t.edges.length - 1 };
}

// Split the edge a-b at its middle. When the edge is a side of quads, the whole strip of quads across it is split
// (each quad into two, its opposite side split too) so that faces stay quads; a triangle is split into two.
export function splitEdge(s, a, b) {
  checkVertex(s, a);
  checkVertex(s, b);
  if (findEdge(s, a, b) < 0) throw new ModelError(`${a}-${b} is not an edge`);
  const t = clone(s);
  const mid = new Map(); // edge key -> new vertex
  const splitOne = (u, v) => {
    const k = edgeKey(u, v);
    if (mid.has(k)) return mid.get(k);
    const m = t.points.push(scale(add(t.points[u], t.points[v]), 0.5)) - 1;
    if (t.radii.length) t.radii.push(0.5 * (t.radii[u] + t.radii[v]));
    const ei = findEdge(t, u, v);
    t.edges[ei] = [u, m];
    t.edges.push([m, v]);
    mid.set(k, m);
    return m;
  };
  const done = new Set();
  const queue = [[a, b]];
  splitOne(a, b);
  while (queue.length) {
    const [u, v] = queue.shift();
    for (let fi = 0; fi < t.faces.length; fi++) {
      if (done.has(fi)) continue;
      const f = t.faces[fi];
      const n = f.length;
      const i = f.findIndex((x, j) => (x === u && f[(j + 1) % n] === v) || (x === v && f[(j + 1) % n] === u));
      if (i < 0) continue;
      done.add(fi);
      const p = f[i], q = f[(i + 1) % n];
      const m = mid.get(edgeKey(u, v));
      if (n === 4) {
        const r = f[(i + 2) % 4], w = f[(i + 3) % 4];
        const isNew = !mid.has(edgeKey(r, w));
        const m2 = splitOne(r, w);
        t.faces[fi] = [p, m, m2, w];
        done.add(t.faces.push([m, q, r, m2]) - 1);
        t.edges.push([m, m2]);
        if (isNew) queue.push([r, w]);
      } else if (n === 3) {
        const r = f[(i + 2) % 3];
        t.faces[fi] = [p, m, r];
        done.add(t.faces.push([m, q, r]) - 1);
        t.edges.push([m, r]);
      } else {
        // Other polygons: insert the vertex into the cycle.
        t.faces[fi] = [...f.slice(0, i + 1), m, ...f.slice(i + 1)];
      }
    }
  }
  return { skeleton: t, vertex: mid.get(edgeKey(a, b)), created: [...mid.values()] };
}

// Remove vertices (with their edges and faces) and edges (with their faces); the rest is renumbered in order.
// Returns the map old vertex -> new vertex (-1 when removed).
export function deleteElements(s, { vertices = [], edges = [], faces = [] } = {}) {
  vertices.forEach((v) => checkVertex(s, v));
  const goneV = new Set(vertices);
  const goneE = new Set(edges.map(([a, b]) => edgeKey(a, b)));
  const goneF = new Set(faces);
  const map = [];
  let k = 0;
  for (let i = 0; i < s.points.length; i++) map.push(goneV.has(i) ? -1 : k++);
  const t = emptySkeleton();
  s.points.forEach((p, i) => { if (map[i] >= 0) t.points.push(p.slice()); });
  if (s.radii.length) s.radii.forEach((r, i) => { if (map[i] >= 0) t.radii.push(r); });
  for (const e of s.edges)
    if (map[e[0]] >= 0 && map[e[1]] >= 0 && !goneE.has(edgeKey(e[0], e[1]))) t.edges.push([map[e[0]], map[e[1]]]);
  s.faces.forEach((f, fi) => {
    if (goneF.has(fi) || f.some((v) => map[v] < 0)) return;
    if (f.some((v, i) => goneE.has(edgeKey(v, f[(i + 1) % f.length])))) return;
    t.faces.push(f.map((v) => map[v]));
  });
  return { skeleton: t, map };
}

// Merge vertex `remove` into vertex `keep` (placed at their midpoint, mean radius): edges and faces of `remove` move
// to `keep`; edges that become loops or duplicates are dropped, faces left with < 3 distinct vertices are dropped.
export function mergeVertices(s, keep, remove) {
  checkVertex(s, keep);
  checkVertex(s, remove);
  if (keep === remove) throw new ModelError('cannot merge a vertex with itself');
  const t = clone(s);
  t.points[keep] = scale(add(s.points[keep], s.points[remove]), 0.5);
  if (t.radii.length) t.radii[keep] = 0.5 * (s.radii[keep] + s.radii[remove]);
  const ren = (v) => (v === remove ? keep : v);
  const seen = new Set();
  t.edges = [];
  for (const e of s.edges) {
    const a = ren(e[0]), b = ren(e[1]);
    if (a === b || seen.has(edgeKey(a, b))) continue;
    seen.add(edgeKey(a, b));
    t.edges.push([a, b]);
  }
  t.faces = [];
  for (const f of s.faces) {
    const g = f.map(ren).filter((v, i, arr) => v !== arr[(i + 1) % arr.length]);
    if (new Set(g).size >= 3 && new Set(g).size === g.length) t.faces.push(g);
  }
  const r = deleteElements(t, { vertices: [remove] });
  return { skeleton: r.skeleton, vertex: r.map[keep], map: r.map.map((m, i) => (i === remove ? r.map[keep] : m)) };
}

// Move vertices to new positions (parallel arrays).
export function moveVertices(s, vs, positions) {
  vs.forEach((v) => checkVertex(s, v));
  positions.forEach(checkPoint);
  const t = clone(s);
  vs.forEach((v, i) => { t.points[v] = positions[i].slice(); });
  return { skeleton: t };
}

// Translate vertices by one offset.
export function translateVertices(s, vs, offset) {
  checkPoint(offset);
  return moveVertices(s, vs, vs.map((v) => add(s.points[v], offset)));
}

// Set the radius of vertices. A skeleton without radii gets `r` on every vertex first (radii are all-or-nothing).
export function setRadius(s, vs, r) {
  if (!(Number.isFinite(r) && r > 0)) throw new ModelError(`a radius must be > 0 (got ${r})`);
  vs.forEach((v) => checkVertex(s, v));
  const t = clone(s);
  if (!t.radii.length) t.radii = s.points.map(() => r);
  for (const v of vs) t.radii[v] = r;
  return { skeleton: t };
}

// Scale the radius of vertices by a factor (the brush), each weighted by w in [0,1]: r *= 1 + (factor-1) w.
export function brushRadius(s, vs, weights, factor) {
  if (!s.radii.length) throw new ModelError('the skeleton has no radii: set one or take them from the domain');
  const t = clone(s);
  vs.forEach((v, i) => {
    checkVertex(s, v);
    t.radii[v] = Math.max(1e-6, t.radii[v] * (1 + (factor - 1) * weights[i]));
  });
  return { skeleton: t };
}

// Replace all radii (e.g. "radius from the domain").
export function setAllRadii(s, radii) {
  if (radii.length !== s.points.length) throw new ModelError(`${radii.length} radii for ${s.points.length} vertices`);
  if (!radii.every((r) => Number.isFinite(r) && r > 0)) throw new ModelError('every radius must be > 0');
  const t = clone(s);
  t.radii = radii.slice();
  return { skeleton: t };
}

// ---- mirror symmetry: plane {axis: 0|1|2, c: coordinate of the plane} ----

export function mirrorPoint(p, plane) {
  const q = p.slice();
  q[plane.axis] = 2 * plane.c - p[plane.axis];
  return q;
}

export function mirrorVector(d, plane) {
  const q = d.slice();
  q[plane.axis] = -d[plane.axis];
  return q;
}

// The vertex at the mirror image of v (within tol), or -1. A vertex on the plane is its own partner.
export function mirrorPartner(s, v, plane, tol) {
  const m = mirrorPoint(s.points[v], plane);
  let best = -1, bd = tol;
  s.points.forEach((p, i) => {
    const d = dist(p, m);
    if (d <= bd) { bd = d; best = i; }
  });
  return best;
}

// Apply an edit to the selection and, when `plane` is given, the same edit to the mirror partners. Each kind is one
// undoable step (the returned skeleton). `tol` is the matching distance for partners.
export function applyEdit(s, kind, args, plane = null, tol = 1e-6) {
  const partner = (v) => (plane ? mirrorPartner(s, v, plane, tol) : -1);
  switch (kind) {
    case 'move': { // args: {vertices, offset}
      const { vertices, offset } = args;
      const vs = [], pos = [];
      const moved = new Set();
      for (const v of vertices) {
        if (moved.has(v)) continue;
        moved.add(v);
        const m = partner(v);
        let d = offset;
        if (m === v) { d = offset.slice(); d[plane.axis] = 0; } // stays on the plane
        vs.push(v); pos.push(add(s.points[v], d));
        if (m >= 0 && m !== v && !moved.has(m) && !vertices.includes(m)) {
          moved.add(m); vs.push(m); pos.push(add(s.points[m], mirrorVector(offset, plane)));
        }
      }
      return moveVertices(s, vs, pos);
    }
    case 'extrudeVertex': { // args: {vertex, offset}
      const { vertex, offset } = args;
      const m = partner(vertex);
      let r = extrudeVertex(s, vertex, offset);
      const created = [r.vertex];
      if (m >= 0) {
        const mo = mirrorVector(offset, plane);
        if (m !== vertex || dist(mo, offset) > tol) {
          r = extrudeVertex(r.skeleton, m, mo);
          created.push(r.vertex);
        }
      }
      return { skeleton: r.skeleton, created };
    }
    case 'extrudeEdge': { // args: {a, b, offset}
      const { a, b, offset } = args;
      let r = extrudeEdge(s, a, b, offset);
      const created = [...r.vertices];
      const ma = partner(a), mb = partner(b);
      if (ma >= 0 && mb >= 0 && edgeKey(ma, mb) !== edgeKey(a, b)) {
        r = extrudeEdge(r.skeleton, ma, mb, mirrorVector(offset, plane));
        created.push(...r.vertices);
      }
      return { skeleton: r.skeleton, created };
    }
    case 'extrudeChain': { // args: {vertices, offset}
      const { vertices, offset } = args;
      let r = extrudeChain(s, vertices, offset);
      const created = [...r.vertices];
      const ms = vertices.map(partner);
      const key = (q) => [...q].sort((x, y) => x - y).join(',');
      if (ms.every((m) => m >= 0) && ms.every((m) => !vertices.includes(m)) && key(ms) !== key(vertices)) {
        r = extrudeChain(r.skeleton, ms, mirrorVector(offset, plane));
        created.push(...r.vertices);
      }
      return { skeleton: r.skeleton, created };
    }
    case 'fill': { // args: {vertices: [4]}
      let r = fillQuad(s, args.vertices);
      const ms = args.vertices.map(partner);
      const key = (q) => [...q].sort((x, y) => x - y).join(',');
      if (ms.every((m) => m >= 0) && key(ms) !== key(args.vertices)) r = fillQuad(r.skeleton, ms);
      return { skeleton: r.skeleton };
    }
    case 'connect': { // args: {a, b}
      let r = connect(s, args.a, args.b);
      const ma = partner(args.a), mb = partner(args.b);
      if (ma >= 0 && mb >= 0 && ma !== mb && edgeKey(ma, mb) !== edgeKey(args.a, args.b) && findEdge(r.skeleton, ma, mb) < 0)
        r = connect(r.skeleton, ma, mb);
      return { skeleton: r.skeleton };
    }
    case 'split': { // args: {a, b}
      let r = splitEdge(s, args.a, args.b);
      const ma = partner(args.a), mb = partner(args.b);
      // Split keeps old indices, so the partners are still valid; skip when the first split already did it.
      if (ma >= 0 && mb >= 0 && ma !== mb && edgeKey(ma, mb) !== edgeKey(args.a, args.b) && findEdge(r.skeleton, ma, mb) >= 0)
        r = splitEdge(r.skeleton, ma, mb);
      return { skeleton: r.skeleton };
    }
    case 'merge': { // args: {keep, remove}
      const { keep, remove } = args;
      const mk = partner(keep), mr = partner(remove);
      let r = mergeVertices(s, keep, remove);
      if (mk >= 0 && mr >= 0 && mk !== mr && edgeKey(mk, mr) !== edgeKey(keep, remove) && mk !== remove && mr !== remove
          && mk !== keep && mr !== keep)
        r = mergeVertices(r.skeleton, r.map[mk], r.map[mr]);
      return { skeleton: r.skeleton };
    }
    case 'delete': { // args: {vertices, edges}
      const vs = new Set(args.vertices || []);
      const es = (args.edges || []).slice();
      if (plane) {
        for (const v of [...vs]) { const m = partner(v); if (m >= 0) vs.add(m); }
        for (const [a, b] of args.edges || []) {
          const ma = partner(a), mb = partner(b);
          if (ma >= 0 && mb >= 0) es.push([ma, mb]);
        }
      }
      return deleteElements(s, { vertices: [...vs], edges: es });
    }
    case 'radius': { // args: {vertices, r}
      const vs = new Set(args.vertices);
      if (plane) for (const v of args.vertices) { const m = partner(v); if (m >= 0) vs.add(m); }
      return setRadius(s, [...vs], args.r);
    }
    case 'brush': { // args: {vertices, weights, factor}
      const vs = args.vertices.slice(), ws = args.weights.slice();
      if (plane)
        args.vertices.forEach((v, i) => {
          const m = partner(v);
          if (m >= 0 && !vs.includes(m)) { vs.push(m); ws.push(args.weights[i]); }
        });
      return brushRadius(s, vs, ws, args.factor);
    }
    default:
      throw new ModelError(`unknown edit ${kind}`);
  }
}

// Unbounded undo / redo over immutable skeleton states.
export class UndoStack {
  constructor(initial = emptySkeleton()) {
    this.past = [];
    this.present = initial;
    this.future = [];
  }
  get current() { return this.present; }
  // Record a new state (the result of an edit); clears the redo list.
  push(next, label = '') {
    this.past.push({ state: this.present, label });
    this.present = next;
    this.future = [];
    return next;
  }
  canUndo() { return this.past.length > 0; }
  canRedo() { return this.future.length > 0; }
  undo() {
    if (!this.past.length) return null;
    const { state, label } = this.past.pop();
    this.future.push({ state: this.present, label });
    this.present = state;
    return this.present;
  }
  redo() {
    if (!this.future.length) return null;
    const { state, label } = this.future.pop();
    this.past.push({ state: this.present, label });
    this.present = state;
    return this.present;
  }
}
