// The studio page: three.js view + editing UI over the pure skeleton model (skeleton_model.js) and the server API.
import * as THREE from 'three';
import { OrbitControls } from '/vendor/OrbitControls.js';
import { TransformControls } from '/vendor/TransformControls.js';
import * as M from '/app/skeleton_model.js';
import * as V from '/app/mesh_view.js';
import * as api from '/app/api.js';

const $ = (id) => document.getElementById(id);

// ---------------------------------------------------------------- state
const st = {
  undo: new M.UndoStack(M.emptySkeleton()),
  selV: [],            // selected vertices, in selection order
  selE: null,          // selected edge [a, b] or null
  domain: null,        // {vertices, triangles, bbox_diagonal}
  saveTarget: null,
  analysis: null,      // analysis of the skeleton last meshed successfully (same V count)
  meshes: { raw: null, final: null }, // last valid responses of /api/mesh (or job results)
  meshedVersion: -1,   // version of the skeleton the raw mesh shows
  version: 0,          // bumps on every change of the skeleton
  error: null,         // {message, where} of the last rejected skeleton
  meshRequests: 0,     // completed raw mesh updates (for tests)
  job: null,           // {id, version}
  lastRoundTripMs: 0,   // request sent -> answer decoded
  editAt: 0,            // performance.now() of the last edit
  lastEditToMeshMs: 0,  // last edit -> its raw mesh drawn
  framesDrawn: 0,       // frames drawn so far (tests: one per arriving mesh, none while idle)
};
const skel = () => st.undo.current;

// ---------------------------------------------------------------- three.js set-up
const canvas = $('canvas');
// Multisampling only on a hardware renderer: a software WebGL (SwiftShader, llvmpipe: virtual machines, remote
// desktops, headless tests) rasterizes every sample on the CPU, and MSAA doubled the frame time there (measured with
// bench/studio_page_latency.mjs on a 10 k-hex mesh).
function softwareWebGL() {
  try {
    const gl = document.createElement('canvas').getContext('webgl');
    const info = gl?.getExtension('WEBGL_debug_renderer_info');
    const name = info ? String(gl.getParameter(info.UNMASKED_RENDERER_WEBGL)) : '';
    gl?.getExtension('WEBGL_lose_context')?.loseContext();
    return /swiftshader|llvmpipe|software/i.test(name);
  } catch { return false; }
}
// The drawing buffer is not preserved after a frame is shown (the screenshot reads the canvas right after drawing it,
// in the same task): the compositor can then take the buffer instead of copying it, 10 % of the tree's edit -> drawn
// in a software WebGL (bench/studio_page_latency.mjs, 114 / 128 against 128 / 139 ms, load 4-6).
const renderer = new THREE.WebGLRenderer({ canvas, antialias: !softwareWebGL(), preserveDrawingBuffer: false });
renderer.setPixelRatio(Math.min(2, window.devicePixelRatio || 1));
renderer.localClippingEnabled = true;
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x1d2026);
const camera = new THREE.PerspectiveCamera(40, 1, 0.001, 1000);
camera.position.set(3, -6, 4);
camera.up.set(0, 0, 1);
const hemi = new THREE.HemisphereLight(0xffffff, 0x445566, 1.6);
scene.add(hemi);
const sun = new THREE.DirectionalLight(0xffffff, 1.4);
camera.add(sun);
sun.position.set(1, 2, 3);
scene.add(camera);
const orbit = new OrbitControls(camera, canvas);
orbit.enableDamping = false;
orbit.addEventListener('change', render);
const gizmoAnchor = new THREE.Object3D();
scene.add(gizmoAnchor);
const gizmo = new TransformControls(camera, canvas);
gizmo.setSize(0.8);
const gizmoHelper = gizmo.getHelper ? gizmo.getHelper() : gizmo;
scene.add(gizmoHelper);
gizmo.addEventListener('change', render);

const groups = {
  domain: new THREE.Group(), skeleton: new THREE.Group(), radii: new THREE.Group(), conn: new THREE.Group(),
  mesh: new THREE.Group(), sing: new THREE.Group(), error: new THREE.Group(), mirror: new THREE.Group(),
};
for (const g of Object.values(groups)) scene.add(g);

// Materials are made once per kind and kept: disposing a material releases its shader program, and the next draw
// would compile it again (hundreds of milliseconds per edit in a software WebGL, measured in
// bench/studio_page_latency.mjs). `clear` disposes the geometry only.
const materials = new Map();
function material(kind, make) {
  let m = materials.get(kind);
  if (!m) { m = make(); materials.set(kind, m); }
  return m;
}

function clear(group) {
  for (const c of [...group.children]) {
    group.remove(c);
    c.geometry?.dispose();
  }
}

// While a raw mesh is on its way (asked less than meshWaitMs() milliseconds ago), a redraw waits for it, so that one
// frame shows the edit with its mesh: a frame of a large scene costs hundreds of milliseconds in a software WebGL and
// would hold the answer back. If the answer is late, the edit is drawn alone when the wait ends. The wait is
// MESH_WAIT_MS, or 1.5 x the last round trip when that is longer (a busy machine, a large mesh), at most
// MESH_WAIT_MAX_MS: on the 12 k-hex tree in SwiftShader at load 2-4 answers came at 80-120 ms, and each one after
// 100 ms waited for the extra frame of the edit alone (200-300 ms) before its own.
const MESH_WAIT_MS = 100;
const MESH_WAIT_MAX_MS = 400;
const meshWaitMs = () => Math.min(MESH_WAIT_MAX_MS, Math.max(MESH_WAIT_MS, 1.5 * (st.lastRoundTripMs || 0)));
let meshAskedAt = -Infinity;
let meshInFlight = false; // a raw-mesh request is on its way (see runMesh)
let deferredRender = null;
let queuedFrame = null; // requestAnimationFrame id of the queued redraw

// Draws the scene (the faces' shader takes the lights as uniforms: updated first).
function drawFrame() {
  st.framesDrawn++;
  placeErrorLabel();
  updateFaceLights();
  renderer.render(scene, camera);
}
function render() {
  if (queuedFrame !== null || deferredRender) return;
  const waited = performance.now() - meshAskedAt;
  if (meshInFlight && waited < meshWaitMs()) {
    deferredRender = setTimeout(() => { deferredRender = null; render(); }, meshWaitMs() - waited);
    return;
  }
  queuedFrame = requestAnimationFrame(() => {
    queuedFrame = null;
    drawFrame();
  });
}
// Draws at once; a redraw already queued or deferred is then not needed.
function renderNow() {
  if (deferredRender) { clearTimeout(deferredRender); deferredRender = null; }
  if (queuedFrame !== null) { cancelAnimationFrame(queuedFrame); queuedFrame = null; }
  drawFrame();
}

function resize() {
  const r = canvas.parentElement.getBoundingClientRect();
  renderer.setSize(r.width, r.height, false);
  camera.aspect = r.width / Math.max(1, r.height);
  camera.updateProjectionMatrix();
  render();
}
window.addEventListener('resize', resize);

// Scale of the scene: domain diagonal, else skeleton bbox, else 1.
function sceneScale() {
  if (st.domain?.bbox_diagonal) return st.domain.bbox_diagonal;
  const b = V.bounds(skel().points.flat());
  return b.diagonal > 0 ? b.diagonal : 4;
}

function frameAll() {
  // The union of the domain and the skeleton (a loaded skeleton may not fit the domain).
  const flat = [...(st.domain ? st.domain.vertices : []), ...skel().points.flat()];
  const b = V.bounds(flat);
  if (!(b.diagonal > 0)) return;
  const c = new THREE.Vector3(...b.min.map((x, i) => (x + b.max[i]) / 2));
  orbit.target.copy(c);
  const d = b.diagonal * 1.25;
  camera.position.copy(c).add(new THREE.Vector3(0.55, -0.75, 0.45).normalize().multiplyScalar(d));
  camera.near = b.diagonal / 1000;
  camera.far = b.diagonal * 100;
  camera.updateProjectionMatrix();
  orbit.update();
  render();
}

// ---------------------------------------------------------------- domain
function drawDomain() {
  clear(groups.domain);
  if (!st.domain) return;
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(st.domain.vertices, 3));
  g.setIndex(st.domain.triangles);
  g.computeVertexNormals();
  const m = new THREE.Mesh(g, material('domain', () => new THREE.MeshPhongMaterial({ color: 0x8fb3ff, transparent: true, opacity: 0.22,
    depthWrite: false, side: THREE.DoubleSide })));
  m.renderOrder = 10;
  groups.domain.add(m);
}

