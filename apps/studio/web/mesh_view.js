// Pure helpers that turn the server's flat mesh arrays into drawable arrays (no three.js here, so node can test
// them): visible faces of a (clipped) hex set, shrunk hexes, colour maps, the scaled-Jacobian histogram.

// The 6 faces of a VTK-ordered hex (0-3 bottom, 4-7 top), outward for a positively oriented hex.
export const HEX_FACES = [
  [0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7],
];

export function hexCount(mesh) {
  return Math.floor((mesh?.hexes?.length || 0) / 8);
}

export function hexCentroids(mesh) {
  const n = hexCount(mesh), V = mesh.vertices, H = mesh.hexes;
  const c = new Float64Array(3 * n);
  for (let h = 0; h < n; h++)
    for (let k = 0; k < 8; k++) {
      const v = H[8 * h + k];
      c[3 * h] += V[3 * v] / 8; c[3 * h + 1] += V[3 * v + 1] / 8; c[3 * h + 2] += V[3 * v + 2] / 8;
    }
  return c;
}

// Faces of the kept hexes that are not shared by two kept hexes: the boundary of the kept set (its outer skin and,
// when some hexes are clipped away, the cut). Returns {quads: [a,b,c,d,...] flat, owner: [hex per quad]}.
// keep: null (all hexes) or a predicate on the hex index. Faces are matched by their sorted corners, chained per
// smallest corner (typed arrays, no string keys: ~10k hexes in a few ms).
// The 4 corner ids of face `face` (local corner indices) of hex h, sorted ascending into out (a sorting network).
function sortFaceCorners(H, h, face, out) {
  let a = H[8 * h + face[0]], b = H[8 * h + face[1]], c = H[8 * h + face[2]], d = H[8 * h + face[3]], x;
  if (a > b) { x = a; a = b; b = x; }
  if (c > d) { x = c; c = d; d = x; }
  if (a > c) { x = a; a = c; c = x; }
  if (b > d) { x = b; b = d; d = x; }
  if (b > c) { x = b; b = c; c = x; }
  out[0] = a; out[1] = b; out[2] = c; out[3] = d;
}

export function visibleQuads(mesh, keep = null) {
  const n = hexCount(mesh), H = mesh.hexes;
  const nv = mesh.vertices.length / 3;
  const kept = [];
  for (let h = 0; h < n; h++) if (!keep || keep(h)) kept.push(h);
  const nf = 6 * kept.length;
  const sorted = new Int32Array(4 * nf), q = new Int32Array(4);
  const head = new Int32Array(nv).fill(-1), next = new Int32Array(nf).fill(-1);
  const alive = new Uint8Array(nf);
  let f = 0;
  for (const h of kept)
    for (const face of HEX_FACES) {
      sortFaceCorners(H, h, face, q);
      const a = q[0], b = q[1], c = q[2], d = q[3];
      let g = head[a], twin = -1;
      while (g >= 0) {
        if (sorted[4 * g + 1] === b && sorted[4 * g + 2] === c && sorted[4 * g + 3] === d) { twin = g; break; }
        g = next[g];
      }
      sorted[4 * f] = a; sorted[4 * f + 1] = b; sorted[4 * f + 2] = c; sorted[4 * f + 3] = d;
      if (twin >= 0) { alive[twin] = 0; alive[f] = 0; }
      else { alive[f] = 1; next[f] = head[a]; head[a] = f; }
      f++;
    }
  const quads = [], owner = [];
  for (let i = 0; i < nf; i++) {
    if (!alive[i]) continue;
    const h = kept[(i / 6) | 0], face = HEX_FACES[i % 6];
    for (let k = 0; k < 4; k++) quads.push(H[8 * h + face[k]]);
    owner.push(h);
  }
  return { quads, owner };
}