// ---------------------------------------------------------------- skeleton drawing
const CLASS_COLORS = {
  Extremity: 0xffd23f, Joint: 0xcfd8e3, BranchingPoint: 0xff5d5d, LeafletInterior: 0x4fc3f7, LeafletBoundary: 0x26a69a,
  BLJoint: 0xff9800, LLJoint: 0xba68c8, FanEdgeVertex: 0x9ccc65, FanEdgeEnd: 0x558b2f, Isolated: 0x888888,
};
const SELECT_COLOR = 0xffffff;
const EDGE_SELECTED = [1, 1, 1], EDGE_BRANCH = [1, 0.85, 0.3], EDGE_FAN = [0.6, 0.8, 0.4], EDGE_LEAFLET = [0.4, 0.8, 1];
// Above this many vertices the skeleton's vertices are drawn as points instead of spheres.
const MANY_VERTICES = 400;
let vertexMesh = null, edgeLines = null, previewPoints = null;

// Vertex markers: small against the scene, and against the skeleton's own edges (a fine skeleton, e.g. an imported
// medial mesh, must stay readable).
function vertexSize() {
  const s = skel();
  const e = s.edges.length ? meanEdgeLength() : Infinity;
  return Math.min(sceneScale() * 0.008, 0.2 * e);
}

// Draws the current skeleton, or a preview (`s`: a skeleton not yet committed, e.g. during a gizmo drag or a brush
// stroke).
function drawSkeleton(s = skel()) {
  clear(groups.skeleton);
  clear(groups.radii);
  const points = s.points;
  const n = points.length;
  vertexMesh = null; edgeLines = null;
  if (n > MANY_VERTICES) {
    // A large skeleton (e.g. an imported medial mesh): pixel-sized points, cheap to draw; the selection on top.
    const classes = st.analysis && st.analysis.vertex_class?.length === n ? st.analysis.vertex_class : null;
    const pos = new Float32Array(3 * n), col = new Float32Array(3 * n), c = new THREE.Color();
    for (let i = 0; i < n; i++) {
      pos[3 * i] = points[i][0]; pos[3 * i + 1] = points[i][1]; pos[3 * i + 2] = points[i][2];
      c.setHex(classes ? CLASS_COLORS[classes[i]] ?? 0x888888 : 0xaaaaaa);
      col[3 * i] = c.r; col[3 * i + 1] = c.g; col[3 * i + 2] = c.b;
    }
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    g.setAttribute('color', new THREE.BufferAttribute(col, 3));
    const pts = new THREE.Points(g, material('skeleton-points', () => new THREE.PointsMaterial({ size: 5, sizeAttenuation: false, vertexColors: true, depthTest: false })));
    pts.renderOrder = 20;
    groups.skeleton.add(pts);
    if (st.selV.length) {
      const sg = new THREE.BufferGeometry();
      sg.setAttribute('position', new THREE.Float32BufferAttribute(st.selV.flatMap((v) => points[v] || []), 3));
      const sel = new THREE.Points(sg, material('skeleton-selected-points', () => new THREE.PointsMaterial({ size: 9, sizeAttenuation: false, color: SELECT_COLOR, depthTest: false })));
      sel.renderOrder = 21;
      groups.skeleton.add(sel);
    }
  } else if (n) {
    const geo = new THREE.SphereGeometry(vertexSize(), 14, 10);
    vertexMesh = new THREE.InstancedMesh(geo, material('skeleton-vertices', () => new THREE.MeshPhongMaterial({ color: 0xffffff, depthTest: false })), n);
    const classes = st.analysis && st.analysis.vertex_class?.length === n ? st.analysis.vertex_class : null;
    const mtx = new THREE.Matrix4(), col = new THREE.Color();
    const sel = new Set(st.selV);
    for (let i = 0; i < n; i++) {
      const big = sel.has(i) ? 1.6 : 1;
      mtx.makeScale(big, big, big).setPosition(...points[i]);
      vertexMesh.setMatrixAt(i, mtx);
      col.setHex(sel.has(i) ? SELECT_COLOR : classes ? CLASS_COLORS[classes[i]] ?? 0x888888 : 0xaaaaaa);
      vertexMesh.setColorAt(i, col);
    }
    vertexMesh.renderOrder = 20;
    groups.skeleton.add(vertexMesh);
  }
  if (s.edges.length) {
    const ne = s.edges.length;
    const pos = new Float32Array(6 * ne), colr = new Float32Array(6 * ne);
    const kinds = st.analysis && st.analysis.edge_kind?.length === ne ? st.analysis.edge_kind : null;
    const selKey = st.selE ? M.edgeKey(...st.selE) : null;
    s.edges.forEach((e, i) => {
      pos.set(points[e[0]], 6 * i); pos.set(points[e[1]], 6 * i + 3);
      const c = selKey !== null && M.edgeKey(e[0], e[1]) === selKey ? EDGE_SELECTED
        : kinds?.[i] === 'branch' ? EDGE_BRANCH : kinds?.[i] === 'fan' ? EDGE_FAN : EDGE_LEAFLET;
      colr.set(c, 6 * i); colr.set(c, 6 * i + 3);
    });
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    g.setAttribute('color', new THREE.BufferAttribute(colr, 3));
    edgeLines = new THREE.LineSegments(g, material('skeleton-edges', () => new THREE.LineBasicMaterial({ vertexColors: true, depthTest: false })));
    edgeLines.renderOrder = 19;
    groups.skeleton.add(edgeLines);
  }
  if (s.faces.length) {
    const pos = [];
    for (const f of s.faces)
      for (let k = 1; k + 1 < f.length; k++) pos.push(...points[f[0]], ...points[f[k]], ...points[f[k + 1]]);
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
    groups.skeleton.add(new THREE.Mesh(g, material('skeleton-faces', () => new THREE.MeshBasicMaterial({ color: 0x4fc3f7, transparent: true,
      opacity: 0.25, side: THREE.DoubleSide, depthWrite: false }))));
  }
  if ($('v-radii').checked && s.radii.length) {
    const geo = new THREE.SphereGeometry(1, 20, 14);
    const im = new THREE.InstancedMesh(geo, material('radii', () => new THREE.MeshPhongMaterial({ color: 0xffcc66, transparent: true,
      opacity: 0.18, depthWrite: false })), n);
    const mtx = new THREE.Matrix4();
    for (let i = 0; i < n; i++) { const r = s.radii[i]; mtx.makeScale(r, r, r).setPosition(...points[i]); im.setMatrixAt(i, mtx); }
    groups.radii.add(im);
  }
  groups.skeleton.visible = $('v-skeleton').checked;
  drawMirrorPlane();
  updateLegend();
  render();
}

// ---------------------------------------------------------------- mesh drawing
let clipRange = null;

function currentMeshResponse() {
  return st.meshes[$('v-stage').value] || null;
}

// Arrays kept between redraws: the triangles of nq quads and their corner coordinates (the wireframe's) depend on nq
// only, so a patch answer that moved vertices reuses them (they are uploaded again with each new geometry: `clear`
// disposes the old one).
let triangleIndexCache = null, cornerCoordsCache = null;
// With inverted hexes (their quads drawn from both sides, see V.quadTriangleIndex) the index also depends on the
// quads' hexes (owner) and the hexes' scaled Jacobians (sj; missing: every quad from both sides): kept while both
// arrays are the same objects (a patch answer leaves an unchanged array as it was: binary_answer.js).
function triangleIndex(nq, owner, sj, nh) {
  const c = triangleIndexCache;
  if (c?.nq === nq && c.owner === owner && c.sj === sj) return c.attr;
  const known = sj.length === nh;
  const inverted = known && !sj.some((x) => !(x > 0)) ? null : (q) => !known || !(sj[owner[q]] > 0);
  triangleIndexCache = { nq, owner, sj, attr: new THREE.BufferAttribute(V.quadTriangleIndex(nq, inverted), 1) };
  return triangleIndexCache.attr;
}
function cornerCoords(nq) {
  if (cornerCoordsCache?.nq !== nq)
    cornerCoordsCache = { nq, attr: new THREE.BufferAttribute(V.quadCornerCoords(nq), 2) };
  return cornerCoordsCache.attr;
}

// The mesh's faces: lit per vertex with one normal per quad (V.quadNormals; the same lights as the scene's
// MeshPhongMaterial had: the hemisphere light and the camera's sun, without its faint specular), and the wireframe
// drawn in the fragment shader from the quads' corner coordinates (V.quadCornerCoords): each side is darkened within
// about one pixel on both of its quads, anti-aliased, blended in sRGB as the transparent lines were. The colour is
// converted to sRGB per vertex (the colours are flat per quad, or smooth in the distance view). No line primitives and
// no per-pixel lighting nor colour conversion: in a software WebGL (SwiftShader) the Phong faces, their per-pixel
// sRGB conversion (a pow per channel) and the 54 k wireframe lines of the 12 k-hex tree were most of a 130-280 ms
// frame (measured with bench/studio_page_latency.mjs; docs/studio.md). On a GPU it also ends the lines' z-fighting.
const MESH_WIRE_OPACITY = 0.5; // how dark the wireframe is: 0 off, 1 the wire colour
const MESH_WIRE_COLOR = 0x111111;
function meshFaceMaterial() {
  return material('mesh-faces', () => {
    return new THREE.ShaderMaterial({
      vertexColors: true, side: THREE.FrontSide, // back faces culled: see V.quadTriangleIndex
      uniforms: {
        skyColor: { value: new THREE.Color(0xffffff) }, groundColor: { value: new THREE.Color(0x445566) },
        sunColor: { value: new THREE.Color(0xffffff) }, sunDirection: { value: new THREE.Vector3(0, 0, 1) },
        wireColor: { value: new THREE.Color(MESH_WIRE_COLOR).convertLinearToSRGB() },
        wireOpacity: { value: MESH_WIRE_OPACITY },
      },
      vertexShader: `
        uniform vec3 skyColor, groundColor, sunColor, sunDirection;
        attribute vec2 corner;
        varying vec3 vColor;
        varying vec2 vCorner;
        vec3 srgb(vec3 c) { // linear -> sRGB (the canvas' colour space, renderer.outputColorSpace)
          c = clamp(c, 0.0, 1.0);
          return mix(1.055 * pow(c, vec3(0.41666)) - 0.055, 12.92 * c, vec3(lessThanEqual(c, vec3(0.0031308))));
        }
        void main() {
          vec4 world = modelMatrix * vec4(position, 1.0);
          vec3 n = normal; // object space = world space: the mesh group is never transformed (identity matrix)
          if (dot(n, cameraPosition - world.xyz) < 0.0) n = -n; // lit as seen (inverted hexes' faces, warped quads)
          vec3 irradiance = mix(groundColor, skyColor, 0.5 * n.y + 0.5) + sunColor * max(dot(n, sunDirection), 0.0);
          vColor = srgb(color * irradiance);
          vCorner = corner;
          gl_Position = projectionMatrix * viewMatrix * world;
        }`,
      fragmentShader: `
        uniform vec3 wireColor;
        uniform float wireOpacity;
        varying vec3 vColor;
        varying vec2 vCorner;
        void main() {
          gl_FragColor = vec4(vColor, 1.0);
          if (wireOpacity > 0.0) {
            vec2 px = min(vCorner, 1.0 - vCorner) / max(fwidth(vCorner), vec2(1e-6)); // pixels to the sides
            float cover = clamp(1.0 - min(px.x, px.y), 0.0, 1.0);
            gl_FragColor.rgb = mix(gl_FragColor.rgb, wireColor, wireOpacity * cover);
          }
        }`,
    });
  });
}
// The lights of the faces' shader follow the scene's (physically based units: irradiance / pi, as three.js's
// Lambert term): the hemisphere light's sky (up = +y, three.js's default) and ground colours, and the sun's
// direction from its target to it, updated per frame (the sun moves with the camera).
function updateFaceLights() {
  const m = materials.get('mesh-faces');
  if (!m) return;
  const u = m.uniforms;
  u.skyColor.value.copy(hemi.color).multiplyScalar(hemi.intensity / Math.PI);
  u.groundColor.value.copy(hemi.groundColor).multiplyScalar(hemi.intensity / Math.PI);
  u.sunColor.value.copy(sun.color).multiplyScalar(sun.intensity / Math.PI);
  const p = new THREE.Vector3(), t = new THREE.Vector3();
  sun.getWorldPosition(p); sun.target.getWorldPosition(t);
  u.sunDirection.value.copy(p).sub(t).normalize();
}

function drawMesh() {
  clear(groups.mesh); clear(groups.sing); clear(groups.conn);
  const resp = currentMeshResponse();
  const mesh = resp?.mesh;
  updateStats();
  if (!mesh || !V.hexCount(mesh)) { drawHistogram([]); render(); return; }
  const sj = mesh.sj || [];
  drawHistogram(sj);
  const b = V.bounds(mesh.vertices);
  clipRange = b;
  let keep = null;
  if ($('v-clip').checked) {
    const axis = +$('v-clip-axis').value, flip = $('v-clip-flip').checked;
    const t = +$('v-clip-pos').value;
    const cut = b.min[axis] + t * (b.max[axis] - b.min[axis]);
    const c = V.hexCentroids(mesh);
    keep = (h) => (flip ? c[3 * h + axis] >= cut : c[3 * h + axis] <= cut);
  }
  // Peel: hide the outer `peel` layers of hexes (layers counted from the boundary, computed once per mesh).
  const peel = +$('v-peel').value;
  $('v-peel-val').textContent = String(peel);
  if (peel > 0) {
    const layers = resp.layers ??= V.hexLayers(mesh);
    const clipKeep = keep;
    keep = (h) => layers[h] >= peel && (!clipKeep || clipKeep(h));
  }
  const shrink = +$('v-shrink').value;
  let quadPos, owner, cornerVerts = null;
  if (shrink < 0.999) {
    const r = V.shrunkQuads(mesh, shrink, keep);
    quadPos = r.positions; owner = r.owner;
  } else {
    // Only the faces not shared by two shown hexes: the boundary (plus the cut when clipped). With every hex shown,
    // the server's boundary quads and their hexes.
    if (!keep && mesh.boundary_quads && mesh.boundary_hexes?.length * 4 === mesh.boundary_quads.length) {
      cornerVerts = mesh.boundary_quads; owner = mesh.boundary_hexes;
    } else {
      const r = V.visibleQuads(mesh, keep);
      owner = r.owner; cornerVerts = r.quads;
    }
    const P = mesh.vertices, nc = cornerVerts.length;
    quadPos = new Float32Array(nc * 3);
    for (let i = 0; i < nc; i++) {
      const v = 3 * cornerVerts[i];
      quadPos[3 * i] = P[v]; quadPos[3 * i + 1] = P[v + 1]; quadPos[3 * i + 2] = P[v + 2];
    }
  }
  const mode = $('v-color').value;
  const nq = owner.length;
  const colors = new Float32Array(nq * 12);
  const dist = mesh.boundary_distance;
  const maxDist = dist?.length ? dist.reduce((m, x) => Math.max(m, x), 0) : 0;
  const byDistance = mode === 'dist' && dist?.length && cornerVerts;
  const plain = [0.78, 0.8, 0.85];
  for (let q = 0; q < nq; q++) {
    if (byDistance) {
      for (let k = 0; k < 4; k++) colors.set(V.distanceColor(dist[cornerVerts[4 * q + k]], maxDist), 12 * q + 3 * k);
      continue;
    }
    const c = mode === 'sj' ? V.sjColor(sj[owner[q]]) : plain, o = 12 * q;
    for (let k = 0; k < 12; k += 3) { colors[o + k] = c[0]; colors[o + k + 1] = c[1]; colors[o + k + 2] = c[2]; }
  }
  const position = new THREE.BufferAttribute(quadPos instanceof Float32Array ? quadPos : new Float32Array(quadPos), 3);
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', position);
  g.setAttribute('color', new THREE.BufferAttribute(colors, 3));
  g.setAttribute('normal', new THREE.BufferAttribute(V.quadNormals(quadPos), 3));
  g.setAttribute('corner', cornerCoords(nq));
  g.setIndex(triangleIndex(nq, owner, sj, V.hexCount(mesh)));
  const faces = meshFaceMaterial();
  faces.uniforms.wireOpacity.value = $('v-wire').checked ? MESH_WIRE_OPACITY : 0;
  // The mesh's bounding sphere from its bounds (three.js would compute one per new geometry, a pass over its corners,
  // to cull and sort it): shrunk and clipped quads are inside it too, and so are the singular edges.
  const sphere = new THREE.Sphere(new THREE.Vector3(...b.min.map((x, i) => (x + b.max[i]) / 2)), b.diagonal / 2);
  g.boundingSphere = sphere;
  groups.mesh.add(new THREE.Mesh(g, faces));
  if ($('v-sing').checked && mesh.singular_edges?.length) {
    const se = mesh.singular_edges, P = mesh.vertices, ns = Math.floor(se.length / 3);
    const pos = new Float32Array(6 * ns), col = new Float32Array(6 * ns);
    for (let e = 0; e < ns; e++) {
      const a = 3 * se[3 * e], bb = 3 * se[3 * e + 1], o = 6 * e;
      pos[o] = P[a]; pos[o + 1] = P[a + 1]; pos[o + 2] = P[a + 2];
      pos[o + 3] = P[bb]; pos[o + 4] = P[bb + 1]; pos[o + 5] = P[bb + 2];
      const c = V.valenceColor(se[3 * e + 2]);
      col.set(c, o); col.set(c, o + 3);
    }
    const sg = new THREE.BufferGeometry();
    sg.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    sg.setAttribute('color', new THREE.BufferAttribute(col, 3));
    const lines = new THREE.LineSegments(sg, material('singular-edges', () => new THREE.LineBasicMaterial({ vertexColors: true, depthTest: false })));
    lines.renderOrder = 15;
    sg.boundingSphere = sphere.clone();
    groups.sing.add(lines);
  }
  const cs = resp.connection_surfaces;
  if ($('v-conn').checked && cs?.quads?.length) {
    const pos = [];
    for (let i = 0; i + 3 < cs.quads.length; i += 4)
      for (const k of [0, 1, 2, 0, 2, 3]) { const v = cs.quads[i + k]; pos.push(cs.vertices[3 * v], cs.vertices[3 * v + 1], cs.vertices[3 * v + 2]); }
    const cg = new THREE.BufferGeometry();
    cg.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
    groups.conn.add(new THREE.Mesh(cg, material('connection-surfaces', () => new THREE.MeshBasicMaterial({ color: 0xff66cc, transparent: true, opacity: 0.35,
      side: THREE.DoubleSide, depthWrite: false }))));
  }
  groups.mesh.visible = $('v-mesh').checked;
  render();
}