// Peeling (HexaLab's "peel"): the layer of each hex counted from the boundary. Hexes with a face on the boundary are
// layer 0, their face neighbours not yet numbered layer 1, and so on (breadth-first over shared faces). Returns an
// Int32Array per hex (-1 for a hex no boundary reaches, which cannot happen in a mesh with a boundary).
export function hexLayers(mesh) {
  const n = hexCount(mesh), H = mesh.hexes;
  const nv = mesh.vertices.length / 3;
  const nf = 6 * n;
  const sorted = new Int32Array(4 * nf), q = new Int32Array(4);
  const head = new Int32Array(nv).fill(-1), next = new Int32Array(nf).fill(-1);
  const twinOf = new Int32Array(nf).fill(-1);
  for (let f = 0; f < nf; f++) {
    const h = (f / 6) | 0, face = HEX_FACES[f % 6];
    sortFaceCorners(H, h, face, q);
    const a = q[0], b = q[1], c = q[2], d = q[3];
    sorted[4 * f] = a; sorted[4 * f + 1] = b; sorted[4 * f + 2] = c; sorted[4 * f + 3] = d;
    let g = head[a];
    while (g >= 0) {
      if (twinOf[g] < 0 && sorted[4 * g + 1] === b && sorted[4 * g + 2] === c && sorted[4 * g + 3] === d) break;
      g = next[g];
    }
    if (g >= 0) { twinOf[g] = f; twinOf[f] = g; } else { next[f] = head[a]; head[a] = f; }
  }
  const layer = new Int32Array(n).fill(-1);
  let front = [];
  for (let h = 0; h < n; h++)
    for (let k = 0; k < 6; k++) if (twinOf[6 * h + k] < 0) { layer[h] = 0; front.push(h); break; }
  for (let depth = 1; front.length; depth++) {
    const nextFront = [];
    for (const h of front)
      for (let k = 0; k < 6; k++) {
        const t = twinOf[6 * h + k];
        if (t < 0) continue;
        const g = (t / 6) | 0;
        if (layer[g] < 0) { layer[g] = depth; nextFront.push(g); }
      }
    front = nextFront;
  }
  return layer;
}

// Every face of every kept hex, each hex shrunk towards its centroid by `factor` (1 = no shrink). Returns flat
// corner positions (4 per quad, 3 numbers each) and the owner hex per quad.
export function shrunkQuads(mesh, factor, keep = null) {
  const n = hexCount(mesh), V = mesh.vertices, H = mesh.hexes;
  const c = hexCentroids(mesh);
  const pos = [], owner = [];
  for (let h = 0; h < n; h++) {
    if (keep && !keep(h)) continue;
    for (const f of HEX_FACES) {
      for (const k of f) {
        const v = H[8 * h + k];
        for (let d = 0; d < 3; d++) pos.push(c[3 * h + d] + factor * (V[3 * v + d] - c[3 * h + d]));
      }
      owner.push(h);
    }
  }
  return { positions: pos, owner };
}

// Scaled Jacobian -> colour: <= 0 magenta (inverted), then red (0) -> yellow (0.5) -> green (1).
export function sjColor(sj) {
  if (!(sj > 0)) return [0.75, 0.0, 0.75];
  const t = Math.min(1, sj);
  if (t < 0.5) return [0.9, 0.15 + 1.5 * t, 0.1];
  return [0.9 - 1.5 * (t - 0.5), 0.9, 0.1 + 0.2 * (t - 0.5)];
}

// Distance -> colour (0 blue, max red).
export function distanceColor(d, max) {
  const t = max > 0 ? Math.min(1, Math.max(0, d / max)) : 0;
  return [0.15 + 0.8 * t, 0.3 + 0.4 * (1 - Math.abs(2 * t - 1)), 0.95 - 0.85 * t];
}

// Singular edge colour by valence, as in the paper's figures: 3 red, 5 green, >= 6 blue; others (boundary
// valences 1 and 3 on corners, etc.) orange / grey.
export function valenceColor(valence) {
  if (valence === 3) return [0.9, 0.1, 0.1];
  if (valence === 5) return [0.1, 0.75, 0.1];
  if (valence >= 6) return [0.15, 0.3, 0.95];
  if (valence === 1) return [1.0, 0.6, 0.0];
  return [0.5, 0.5, 0.5];
}

// Histogram of scaled Jacobians: bin 0 is "<= 0" (inverted or flat), then `bins` equal bins over (0, 1].
// Returns {labels, counts}.
export function sjHistogram(sj, bins = 10) {
  const counts = new Array(bins + 1).fill(0);
  for (const x of sj) {
    if (!(x > 0)) counts[0]++;
    else counts[1 + Math.min(bins - 1, Math.floor(Math.min(x, 1) * bins - 1e-12))]++;
  }
  const labels = ['<=0'];
  for (let i = 0; i < bins; i++) labels.push(`${(i / bins).toFixed(1)}-${((i + 1) / bins).toFixed(1)}`);
  return { labels, counts };
}

// min / mean / count <= 0 of the scaled Jacobians.
export function sjStats(sj) {
  let min = Infinity, sum = 0, bad = 0;
  for (const x of sj) { min = Math.min(min, x); sum += x; if (!(x > 0)) bad++; }
  return { min: sj.length ? min : NaN, avg: sj.length ? sum / sj.length : NaN, inverted: bad };
}