function drawHistogram(sj) {
  const h = V.sjHistogram(sj, 10);
  const max = Math.max(1, ...h.counts);
  $('hist').innerHTML = '';
  h.counts.forEach((c, i) => {
    const bar = document.createElement('div');
    bar.className = 'bar';
    bar.title = `${h.labels[i]}: ${c} hexes`;
    const fill = document.createElement('div');
    const col = i === 0 ? V.sjColor(0) : V.sjColor((i - 0.5) / 10);
    fill.style.background = `rgb(${col.map((x) => Math.round(255 * x)).join(',')})`;
    fill.style.height = `${c ? Math.max(3, (88 * c) / max) : 1}%`;
    const lab = document.createElement('span');
    lab.textContent = i === 0 ? '≤0' : i % 2 ? '' : (i / 10).toFixed(1);
    bar.append(fill, lab);
    bar.dataset.count = c;
    bar.dataset.label = h.labels[i];
    $('hist').append(bar);
  });
}

function updateStats() {
  const rows = [];
  const resp = currentMeshResponse();
  const mesh = resp?.mesh;
  const stage = $('v-stage').value;
  if (mesh) {
    const q = V.sjStats(mesh.sj || []);
    rows.push([`${stage} hexes`, `<span id="hexcount">${V.hexCount(mesh)}</span>`]);
    rows.push(['min / avg SJ', `${q.min.toFixed(3)} / ${q.avg.toFixed(3)}`]);
    rows.push(['SJ ≤ 0', q.inverted]);
    rows.push(['singular edges', (mesh.singular_edges?.length || 0) / 3]);
    if (mesh.boundary_distance?.length && st.domain) {
      const d = mesh.boundary_distance.reduce((m, x) => Math.max(m, x), 0);
      rows.push(['Hausdorff (boundary)', `${d.toPrecision(3)} (${((100 * d) / st.domain.bbox_diagonal).toFixed(2)} % diag)`]);
    }
    if (resp.server_ms !== undefined && stage === 'raw')
      rows.push(['edit → mesh', `<span title="server ${(+resp.server_ms).toFixed(1)} ms, round trip ${st.lastRoundTripMs.toFixed(1)} ms">${st.lastEditToMeshMs.toFixed(0)} ms (server ${(+resp.server_ms).toFixed(0)})</span>`]);
  } else rows.push([`${stage} hexes`, `<span id="hexcount">–</span>`]);
  const a = st.analysis;
  if (a?.predicted) {
    rows.push(['predicted raw hexes', `<span id="predicted">${a.predicted.hexes}</span>`]);
    const irr = (o) => Object.entries(o || {}).map(([k, v]) => `${v}×v${k}`).join(' ') || 'none';
    rows.push(['irregular (interior)', irr(a.predicted.irregular_edges?.interior)]);
    rows.push(['irregular (boundary)', irr(a.predicted.irregular_edges?.boundary)]);
  }
  $('stats').innerHTML = rows.map(([k, v]) => `<tr><td>${k}</td><td>${v}</td></tr>`).join('');
}

function updateLegend() {
  const used = new Set(st.analysis?.vertex_class || []);
  const items = Object.entries(CLASS_COLORS).filter(([k]) => used.size === 0 || used.has(k))
    .map(([k, c]) => `<div><span class="sw" style="background:#${c.toString(16).padStart(6, '0')}"></span>${k}</div>`);
  items.push('<div style="margin-top:4px">singular edges: <span class="sw" style="background:#e61a1a"></span>3 ' +
    '<span class="sw" style="background:#1abf1a"></span>5 <span class="sw" style="background:#264cf2"></span>≥6 ' +
    '<span class="sw" style="background:#ff9900"></span>1 (boundary)</div>');
  items.push('<div>hexes: <span class="sw" style="background:#bf00bf"></span>SJ ≤ 0 ' +
    '<span class="sw" style="background:#e62619"></span>0 <span class="sw" style="background:#e6e61a"></span>0.5 ' +
    '<span class="sw" style="background:#1ae64d"></span>1</div>');
  $('legend').innerHTML = items.join('');
}

// ---------------------------------------------------------------- status, errors
function setStatus(state, text) {
  const s = $('status');
  s.dataset.state = state;
  s.textContent = text;
}

let toastTimer = null;
function toast(msg) {
  const t = $('toast');
  t.textContent = msg;
  t.hidden = false;
  clearTimeout(toastTimer);
  toastTimer = setTimeout(() => { t.hidden = true; }, 5000);
}

let errorAnchor = null;
function showError(err) {
  clear(groups.error);
  errorAnchor = null;
  $('errorlabel').hidden = true;
  st.error = err;
  if (!err) { render(); return; }
  const s = skel(), w = err.where || {};
  const mat = material('error', () => new THREE.MeshBasicMaterial({ color: 0xff2020, transparent: true, opacity: 0.6, side: THREE.DoubleSide, depthTest: false }));
  const r = vertexSize() * 3;
  if (w.kind === 'skeleton_vertex' && s.points[w.index]) {
    const m = new THREE.Mesh(new THREE.SphereGeometry(r, 16, 12), mat);
    m.position.set(...s.points[w.index]);
    groups.error.add(m);
    errorAnchor = s.points[w.index];
  } else if (w.kind === 'skeleton_edge' && s.edges[w.index]) {
    const [a, b] = s.edges[w.index];
    const pa = new THREE.Vector3(...s.points[a]), pb = new THREE.Vector3(...s.points[b]);
    const len = pa.distanceTo(pb);
    const m = new THREE.Mesh(new THREE.CylinderGeometry(r / 2, r / 2, len, 10), mat);
    m.position.copy(pa).add(pb).multiplyScalar(0.5);
    m.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), pb.clone().sub(pa).normalize());
    groups.error.add(m);
    errorAnchor = m.position.toArray();
  } else if (w.kind === 'skeleton_face' && s.faces[w.index]) {
    const f = s.faces[w.index], pos = [];
    for (let k = 1; k + 1 < f.length; k++) pos.push(...s.points[f[0]], ...s.points[f[k]], ...s.points[f[k + 1]]);
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
    groups.error.add(new THREE.Mesh(g, mat));
    errorAnchor = [0, 1, 2].map((d) => f.reduce((acc, v) => acc + s.points[v][d], 0) / f.length);
  }
  groups.error.renderOrder = 30;
  const label = $('errorlabel');
  label.textContent = `${w.kind && w.kind !== 'none' ? `${w.kind.replace('skeleton_', '')} ${w.index}: ` : ''}${err.message}`;
  label.hidden = false;
  if (!errorAnchor) { label.style.left = '8px'; label.style.top = '40px'; }
  render();
}

function placeErrorLabel() {
  if (!errorAnchor || $('errorlabel').hidden) return;
  const p = toScreen(errorAnchor);
  const w = canvas.getBoundingClientRect().width;
  const l = $('errorlabel');
  // Keep the label inside the view: to the left of the element when it is near the right border.
  l.style.left = `${Math.max(0, p.x > w - 360 ? p.x - 360 : p.x)}px`;
  l.style.top = `${p.y}px`;
}

function toScreen(p) {
  const v = new THREE.Vector3(...p).project(camera);
  const r = canvas.getBoundingClientRect();
  return { x: ((v.x + 1) / 2) * r.width, y: ((1 - v.y) / 2) * r.height, behind: v.z > 1 };
}

// ---------------------------------------------------------------- live mesh
// One raw-mesh request at a time: an edit sends the skeleton at once when none is in flight; edits made while one is
// in flight are coalesced into one request for the latest skeleton, sent when the answer arrives (the older answer is
// then not drawn). No debounce: a gizmo drag, a brush stroke or a typed coordinate is one edit when it ends.
// The answer comes in binary form (float32 / uint32 arrays, binary_answer.js): the same content as the JSON API.

function scheduleMesh() {
  if (!skel().points.length) {
    st.meshes.raw = null; st.analysis = null; showError(null); drawMesh();
    setStatus('empty', 'no skeleton: load one, take the curve skeleton of the domain, or press N');
    return;
  }
  setStatus('stale', 'mesh is stale: updating…');
  if (!meshInFlight) runMesh();
}

function sameAnalysis(a, b) {
  const same = (x, y) => x && y && x.length === y.length && x.every((v, i) => v === y[i]);
  return !!(a && b && same(a.vertex_class, b.vertex_class) && same(a.edge_kind, b.edge_kind));
}

// The server keeps the page's last skeleton (its session, named by api.clientId): after an edit that moves vertices or
// changes radii only the changed vertices go up (an MHSD delta, a few bytes instead of the whole skeleton), and the
// server remeshes incrementally. Anything else, or a session the server does not hold (any more: 409
// SendFullSkeleton), sends the whole skeleton. `session.base` is the skeleton the server holds as revision
// `session.revision` (skeletons are never modified in place: every edit makes a new one).
// `session.answer`: the answer drawn (st.meshes.raw) and its revision, when it came from this session: the server then
// sends only the arrays' values that changed since (a patch answer).
const session = { base: null, baseRevision: 0, revision: 0, answer: null, deltas: 0, full: 0, patches: 0 };
async function meshInSession(s, encoded) {
  const revision = ++session.revision;
  const delta = M.toDelta(session.base, s);
  const since = session.answer && session.answer.answer === st.meshes.raw ? session.answer : null;
  const full = () => { const b = M.toBinary(s); encoded(performance.now()); session.full++; return api.meshSession(b, revision, since); };
  const base = session.baseRevision;
  session.base = null; // until the server has this one
  try {
    let resp;
    if (delta) {
      encoded(performance.now());
      try {
        resp = await api.meshDelta(delta, base, revision, since);
        session.deltas++;
      } catch (e) {
        if (!(e instanceof api.ApiError && e.code === 'SendFullSkeleton')) throw e;
        resp = await full();
      }
    } else {
      resp = await full();
    }
    session.base = s; session.baseRevision = revision;
    if (resp.patch_of !== undefined) session.patches++;
    return { resp, revision };
  } catch (e) {
    // A skeleton the server read but could not mesh (422) is its session's skeleton all the same.
    if (e instanceof api.ApiError && e.status === 422) { session.base = s; session.baseRevision = revision; }
    throw e;
  }
}

async function runMesh() {
  meshInFlight = true;
  meshAskedAt = performance.now();
  const version = st.version;
  const editAt = st.editAt;
  const t0 = performance.now();
  let tEncoded = t0;
  try {
    const { resp, revision } = await meshInSession(skel(), (t) => { tEncoded = t; });
    if (version !== st.version) return; // a newer edit: its request goes out below
    const t1 = performance.now();
    st.lastRoundTripMs = t1 - t0;
    st.meshes.raw = resp;
    session.answer = { revision, answer: resp };
    // The skeleton is redrawn only when its colours (vertex classes, edge kinds) changed or an error was shown.
    const recolour = !sameAnalysis(st.analysis, resp.analysis) || st.error;
    st.analysis = resp.analysis || null;
    st.meshedVersion = version;
    showError(null);
    if (recolour) drawSkeleton();
    const t2 = performance.now();
    if ($('v-stage').value === 'raw' || !st.meshes.final) { $('v-stage').value = 'raw'; }
    drawMesh();
    const t3 = performance.now();
    renderNow();
    const t4 = performance.now();
    const rt = api.lastTiming || {};
    st.lastPhasesMs = { queued: t0 - editAt, roundTrip: t1 - t0, encode: tEncoded - t0, send: rt.send, wait: rt.wait,
      download: rt.download, handover: rt.handover, decode: rt.decode, answerKB: rt.bytes / 1024, skeleton: t2 - t1,
      mesh: t3 - t2, render: t4 - t3 };
    // Edit -> updated mesh on screen: request, server, decoding, geometry and the draw call.
    st.lastEditToMeshMs = performance.now() - editAt;
    st.meshRequests++;
    setStatus('ok', `raw mesh up to date: ${V.hexCount(resp.mesh)} hexes (${st.lastEditToMeshMs.toFixed(0)} ms)`);
    updateStats();
  } catch (e) {
    if (version !== st.version) return;
    st.meshRequests++;
    if (e instanceof api.ApiError) {
      showError({ message: e.message, where: e.where });
      setStatus('error', `skeleton rejected (${e.code}): the mesh shown is the last valid one (stale)`);
      // Keep the vertex classes only if they still fit.
      if (st.analysis && st.analysis.vertex_class?.length !== skel().points.length) st.analysis = null;
      drawSkeleton();
    } else {
      setStatus('error', `server unreachable: ${e.message}`);
    }
  } finally {
    meshInFlight = false;
    if (version !== st.version && skel().points.length) runMesh();
    else if (deferredRender) { clearTimeout(deferredRender); deferredRender = null; render(); }
  }
}

// ---------------------------------------------------------------- finish job
async function finish() {
  if (!skel().points.length) return;
  await cancelJob();
  const version = st.version;
  try {
    const { job } = await api.startJob(M.toBinary(skel()));
    st.job = { id: job, version };
    $('progress').hidden = false;
    $('progress').value = 0;
    $('jobinfo').textContent = `job ${job}: queued`;
    pollJob(job);
  } catch (e) {
    $('jobinfo').textContent = `finish failed: ${e.message}`;
    if (e.where && e.where.kind !== 'none') showError({ message: e.message, where: e.where });
  }
}

// Progress is streamed from the server (/api/jobs/ID/events, server-sent events); the result is fetched once the
// job is finished. Polling every 250 ms takes over if the stream fails.
function showJobProgress(id, j) {
  const p = j.progress || {};
  $('progress').value = p.steps ? p.step / p.steps : 0;
  $('jobinfo').textContent = `job ${id}: ${j.state}${p.stage ? ` (${p.stage}${p.what ? ` "${p.what}"` : ''} ${p.step ?? ''}/${p.steps ?? ''})` : ''}`;
  st.jobEvents = (st.jobEvents || 0) + 1;
}

function jobFinished(id, j) {
  if (j.state === 'done') {
    st.meshes.final = j.result;
    $('v-stage').value = 'final';
    $('progress').value = 1;
    st.job = null;
    if (st.meshedVersion === st.version)
      setStatus('ok', `final mesh of this skeleton: ${V.hexCount(j.result.mesh)} hexes (raw: ${V.hexCount(st.meshes.raw?.mesh)})`);
    drawMesh();
    return;
  }
  if (j.error) {
    $('jobinfo').textContent += `: ${j.error.message}`;
    if (j.error.where && j.error.where.kind !== 'none') showError(j.error);
  }
  st.job = null;
}

const finishedState = (state) => state === 'done' || state === 'failed' || state === 'cancelled';