// Axis-aligned bounds of a flat xyz array: {min: [..], max: [..], diagonal}.
export function bounds(flat) {
  const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i + 2 < flat.length; i += 3)
    for (let d = 0; d < 3; d++) { min[d] = Math.min(min[d], flat[i + d]); max[d] = Math.max(max[d], flat[i + d]); }
  const diagonal = flat.length ? Math.hypot(max[0] - min[0], max[1] - min[1], max[2] - min[2]) : 0;
  return { min, max, diagonal };
}

// Index buffer over quad corners (4 per quad, in order): two triangles a,b,c / a,c,d per quad. (The wireframe is drawn
// by the faces' fragment shader from quadCornerCoords: no line index.) The faces are drawn with back-face culling
// (a closed, outward-oriented boundary shows only its front faces; a software WebGL then rasterizes half the
// triangles), so a quad that may face inwards (its hex inverted: scaled Jacobian <= 0, whose faces can point either
// way) is also drawn from behind: bothSides(q) true appends its triangles reversed, a,c,b / a,d,c, after all the
// others. Returns a Uint32Array of 6 indices per quad plus 6 per quad drawn from both sides.
export function quadTriangleIndex(nq, bothSides = null) {
  let extra = 0;
  if (bothSides) for (let q = 0; q < nq; q++) if (bothSides(q)) extra++;
  const idx = new Uint32Array(6 * (nq + extra));
  for (let q = 0; q < nq; q++) {
    const b = 4 * q, i = 6 * q;
    idx[i] = b; idx[i + 1] = b + 1; idx[i + 2] = b + 2; idx[i + 3] = b; idx[i + 4] = b + 2; idx[i + 5] = b + 3;
  }
  if (extra)
    for (let q = 0, i = 6 * nq; q < nq; q++) {
      if (!bothSides(q)) continue;
      const b = 4 * q;
      idx[i++] = b; idx[i++] = b + 2; idx[i++] = b + 1; idx[i++] = b; idx[i++] = b + 3; idx[i++] = b + 2;
    }
  return idx;
}

// Quad-local corner coordinates for a wireframe drawn in the faces' fragment shader (no line primitives): corner k of
// every quad gets (0,0), (1,0), (1,1), (0,1), so that, interpolated over the quad's two triangles (a,b,c / a,c,d of
// quadTriangleIndex), a coordinate is 0 or 1 exactly along the quad's 4 sides and strictly between inside it (the
// diagonal a-c included). The fragment's distance to the nearest side in pixels is then min(u, 1-u, v, 1-v) over the
// screen-space derivative. Returns a Float32Array of 8 numbers per quad (2 per corner).
export function quadCornerCoords(nq) {
  const uv = new Float32Array(8 * nq);
  for (let q = 0; q < nq; q++) {
    const i = 8 * q;
    uv[i + 2] = 1; uv[i + 4] = 1; uv[i + 5] = 1; uv[i + 7] = 1;
  }
  return uv;
}

// One normal per quad, repeated at its 4 corners, for lighting the faces per vertex (flat per quad): the unit cross
// product of the quad's diagonals (c - a) x (d - b), i.e. for a warped quad the normal of the plane through the
// midpoints of its sides (their parallelogram has sides parallel to the diagonals), pointing to the side from which
// a, b, c, d turn counterclockwise. positions: 12 numbers per quad (4 corners, xyz). A degenerate
// quad (zero cross product) gets 0 0 0 (the shader then lights it by the ambient part only).
export function quadNormals(positions) {
  const nq = Math.floor(positions.length / 12);
  const n = new Float32Array(12 * nq);
  const P = positions;
  for (let q = 0; q < nq; q++) {
    const o = 12 * q;
    const ux = P[o + 6] - P[o], uy = P[o + 7] - P[o + 1], uz = P[o + 8] - P[o + 2];
    const wx = P[o + 9] - P[o + 3], wy = P[o + 10] - P[o + 4], wz = P[o + 11] - P[o + 5];
    let x = uy * wz - uz * wy, y = uz * wx - ux * wz, z = ux * wy - uy * wx;
    const len = Math.hypot(x, y, z);
    if (!(len > 0)) continue;
    x /= len; y /= len; z /= len;
    for (let k = 0; k < 4; k++) { n[o + 3 * k] = x; n[o + 3 * k + 1] = y; n[o + 3 * k + 2] = z; }
  }
  return n;
}