function pollJob(id) {
  if (typeof EventSource === 'undefined') { pollJobByRequests(id); return; }
  const es = new EventSource(`/api/jobs/${id}/events`);
  st.jobStream = es;
  es.onmessage = async (ev) => {
    if (!st.job || st.job.id !== id) { es.close(); return; }
    const j = JSON.parse(ev.data);
    showJobProgress(id, j);
    if (!finishedState(j.state)) return;
    es.close();
    try { jobFinished(id, await api.job(id)); } catch (e) { $('jobinfo').textContent = `job ${id}: ${e.message}`; }
  };
  es.onerror = () => {
    es.close();
    if (st.job && st.job.id === id) pollJobByRequests(id);
  };
}

async function pollJobByRequests(id) {
  while (st.job && st.job.id === id) {
    let j;
    try { j = await api.job(id); } catch (e) { $('jobinfo').textContent = `job ${id}: ${e.message}`; break; }
    if (!st.job || st.job.id !== id) break;
    showJobProgress(id, j);
    if (finishedState(j.state)) { jobFinished(id, j); break; }
    await new Promise((r) => setTimeout(r, 250));
  }
}

async function cancelJob() {
  if (!st.job) return;
  const id = st.job.id;
  st.job = null;
  st.jobStream?.close();
  $('jobinfo').textContent = `job ${id}: cancelled by the edit`;
  $('progress').hidden = true;
  await api.cancelJob(id);
}

// ---------------------------------------------------------------- editing
function changed({ frame = false } = {}) {
  st.version++;
  st.editAt = performance.now();
  st.meshes.final = null; // a final mesh belongs to the skeleton it was made for
  if ($('v-stage').value === 'final') $('v-stage').value = 'raw';
  cancelJob();
  // The request first: the server meshes while the page redraws the skeleton.
  scheduleMesh();
  const n = skel().points.length;
  st.selV = st.selV.filter((v) => v < n);
  if (st.selE && (st.selE[0] >= n || st.selE[1] >= n || M.findEdge(skel(), ...st.selE) < 0)) st.selE = null;
  drawSkeleton();
  updateSelection();
  updateCounts();
  if (frame) frameAll();
}

function commit(next, label) {
  st.undo.push(next, label);
  changed();
}

function edit(kind, args) {
  try {
    const r = M.applyEdit(skel(), kind, args, mirrorPlane(), sceneScale() * 1e-4);
    commit(r.skeleton, kind);
    return r;
  } catch (e) {
    toast(e.message);
    return null;
  }
}

function mirrorPlane() {
  const a = $('mirror').value;
  if (a === '') return null;
  const axis = +a;
  const flat = st.domain ? st.domain.vertices : skel().points.flat();
  const b = V.bounds(flat);
  return { axis, c: b.diagonal > 0 || flat.length ? (b.min[axis] + b.max[axis]) / 2 : 0 };
}

function drawMirrorPlane() {
  clear(groups.mirror);
  const p = mirrorPlane();
  if (!p) return;
  const size = sceneScale() * 1.1;
  const m = new THREE.Mesh(new THREE.PlaneGeometry(size, size), material('mirror-plane', () => new THREE.MeshBasicMaterial({ color: 0xffffff,
    transparent: true, opacity: 0.06, side: THREE.DoubleSide, depthWrite: false })));
  const flat = st.domain ? st.domain.vertices : skel().points.flat();
  const b = V.bounds(flat);
  if (b.diagonal > 0) m.position.set(...b.min.map((x, i) => (x + b.max[i]) / 2));
  if (p.axis === 0) m.rotation.y = Math.PI / 2;
  if (p.axis === 1) m.rotation.x = Math.PI / 2;
  groups.mirror.add(m);
}

const sub3 = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const len3 = (a) => Math.hypot(a[0], a[1], a[2]);
const norm3 = (a) => { const l = len3(a) || 1; return [a[0] / l, a[1] / l, a[2] / l]; };

function meanEdgeLength() {
  const s = skel();
  if (!s.edges.length) return sceneScale() * 0.1;
  return s.edges.reduce((acc, [a, b]) => acc + len3(sub3(s.points[a], s.points[b])), 0) / s.edges.length;
}

function extrude() {
  const s = skel();
  const e = selectedEdge();
  if (e) {
    const [a, b] = e;
    const fs = M.facesOfEdge(s, a, b);
    const mid = s.points[a].map((x, i) => (x + s.points[b][i]) / 2);
    let dir;
    if (fs.length === 1) {
      const f = s.faces[fs[0]];
      const c = [0, 1, 2].map((d) => f.reduce((acc, v) => acc + s.points[v][d], 0) / f.length);
      const ab = norm3(sub3(s.points[b], s.points[a]));
      const out = sub3(mid, c);
      const along = out[0] * ab[0] + out[1] * ab[1] + out[2] * ab[2];
      dir = norm3(out.map((x, i) => x - along * ab[i]));
    } else {
      const ab = norm3(sub3(s.points[b], s.points[a]));
      dir = norm3(Math.abs(ab[2]) < 0.9 ? [ab[1], -ab[0], 0] : [0, ab[2], -ab[1]]);
    }
    const l = len3(sub3(s.points[a], s.points[b]));
    const r = edit('extrudeEdge', { a, b, offset: dir.map((x) => x * l) });
    if (r) { st.selV = r.created.slice(0, 2); st.selE = null; updateSelection(); drawSkeleton(); }
    return;
  }
  if (st.selV.length >= 3) { extrudeChain(); return; }
  if (st.selV.length !== 1) { toast('extrude: select one vertex (branch), one edge (quad) or a chain of vertices (strip)'); return; }
  const v = st.selV[0];
  const nb = M.neighbours(s, v);
  let dir = [0, 0, 1];
  if (nb.length) {
    const away = nb.reduce((acc, u) => acc.map((x, i) => x + s.points[v][i] - s.points[u][i]), [0, 0, 0]);
    if (len3(away) > 1e-12) dir = norm3(away);
    else dir = norm3(sub3(s.points[v], s.points[nb[0]]));
  }
  const l = meanEdgeLength();
  const r = edit('extrudeVertex', { vertex: v, offset: dir.map((x) => x * l) });
  if (r) { st.selV = [r.created[0]]; updateSelection(); drawSkeleton(); }
}

// Extrude the selected chain (a path or loop of edges) into a strip of quads: away from the faces its edges border,
// else along the normal of the chain's plane (Newell's normal; a straight chain: a perpendicular), one mean length of
// its edges. The new vertices are selected, to be moved on.
function extrudeChain() {
  const s = skel();
  let chain;
  try { chain = M.chainEdges(s, st.selV); } catch (e) { toast(`extrude: ${e.message}`); return; }
  let dir = [0, 0, 0], n = [0, 0, 0], l = 0;
  for (const [a, b] of chain) {
    const pa = s.points[a], pb = s.points[b];
    l += len3(sub3(pb, pa)) / chain.length;
    n = n.map((x, i) => x + (pa[(i + 1) % 3] - pb[(i + 1) % 3]) * (pa[(i + 2) % 3] + pb[(i + 2) % 3]));
    const fs = M.facesOfEdge(s, a, b);
    if (fs.length !== 1) continue;
    const f = s.faces[fs[0]];
    const c = [0, 1, 2].map((d) => f.reduce((acc, v) => acc + s.points[v][d], 0) / f.length);
    const mid = pa.map((x, i) => (x + pb[i]) / 2), ab = norm3(sub3(pb, pa)), out = sub3(mid, c);
    const along = out[0] * ab[0] + out[1] * ab[1] + out[2] * ab[2];
    dir = dir.map((x, i) => x + out[i] - along * ab[i]);
  }
  if (len3(dir) < 1e-12) dir = n;
  if (len3(dir) < 1e-9 * l * l) {
    const ab = norm3(sub3(s.points[chain[0][1]], s.points[chain[0][0]]));
    dir = Math.abs(ab[2]) < 0.9 ? [ab[1], -ab[0], 0] : [0, ab[2], -ab[1]];
  }
  dir = norm3(dir);
  const r = edit('extrudeChain', { vertices: st.selV.slice(), offset: dir.map((x) => x * l) });
  if (r) { st.selV = r.created.slice(0, st.selV.length); st.selE = null; updateSelection(); drawSkeleton(); }
}

function selectedEdge() {
  if (st.selE) return st.selE;
  if (st.selV.length === 2 && M.findEdge(skel(), st.selV[0], st.selV[1]) >= 0) return st.selV.slice();
  return null;
}

function op(name) {
  const s = skel();
  switch (name) {
    case 'add': {
      const p = orbit.target.toArray();
      const r = M.addVertex(s, p);
      commit(r.skeleton, 'add');
      st.selV = [r.vertex]; st.selE = null;
      updateSelection(); drawSkeleton();
      break;
    }
    case 'extrude': extrude(); break;
    case 'fill':
      if (st.selV.length !== 4) { toast('fill: select exactly 4 vertices'); return; }
      edit('fill', { vertices: st.selV.slice() });
      break;
    case 'connect':
      if (st.selV.length !== 2) { toast('connect: select exactly 2 vertices'); return; }
      edit('connect', { a: st.selV[0], b: st.selV[1] });
      break;
    case 'split': {
      const e = selectedEdge();
      if (!e) { toast('split: select an edge (click it, or select its 2 vertices)'); return; }
      if (edit('split', { a: e[0], b: e[1] })) { st.selE = null; st.selV = []; changed(); }
      break;
    }
    case 'merge':
      if (st.selV.length !== 2) { toast('merge: select exactly 2 vertices (the first one is kept)'); return; }
      if (edit('merge', { keep: st.selV[0], remove: st.selV[1] })) { st.selV = []; updateSelection(); drawSkeleton(); }
      break;
    case 'delete': {
      if (!st.selV.length && !st.selE) return;
      const args = { vertices: st.selV.slice(), edges: st.selE && !st.selV.length ? [st.selE] : [] };
      if (edit('delete', args)) { st.selV = []; st.selE = null; updateSelection(); drawSkeleton(); }
      break;
    }
  }
}

// ---------------------------------------------------------------- selection + gizmo
function updateSelection() {
  const s = skel();
  const info = $('selinfo');
  if (st.selE && !st.selV.length) info.textContent = `edge ${st.selE[0]}-${st.selE[1]}`;
  else if (st.selV.length) info.textContent = `${st.selV.length} vert${st.selV.length > 1 ? 'ices' : 'ex'}: ${st.selV.slice(0, 8).join(', ')}${st.selV.length > 8 ? '…' : ''}`;
  else info.textContent = 'nothing selected';
  const vs = st.selV.length ? st.selV : st.selE || [];
  if (vs.length && !$('brush').checked) {
    const c = [0, 1, 2].map((d) => vs.reduce((acc, v) => acc + s.points[v][d], 0) / vs.length);
    gizmoAnchor.position.set(...c);
    gizmo.attach(gizmoAnchor);
    // The gizmo's hover test (which decides whether a click is the gizmo's) uses its world matrices, otherwise only
    // brought up to date by the next frame: a click before that frame hit the gizmo where it was.
    gizmoAnchor.updateMatrixWorld();
    gizmoHelper.updateMatrixWorld(true);
    ['x', 'y', 'z'].forEach((k, d) => { $(`pos-${k}`).value = +c[d].toPrecision(8); });
    if (s.radii.length) $('radius').value = +s.radii[vs[0]].toPrecision(6);
  } else {
    gizmo.detach();
    ['x', 'y', 'z'].forEach((k) => { $(`pos-${k}`).value = ''; });
  }
  render();
}

function selectedVertexSet() {
  return st.selV.length ? st.selV.slice() : st.selE ? st.selE.slice() : [];
}

let dragStart = null;
gizmo.addEventListener('dragging-changed', (ev) => {
  orbit.enabled = !ev.value;
  if (ev.value) { dragStart = gizmoAnchor.position.clone(); return; }
  if (!dragStart) return;
  const offset = gizmoAnchor.position.clone().sub(dragStart).toArray();
  dragStart = null;
  if (len3(offset) === 0) return;
  moveSelection(offset);
});
gizmo.addEventListener('objectChange', () => {
  if (!dragStart) return;
  const offset = gizmoAnchor.position.clone().sub(dragStart).toArray();
  try {
    const r = M.applyEdit(skel(), 'move', { vertices: selectedVertexSet(), offset }, mirrorPlane(), sceneScale() * 1e-4);
    drawSkeleton(r.skeleton);
  } catch { /* preview only */ }
});

async function moveSelection(offset) {
  const r = edit('move', { vertices: selectedVertexSet(), offset });
  if (!r || !$('snap').checked || !st.domain) { updateSelection(); return; }
  // Snap every vertex that moved to the medial position of the domain (one more undoable step).
  const before = st.undo.past[st.undo.past.length - 1].state;
  const moved = skel().points.map((p, i) => i).filter((i) => len3(sub3(skel().points[i], before.points[i])) > 0);
  try {
    const res = await api.snapMedial(moved.map((i) => skel().points[i]));
    commit(M.moveVertices(skel(), moved, res.points).skeleton, 'snap');
  } catch (e) { toast(`snap: ${e.message}`); }
  updateSelection();
}

function moveTo(axis, value) {
  const vs = selectedVertexSet();
  if (!vs.length || !Number.isFinite(value)) return;
  const s = skel();
  const c = vs.reduce((acc, v) => acc + s.points[v][axis], 0) / vs.length;
  const offset = [0, 0, 0];
  offset[axis] = value - c;
  if (offset[axis] !== 0) moveSelection(offset);
}

// Picking: vertices first (screen distance), then edges.
function pick(ev) {
  const r = canvas.getBoundingClientRect();
  const x = ev.clientX - r.left, y = ev.clientY - r.top;
  const s = skel();
  let best = -1, bd = 10;
  s.points.forEach((p, i) => {
    const q = toScreen(p);
    if (q.behind) return;
    const d = Math.hypot(q.x - x, q.y - y);
    if (d < bd) { bd = d; best = i; }
  });
  if (best >= 0) return { vertex: best };
  let be = -1; bd = 6;
  s.edges.forEach((e, i) => {
    const a = toScreen(s.points[e[0]]), b = toScreen(s.points[e[1]]);
    if (a.behind || b.behind) return;
    const dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy || 1;
    const t = Math.max(0, Math.min(1, ((x - a.x) * dx + (y - a.y) * dy) / l2));
    const d = Math.hypot(a.x + t * dx - x, a.y + t * dy - y);
    if (d < bd) { bd = d; be = i; }
  });
  if (be >= 0) return { edge: s.edges[be].slice() };
  return null;
}

let down = null, brushStroke = null;
canvas.addEventListener('pointerdown', (ev) => {
  if (ev.button !== 0) return;
  if (gizmo.dragging || (gizmo.axis && gizmo.object)) return; // the gizmo takes it
  down = { x: ev.clientX, y: ev.clientY, shift: ev.shiftKey };
  if (ev.shiftKey) orbit.enabled = false;
  if ($('brush').checked && !skel().radii.length) toast('radius brush: the skeleton has no radii (set one, or take them from the domain)');
  if ($('brush').checked && skel().radii.length) {
    orbit.enabled = false;
    brushStroke = { start: skel(), current: skel() };
    brushAt(ev);
  }
});
canvas.addEventListener('pointermove', (ev) => {
  if (brushStroke) { brushAt(ev); return; }
  if (!down || !down.shift) return;
  const r = canvas.getBoundingClientRect();
  const b = $('boxsel');
  b.hidden = false;
  b.style.left = `${Math.min(down.x, ev.clientX) - r.left}px`;
  b.style.top = `${Math.min(down.y, ev.clientY) - r.top}px`;
  b.style.width = `${Math.abs(ev.clientX - down.x)}px`;
  b.style.height = `${Math.abs(ev.clientY - down.y)}px`;
});
window.addEventListener('pointerup', (ev) => {
  if (brushStroke) {
    const { start, current } = brushStroke;
    brushStroke = null;
    orbit.enabled = true;
    down = null;
    if (current !== start) { st.undo.push(current, 'brush'); changed(); }
    return;
  }
  if (!down) return;
  const d = down;
  down = null;
  orbit.enabled = true;
  $('boxsel').hidden = true;
  const moved = Math.hypot(ev.clientX - d.x, ev.clientY - d.y);
  if (d.shift && moved > 4) { // box select
    const r = canvas.getBoundingClientRect();
    const x0 = Math.min(d.x, ev.clientX) - r.left, x1 = Math.max(d.x, ev.clientX) - r.left;
    const y0 = Math.min(d.y, ev.clientY) - r.top, y1 = Math.max(d.y, ev.clientY) - r.top;
    const add = skel().points.map((p, i) => [toScreen(p), i]).filter(([q]) => !q.behind && q.x >= x0 && q.x <= x1 && q.y >= y0 && q.y <= y1).map(([, i]) => i);
    st.selV = [...new Set([...st.selV, ...add])];
    st.selE = null;
  } else if (moved <= 4 && ev.target === canvas) {
    const p = pick(ev);
    if (!p) { if (!d.shift) { st.selV = []; st.selE = null; } }
    else if (p.vertex !== undefined) {
      if (d.shift) st.selV = st.selV.includes(p.vertex) ? st.selV.filter((v) => v !== p.vertex) : [...st.selV, p.vertex];
      else st.selV = [p.vertex];
      st.selE = null;
    } else { st.selE = p.edge; st.selV = []; }
  } else return;
  updateSelection();
  drawSkeleton();
});

function brushAt(ev) {
  const r = canvas.getBoundingClientRect();
  const x = ev.clientX - r.left, y = ev.clientY - r.top;
  const R = 40; // brush radius in pixels
  const s = brushStroke.current;
  const vs = [], ws = [];
  s.points.forEach((p, i) => {
    const q = toScreen(p);
    const d = Math.hypot(q.x - x, q.y - y);
    if (!q.behind && d < R) { vs.push(i); ws.push(1 - d / R); }
  });
  if (!vs.length) return;
  try {
    const res = M.applyEdit(s, 'brush', { vertices: vs, weights: ws, factor: +$('brush-dir').value }, mirrorPlane(), sceneScale() * 1e-4);
    brushStroke.current = res.skeleton; // a preview: the stroke becomes one undo step on release
    drawSkeleton(res.skeleton);
  } catch (e) { toast(e.message); }
}

// ---------------------------------------------------------------- file and server actions
function setSkeleton(json, label, { frame = true } = {}) {
  const s = M.fromJson(json);
  st.selV = []; st.selE = null;
  st.undo.push(s, label);
  changed({ frame: frame === 'always' || (frame && !st.domain) });
}

function download(name, text, type = 'text/plain') {
  const a = document.createElement('a');
  a.href = typeof text === 'string' && text.startsWith('data:') ? text : URL.createObjectURL(new Blob([text], { type }));
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
}

async function guarded(what, fn) {
  try { await fn(); } catch (e) {
    toast(`${what}: ${e.message}`);
    if (e.where && e.where.kind !== 'none' && e.where.kind !== 'line') showError({ message: e.message, where: e.where });
  }
}

$('btn-auto').onclick = () => guarded('curve skeleton', async () => {
  const r = await api.autoSkeleton();
  setSkeleton(r.skeleton, 'auto skeleton');
});
$('file').onchange = (ev) => guarded('load', async () => {
  const f = ev.target.files[0];
  if (!f) return;
  const text = await f.text();
  const ext = f.name.split('.').pop().toLowerCase();
  const r = ext === 'ma' ? await api.importMa(text) : await api.parse(text, ext);
  setSkeleton(r.skeleton, `load ${f.name}`, { frame: 'always' });
  $('counts').dataset.file = f.name;
  ev.target.value = '';
});
for (const fmt of ['obj', 'ig'])
  $(`btn-save-${fmt}`).onclick = () => guarded(`save .${fmt}`, async () => {
    const text = await api.serialize(skel(), fmt);
    download(`skeleton.${fmt}`, text);
  });
$('btn-save').onclick = () => guarded('save', async () => {
  const fmt = /\.ig$/i.test(st.saveTarget || '') ? 'ig' : 'obj';
  const text = fmt === 'obj' ? M.toObj(skel()) : await api.serialize(skel(), 'ig');
  await api.save(text, fmt);
  toast(`saved to ${st.saveTarget}`);
});
$('btn-radius-domain').onclick = () => guarded('radius from the domain', async () => {
  if (!skel().points.length) return;
  const r = await api.radiusFromDomain(M.toBinary(skel()));
  commit(M.setAllRadii(skel(), r.radii).skeleton, 'radius from domain');
});
$('btn-radius').onclick = () => {
  const vs = selectedVertexSet();
  if (!vs.length) { toast('radius: select vertices'); return; }
  edit('radius', { vertices: vs, r: +$('radius').value });
};
$('btn-undo').onclick = () => { if (st.undo.undo()) changed(); };
$('btn-redo').onclick = () => { if (st.undo.redo()) changed(); };
$('btn-finish').onclick = finish;
$('btn-shot').onclick = () => { renderNow(); download('mesohex-studio.png', canvas.toDataURL('image/png')); };
document.querySelectorAll('[data-op]').forEach((b) => { b.onclick = () => op(b.dataset.op); });
['x', 'y', 'z'].forEach((k, d) => { $(`pos-${k}`).onchange = (ev) => { ev.target.blur(); moveTo(d, parseFloat(ev.target.value)); }; });
for (const id of ['v-mesh', 'v-wire', 'v-color', 'v-sing', 'v-clip', 'v-clip-axis', 'v-clip-flip', 'v-clip-pos', 'v-shrink', 'v-peel', 'v-stage', 'v-conn'])
  $(id).addEventListener('input', drawMesh);
$('v-domain').oninput = () => { groups.domain.visible = $('v-domain').checked; render(); };
$('v-skeleton').oninput = () => drawSkeleton();
$('v-radii').oninput = () => drawSkeleton();
$('mirror').oninput = () => drawSkeleton();
$('brush').oninput = () => updateSelection();

window.addEventListener('keydown', (ev) => {
  if (ev.target instanceof HTMLInputElement && ev.target.type !== 'checkbox' && ev.target.type !== 'range') return;
  if (ev.target instanceof HTMLSelectElement) return;
  const k = ev.key.toLowerCase();
  if ((ev.ctrlKey || ev.metaKey) && k === 'z') { ev.preventDefault(); (ev.shiftKey ? $('btn-redo') : $('btn-undo')).click(); return; }
  if ((ev.ctrlKey || ev.metaKey) && k === 'y') { ev.preventDefault(); $('btn-redo').click(); return; }
  if (ev.ctrlKey || ev.metaKey || ev.altKey) return;
  const map = { n: 'add', e: 'extrude', f: 'fill', c: 'connect', s: 'split', m: 'merge', delete: 'delete', backspace: 'delete' };
  if (map[k]) { ev.preventDefault(); op(map[k]); return; }
  if (k === 'b') { $('brush').checked = !$('brush').checked; updateSelection(); }
  if (k === 'escape') { st.selV = []; st.selE = null; updateSelection(); drawSkeleton(); }
});

function updateCounts() {
  const c = M.counts(skel());
  $('counts').textContent = `${c.V} vertices, ${c.E} edges, ${c.F} faces${skel().radii.length ? '' : ' (no radii)'}`;
  $('btn-undo').disabled = !st.undo.canUndo();
  $('btn-redo').disabled = !st.undo.canRedo();
}

// ---------------------------------------------------------------- start
async function start() {
  resize();
  updateLegend();
  drawHistogram([]);
  let sess = null;
  try { sess = await api.session(); } catch (e) { setStatus('error', `no session: ${e.message}`); }
  if (sess) {
    st.domain = sess.domain || null;
    st.saveTarget = sess.save_target || null;
    $('btn-save').hidden = !st.saveTarget;
    if (st.saveTarget) $('btn-save').textContent = `save (${st.saveTarget.split('/').pop()})`;
    $('btn-auto').disabled = !st.domain;
    $('btn-radius-domain').disabled = !st.domain;
    $('snap').disabled = !st.domain;
    drawDomain();
    const sk = sess.skeleton || sess.medial;
    st.undo = new M.UndoStack(sk ? M.fromJson(sk) : M.emptySkeleton());
  }
  frameAll();
  changed({ frame: !st.domain });
  st.ready = true;
}

// Test and scripting hooks (read-only views of the state, plus screen positions for clicking).
window.studio = {
  state: st,
  skeleton: skel,
  screenPosition: (v) => { const r = canvas.getBoundingClientRect(); const p = toScreen(skel().points[v]); return { x: r.left + p.x, y: r.top + p.y }; },
  hexCount: () => V.hexCount(currentMeshResponse()?.mesh),
  select: (vertices) => { st.selV = vertices.slice(); st.selE = null; updateSelection(); drawSkeleton(); },
  renderNow,
  frameAll,
  // Raw-mesh requests sent as deltas and as whole skeletons (tests), and a way to forget the server's session (tests:
  // the next request then sends a delta for a revision the server does not hold and must recover).
  meshUploads: () => ({ deltas: session.deltas, full: session.full, patches: session.patches }),
  spoilSession: () => { session.baseRevision += 1000; },
};

start();
