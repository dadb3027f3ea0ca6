// The script of the `foldfill serve` page: it opens a mesh (an upload to
// POST /api/mesh, or the one the server was started with), outlines its loops
// and lets one pick them, starts a fill (POST /api/fill), shows its progress
// (GET /api/progress) with a cancel button, then the result (GET /api/result)
// with its report; GET /api/download gives the file. Meshes come as base64
// binary buffers, as in the `view` page, whose stylesheet it shares.
// The edit tool drags a point of a patch (POST /api/edit/begin, move, end;
// POST /api/undo); "compare with Liepa" shows CGAL's fill of the same holes
// (GET /api/liepa) in a second panel with the same camera; obstacles are set
// as the CLI's obstacles JSON (POST /api/obstacles) or a mesh file
// (POST /api/obstacle-mesh) and drawn in both panels.
import * as THREE from '/three.js';

const BACKGROUND = 0xf4f4f2;
const INPUT_COLOUR = 0xc9c4b8;
const LOOP_COLOUR = 0x2060d0;
const SELECTED_COLOUR = 0xff7a00;

const $ = (id) => document.getElementById(id);

// The page's state, read by the browser tests.
const state = {mesh: null, result: null, liepa: null, selected: new Set(), useDefault: true, job: 0,
               running: false, error: null, obstacles: [],
               edit: {on: false, dragging: false, vertex: -1, hole: -1, inFlight: false, target: null,
                      moves: 0, ends: 0, undos: 0, lastMs: 0}};
window.foldfillServe = state;

function decodeBase64(text) {
  const binary = atob(text);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
  return bytes.buffer;
}

function showError(text) {
  state.error = text || null;
  $('error').textContent = text || '';
  $('error').hidden = !text;
}

async function api(path, options = {}) {
  const response = await fetch(path, options);
  const body = await response.json().catch(() => ({error: `${response.status} ${response.statusText}`}));
  if (!response.ok) throw new Error(body.error || `${response.status} ${response.statusText}`);
  return body;
}

// ---- rendering ----

const canvas = $('canvas');
const renderer = new THREE.WebGLRenderer({canvas, antialias: true, preserveDrawingBuffer: true});
renderer.setPixelRatio(window.devicePixelRatio || 1);
renderer.setClearColor(BACKGROUND);
const scene = new THREE.Scene();
scene.add(new THREE.HemisphereLight(0xffffff, 0x606060, 2.2));
const light = new THREE.DirectionalLight(0xffffff, 1.6);
scene.add(light);
const camera = new THREE.PerspectiveCamera(35, 1, 0.01, 100);
const view = {target: new THREE.Vector3(), distance: 1, azimuth: 0.5, elevation: 0.6, radius: 1};
let surface = null, wire = null, loopLines = null;
// The Liepa panel: its own renderer and scene, the same camera.
const canvas2 = $('canvas2');
const renderer2 = new THREE.WebGLRenderer({canvas: canvas2, antialias: true, preserveDrawingBuffer: true});
renderer2.setPixelRatio(window.devicePixelRatio || 1);
renderer2.setClearColor(BACKGROUND);
const scene2 = new THREE.Scene();
scene2.add(new THREE.HemisphereLight(0xffffff, 0x606060, 2.2));
const light2 = new THREE.DirectionalLight(0xffffff, 1.6);
scene2.add(light2);
let surface2 = null;
let obstacleGroups = [];  // one per scene

function holeColour(hole) {
  return new THREE.Color().setHSL((0.07 + Math.max(0, hole) * 0.381966) % 1, 0.8, 0.52);
}

// A three.js geometry of one mesh reply (mesh_buffers in app/serve.cpp),
// faces coloured by their hole when the reply has face_hole.
function geometryOf(reply) {
  // Kept on the reply: the edit tool moves the result's vertices in place.
  const positions = reply.vertexPositions ||
                    (reply.vertexPositions = new Float32Array(decodeBase64(reply.positions)));
  const index = new Uint32Array(decodeBase64(reply.index));
  const holes = reply.face_hole ? new Int32Array(decodeBase64(reply.face_hole)) : null;
  // Unshared corners, so that each face has its own colour.
  const corner = new Float32Array(index.length * 3), colours = new Float32Array(index.length * 3);
  const base = new THREE.Color(INPUT_COLOUR);
  for (let i = 0; i < index.length; ++i) {
    corner.set(positions.subarray(index[i] * 3, index[i] * 3 + 3), i * 3);
    const hole = holes ? holes[Math.floor(i / 3)] : -1;
    const c = hole >= 0 ? holeColour(hole) : base;
    colours[i * 3] = c.r; colours[i * 3 + 1] = c.g; colours[i * 3 + 2] = c.b;
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(corner, 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
  geometry.computeVertexNormals();
  geometry.computeBoundingSphere();
  return {geometry, positions, index};
}

function surfaceMaterial() {
  return new THREE.MeshStandardMaterial(
      {vertexColors: true, side: THREE.DoubleSide, flatShading: true, roughness: 0.85,
       polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1});
}

function shownReply() {
  return $('show-result').checked && state.result ? state.result : state.mesh;
}

function rebuild() {
  for (const object of [surface, wire, loopLines]) {
    if (object) { scene.remove(object); object.geometry.dispose(); }
  }
  surface = wire = loopLines = null;
  const reply = shownReply();
  if (!reply) return requestRender();
  const {geometry, positions, index} = geometryOf(reply);
  surface = new THREE.Mesh(geometry, surfaceMaterial());
  surface.userData = {reply, positions, index};
  scene.add(surface);
  wire = new THREE.LineSegments(new THREE.WireframeGeometry(geometry),
                                new THREE.LineBasicMaterial({color: 0x333333}));
  wire.visible = $('wireframe').checked;
  scene.add(wire);
  if (reply === state.mesh) drawLoops();
  requestRender();
}

// The input's loops as lines, the selected ones in orange.
function drawLoops() {
  if (loopLines) { scene.remove(loopLines); loopLines.geometry.dispose(); loopLines = null; }
  const mesh = state.mesh;
  if (!mesh || shownReply() !== mesh) return;
  const positions = mesh.vertexPositions;
  const points = [], colours = [];
  for (const loop of mesh.loops) {
    const c = new THREE.Color(isSelected(loop.id) ? SELECTED_COLOUR : LOOP_COLOUR);
    const n = loop.vertices.length;
    for (let k = 0; k < n; ++k) {
      for (const v of [loop.vertices[k], loop.vertices[(k + 1) % n]]) {
        points.push(positions[v * 3], positions[v * 3 + 1], positions[v * 3 + 2]);
        colours.push(c.r, c.g, c.b);
      }
    }
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(points, 3));
  geometry.setAttribute('color', new THREE.Float32BufferAttribute(colours, 3));
  loopLines = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial(
      {vertexColors: true, depthTest: false}));
  loopLines.renderOrder = 1;
  scene.add(loopLines);
}

function frameView() {
  const sphere = surface ? surface.geometry.boundingSphere : new THREE.Sphere(new THREE.Vector3(), 1);
  view.target.copy(sphere.center);
  view.radius = Math.max(sphere.radius, 1e-9);
  view.distance = view.radius / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2)) * 1.05;
  requestRender();
}

function placeCamera() {
  const c = Math.cos(view.elevation);
  camera.position.set(view.target.x + view.distance * c * Math.sin(view.azimuth),
                      view.target.y + view.distance * Math.sin(view.elevation),
                      view.target.z + view.distance * c * Math.cos(view.azimuth));
  camera.lookAt(view.target);
  camera.near = Math.max(view.distance - view.radius * 2, view.distance * 1e-3);
  camera.far = view.distance + view.radius * 2;
  camera.updateProjectionMatrix();
  light.position.copy(camera.position);
}

// Screen position (CSS pixels in the canvas) of a point, or null behind the camera.
function toScreen(x, y, z) {
  const p = new THREE.Vector3(x, y, z).project(camera);
  if (p.z > 1) return null;
  return {x: (p.x + 1) / 2 * canvas.clientWidth, y: (1 - p.y) / 2 * canvas.clientHeight};
}

function placeLabels() {
  const layer = $('labels');
  layer.replaceChildren();
  const mesh = state.mesh;
  if (!mesh || shownReply() !== mesh) return;
  const p = mesh.vertexPositions;
  for (const loop of mesh.loops) {
    // A hole's id in its middle; an outer edge's or a tube end's on the loop.
    const v = loop.vertices[0] * 3;
    const at = loop.kind === 'hole' ? toScreen(...loop.centroid) : toScreen(p[v], p[v + 1], p[v + 2]);
    if (!at) continue;
    const label = document.createElement('span');
    label.className = 'loop-label';
    label.dataset.loop = loop.id;
    label.textContent = loop.id;
    label.style.left = `${at.x}px`;
    label.style.top = `${at.y}px`;
    label.style.pointerEvents = 'auto';
    label.style.cursor = 'pointer';
    label.style.background = isSelected(loop.id) ? '#ffe2c4' : 'rgba(255, 255, 255, 0.85)';
    label.addEventListener('click', (e) => clickLoop(loop.id, e));
    layer.appendChild(label);
  }
}

let pending = false;
function requestRender() {
  if (pending) return;
  pending = true;
  requestAnimationFrame(() => {
    pending = false;
    const width = canvas.clientWidth, height = canvas.clientHeight;
    renderer.setSize(width, height, false);
    camera.aspect = width / Math.max(height, 1);
    placeCamera();
    light2.position.copy(camera.position);
    renderer.render(scene, camera);
    if (!$('stage2').hidden) {
      renderer2.setSize(canvas2.clientWidth, canvas2.clientHeight, false);
      renderer2.render(scene2, camera);
    }
    placeLabels();
    state.frames = (state.frames || 0) + 1;
  });
}
new ResizeObserver(requestRender).observe(canvas);
new ResizeObserver(requestRender).observe(canvas2);

let drag = null;
canvas.addEventListener('contextmenu', (e) => e.preventDefault());
canvas.addEventListener('pointerdown', (e) => {
  canvas.setPointerCapture(e.pointerId);
  if (state.edit.on && e.button === 0 && !e.shiftKey && beginEdit(e)) return;
  drag = {x: e.clientX, y: e.clientY, startX: e.clientX, startY: e.clientY,
          pan: e.button !== 0 || e.shiftKey};
});
canvas.addEventListener('pointermove', (e) => {
  if (state.edit.dragging) return moveEdit(e);
  if (!drag) return;
  const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
  drag.x = e.clientX;
  drag.y = e.clientY;
  turnOrPan(dx, dy, drag.pan);
});
canvas.addEventListener('pointerup', (e) => {
  if (state.edit.dragging) return endEdit();
  const click = drag && e.button === 0 &&
                Math.hypot(e.clientX - drag.startX, e.clientY - drag.startY) < 4;
  drag = null;
  if (click) pickLoop(e);
});
// The Liepa panel turns, pans and zooms the same camera.
let drag2 = null;
canvas2.addEventListener('contextmenu', (e) => e.preventDefault());
canvas2.addEventListener('pointerdown', (e) => {
  canvas2.setPointerCapture(e.pointerId);
  drag2 = {x: e.clientX, y: e.clientY, pan: e.button !== 0 || e.shiftKey};
});
canvas2.addEventListener('pointermove', (e) => {
  if (!drag2) return;
  const dx = e.clientX - drag2.x, dy = e.clientY - drag2.y;
  drag2.x = e.clientX;
  drag2.y = e.clientY;
  turnOrPan(dx, dy, drag2.pan);
});
canvas2.addEventListener('pointerup', () => { drag2 = null; });

function turnOrPan(dx, dy, pan) {
  const height = canvas.clientHeight || 1;
  if (pan) {
    const scale = 2 * view.distance * Math.tan(THREE.MathUtils.degToRad(camera.fov / 2)) / height;
    const right = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 0);
    const up = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 1);
    view.target.addScaledVector(right, -dx * scale).addScaledVector(up, dy * scale);
  } else {
    view.azimuth -= dx * Math.PI / height;
    view.elevation = THREE.MathUtils.clamp(view.elevation + dy * Math.PI / height,
                                           -Math.PI / 2 + 1e-3, Math.PI / 2 - 1e-3);
  }
  requestRender();
}

// The wheel zooms the one camera, from either panel.
function zoom(e) {
  e.preventDefault();
  view.distance *= Math.exp(e.deltaY * 0.001);
  requestRender();
}
canvas.addEventListener('wheel', zoom, {passive: false});
canvas2.addEventListener('wheel', zoom, {passive: false});

// A click on the canvas picks the loop with a vertex or edge midpoint
// nearest on screen, within 12 pixels.
function pickLoop(e) {
  const mesh = state.mesh;
  if (!mesh || shownReply() !== mesh) return;
  const rect = canvas.getBoundingClientRect();
  const x = e.clientX - rect.left, y = e.clientY - rect.top;
  const p = mesh.vertexPositions;
  let best = null, bestDistance = 12;
  for (const loop of mesh.loops) {
    const n = loop.vertices.length;
    for (let k = 0; k < n; ++k) {
      const a = loop.vertices[k] * 3, b = loop.vertices[(k + 1) % n] * 3;
      for (const t of [0, 0.5]) {
        const at = toScreen(p[a] + (p[b] - p[a]) * t, p[a + 1] + (p[b + 1] - p[a + 1]) * t,
                            p[a + 2] + (p[b + 2] - p[a + 2]) * t);
        if (!at) continue;
        const d = Math.hypot(at.x - x, at.y - y);
        if (d < bestDistance) { bestDistance = d; best = loop.id; }
      }
    }
  }
  if (best !== null) clickLoop(best, e);
}

// ---- loops and selection ----

function isSelected(id) {
  return state.useDefault ? state.mesh.default_holes.includes(id) : state.selected.has(id);
}

// A click selects the loop alone; with Shift, Ctrl or Cmd it adds or removes it.
function clickLoop(id, event) {
  const add = event && (event.shiftKey || event.ctrlKey || event.metaKey);
  if (state.useDefault) state.selected = new Set(add ? state.mesh.default_holes : []);
  state.useDefault = false;
  if (!add) state.selected = new Set([id]);
  else if (state.selected.has(id)) state.selected.delete(id);
  else state.selected.add(id);
  showSelection();
}

function showSelection() {
  const list = $('loop-list');
  list.replaceChildren();
  for (const loop of state.mesh ? state.mesh.loops : []) {
    const item = document.createElement('li');
    item.dataset.loop = loop.id;
    item.className = isSelected(loop.id) ? 'selected' : '';
    item.textContent = `loop ${loop.id}: ${loop.kind.replaceAll("_", " ")}, ${loop.vertex_count} vertices, ` +
                       `length ${loop.length.toPrecision(4)}`;
    item.title = loop.explanation || '';
    item.addEventListener('click', (e) => clickLoop(loop.id, e));
    list.appendChild(item);
  }
  $('default-selection').classList.toggle('on', state.useDefault);
  $('fill').disabled = !state.mesh || state.running ||
                       (!state.useDefault && state.selected.size === 0);
  drawLoops();
  requestRender();
}

$('default-selection').addEventListener('click', () => {
  state.useDefault = true;
  state.selected.clear();
  showSelection();
});

// ---- the mesh ----

function setDefaults(defaults) {
  for (const key of ['lambda', 'shrink', 'density', 'repulsion']) {
    if (defaults && $(key).value === '') $(key).value = defaults[key];
  }
}

function openMesh(reply) {
  reply.vertexPositions = new Float32Array(decodeBase64(reply.positions));
  state.mesh = reply;
  state.result = null;
  state.useDefault = true;
  state.selected.clear();
  $('mesh-name').textContent = `${reply.name}: ${reply.vertex_count} vertices, ` +
                               `${reply.face_count} faces, ${reply.loops.length} loops`;
  $('show-input').checked = true;
  $('show-result').disabled = true;
  $('download').disabled = true;
  $('report').hidden = true;
  $('edit').disabled = true;
  $('undo').disabled = true;
  showLiepa(null);
  $('progress').textContent = reply.warnings.length ? `warnings: ${reply.warnings.join('; ')}` : '';
  setDefaults(reply.defaults);
  rebuild();
  frameView();
  showSelection();
}

$('file').addEventListener('change', async () => {
  const file = $('file').files[0];
  if (!file) return;
  showError(null);
  try {
    openMesh(await api(`/api/mesh?name=${encodeURIComponent(file.name)}`,
                       {method: 'POST', body: await file.arrayBuffer()}));
  } catch (error) {
    showError(error.message);
  }
});

// ---- the fill ----

function request() {
  const body = {holes: state.useDefault ? 'default' : [...state.selected].sort((a, b) => a - b),
                method: $('method').value, bending: $('bending').value,
                compare_liepa: $('compare-liepa').checked};
  for (const key of ['lambda', 'shrink', 'density', 'repulsion']) {
    if ($(key).value !== '') body[key] = Number($(key).value);
  }
  return body;
}

function setRunning(running) {
  state.running = running;
  $('cancel').disabled = !running;
  $('file').disabled = running;
  showSelection();
}

$('fill').addEventListener('click', async () => {
  showError(null);
  try {
    const {job} = await api('/api/fill', {method: 'POST', headers: {'Content-Type': 'application/json'},
                                          body: JSON.stringify(request())});
    state.job = job;
    setRunning(true);
    $('progress').textContent = 'starting';
    poll();
  } catch (error) {
    showError(error.message);
  }
});

$('cancel').addEventListener('click', () => {
  api('/api/cancel', {method: 'POST'}).catch((error) => showError(error.message));
});

async function poll() {
  let progress;
  try {
    progress = await api('/api/progress');
  } catch (error) {
    setRunning(false);
    return showError(error.message);
  }
  if (!progress.done) {
    $('progress').textContent = progress.hole < 0 ? 'starting'
        : `hole ${progress.hole}: iteration ${progress.iteration}, energy ${progress.energy.toPrecision(6)}` +
          (progress.cancelled ? ' (cancelling)' : '');
    setTimeout(poll, 200);
    return;
  }
  setRunning(false);
  if (progress.error) return showError(progress.error);
  try {
    showResult(await api('/api/result'));
  } catch (error) {
    showError(error.message);
  }
}

const COLUMNS = [
  ['loop', (h) => h.loop_id], ['status', (h) => h.status ?? (h.filled ? 'filled' : 'open')],
  ['patch vertices', (h) => h.patch_vertex_count], ['patch faces', (h) => h.patch_face_count],
  ['iterations', (h) => h.iterations], ['stop', (h) => h.stop_reason],
  ['seconds', (h) => h.seconds?.total], ['energy', (h) => h.energy?.final?.total],
  ['area / flat', (h) => h.area_ratio_to_flat], ['edge rms', (h) => h.edge_length_rms_rel?.final],
  ['min angle', (h) => h.patch_min_angle_deg], ['crossings', (h) => h.self_intersections],
  ['reason', (h) => h.reason ?? h.warning],
];

function cell(value) {
  if (value === undefined || value === null) return '';
  if (typeof value === 'number') return Number.isInteger(value) ? String(value) : value.toPrecision(5);
  if (typeof value === 'object') return JSON.stringify(value);
  return String(value);
}

function showReport(table, report) {
  const holes = report.holes || [];
  table.replaceChildren();
  const head = table.insertRow();
  for (const [name] of COLUMNS) {
    const th = document.createElement('th');
    th.textContent = name;
    head.appendChild(th);
  }
  for (const hole of holes) {
    const row = table.insertRow();
    row.dataset.loop = hole.loop_id;
    for (const [name, get] of COLUMNS) {
      const td = row.insertCell();
      td.dataset.column = name;
      td.textContent = cell(get(hole));
    }
  }
}

function showResult(result) {
  state.result = result;
  state.liepa = null;
  const report = result.report;
  const holes = report.holes || [];
  const filled = holes.filter((h) => h.filled).length;
  $('progress').textContent = `${report.cancelled ? 'cancelled: ' : 'done: '}${filled} of ` +
                              `${holes.length} holes filled, ${result.face_count - result.input_face_count} new faces`;
  showReport($('report-table'), report);
  $('report').hidden = false;
  $('show-result').disabled = false;
  $('show-result').checked = true;
  $('download').disabled = false;
  $('edit').disabled = false;
  $('undo').disabled = !result.undo;
  rebuild();
  showLiepa(null);
  if (result.liepa) {
    api('/api/liepa').then(showLiepa).catch((error) => showError(error.message));
  }
}

// ---- the Liepa panel ----

function showLiepa(liepa) {
  state.liepa = liepa;
  if (surface2) { scene2.remove(surface2); surface2.geometry.dispose(); surface2 = null; }
  $('stage2').hidden = !liepa;
  $('liepa-report').hidden = !liepa;
  if (liepa) {
    surface2 = new THREE.Mesh(geometryOf(liepa).geometry, surfaceMaterial());
    scene2.add(surface2);
    showReport($('liepa-table'), liepa.report);
  }
  requestRender();
}

// ---- obstacles ----

function showObstacles(reply) {
  for (const group of obstacleGroups) group.parent.remove(group);
  obstacleGroups = [];
  state.obstacles = reply.obstacles;
  const material = new THREE.MeshStandardMaterial({color: 0x4f8fbf, transparent: true, opacity: 0.35,
                                                   side: THREE.DoubleSide, depthWrite: false});
  for (const target of [scene, scene2]) {
    const group = new THREE.Group();
    for (const obstacle of reply.obstacles) {
      const positions = new Float32Array(decodeBase64(obstacle.positions));
      const index = new Uint32Array(decodeBase64(obstacle.index));
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
      geometry.setIndex(new THREE.BufferAttribute(index, 1));
      geometry.computeVertexNormals();
      group.add(new THREE.Mesh(geometry, material));
    }
    group.renderOrder = 2;
    target.add(group);
    obstacleGroups.push(group);
  }
  $('clear-obstacle-mesh').disabled = !reply.mesh_obstacle;
  $('obstacles-status').textContent = reply.obstacles.length
      ? `${reply.obstacles.length} obstacles: ${reply.obstacles.map((o) => o.type).join(', ')} (for the next fill)`
      : '';
  requestRender();
}

$('set-obstacles').addEventListener('click', async () => {
  showError(null);
  try {
    showObstacles(await api('/api/obstacles', {method: 'POST', body: $('obstacles-json').value.trim()}));
  } catch (error) {
    showError(error.message);
  }
});

$('obstacle-file').addEventListener('change', async () => {
  const file = $('obstacle-file').files[0];
  if (!file) return;
  showError(null);
  try {
    showObstacles(await api(`/api/obstacle-mesh?name=${encodeURIComponent(file.name)}`,
                            {method: 'POST', body: await file.arrayBuffer()}));
  } catch (error) {
    showError(error.message);
  }
});

$('clear-obstacle-mesh').addEventListener('click', async () => {
  $('obstacle-file').value = '';
  try {
    showObstacles(await api('/api/obstacle-mesh', {method: 'POST', body: ''}));
  } catch (error) {
    showError(error.message);
  }
});

// ---- the edit tool ----

const postJson = (path, body) => api(path, {method: 'POST', headers: {'Content-Type': 'application/json'},
                                            body: JSON.stringify(body)});
const raycaster = new THREE.Raycaster();

// The new vertex of a patch face under the pointer nearest the point hit,
// with that point, or null.
function pickPatchVertex(e) {
  const reply = state.result;
  if (!surface || !reply || shownReply() !== reply || !reply.face_hole) return null;
  const rect = canvas.getBoundingClientRect();
  const pointer = new THREE.Vector2((e.clientX - rect.left) / rect.width * 2 - 1,
                                    -((e.clientY - rect.top) / rect.height) * 2 + 1);
  placeCamera();
  raycaster.setFromCamera(pointer, camera);
  const hit = raycaster.intersectObject(surface)[0];
  if (!hit) return null;
  const face = Math.floor(hit.face.a / 3);  // corners are unshared: 3 per face
  const holes = reply.faceHoles || (reply.faceHoles = new Int32Array(decodeBase64(reply.face_hole)));
  if (holes[face] < 0) return null;
  const {positions, index} = surface.userData;
  const firstNew = state.mesh.vertex_count;
  let best = -1, bestDistance = Infinity;
  for (let k = 0; k < 3; ++k) {
    const v = index[face * 3 + k];
    if (v < firstNew) continue;
    const d = hit.point.distanceToSquared(new THREE.Vector3(positions[v * 3], positions[v * 3 + 1], positions[v * 3 + 2]));
    if (d < bestDistance) { bestDistance = d; best = v; }
  }
  return best < 0 ? null : {vertex: best, hole: holes[face]};
}

// Writes a patch's positions (an edit reply) into the shown surface.
function applyPatch(reply) {
  if (!surface) return;
  const {positions, index} = surface.userData;
  positions.set(new Float32Array(decodeBase64(reply.positions)), reply.first * 3);
  const corner = surface.geometry.attributes.position.array;
  const end = reply.first + reply.count;
  for (let i = 0; i < index.length; ++i) {
    const v = index[i];
    if (v >= reply.first && v < end) corner.set(positions.subarray(v * 3, v * 3 + 3), i * 3);
  }
  surface.geometry.attributes.position.needsUpdate = true;
  surface.geometry.computeVertexNormals();
  if (wire && wire.visible) {
    wire.geometry.dispose();
    wire.geometry = new THREE.WireframeGeometry(surface.geometry);
  }
  requestRender();
}

function beginEdit(e) {
  const picked = pickPatchVertex(e);
  if (!picked) return false;
  const {positions} = surface.userData;
  const p = new THREE.Vector3(positions[picked.vertex * 3], positions[picked.vertex * 3 + 1],
                              positions[picked.vertex * 3 + 2]);
  const normal = new THREE.Vector3();
  camera.getWorldDirection(normal);
  state.edit = {...state.edit, dragging: true, vertex: picked.vertex, hole: picked.hole, target: null,
                plane: new THREE.Plane().setFromNormalAndCoplanarPoint(normal, p), began: null};
  $('edit-status').textContent = `loop ${picked.hole}: vertex ${picked.vertex}`;
  state.edit.began = postJson('/api/edit/begin', {vertex: picked.vertex, hole: picked.hole})
      .catch((error) => { state.edit.dragging = false; showError(error.message); });
  return true;
}

// The pointer's point on the drag plane; one move request at a time, the
// latest target sent when the one in flight comes back.
function moveEdit(e) {
  const rect = canvas.getBoundingClientRect();
  const pointer = new THREE.Vector2((e.clientX - rect.left) / rect.width * 2 - 1,
                                    -((e.clientY - rect.top) / rect.height) * 2 + 1);
  raycaster.setFromCamera(pointer, camera);
  const target = new THREE.Vector3();
  if (!raycaster.ray.intersectPlane(state.edit.plane, target)) return;
  state.edit.target = target;
  if (!state.edit.inFlight) sendMove();
}

async function sendMove() {
  const edit = state.edit;
  if (!edit.target) return;
  edit.inFlight = true;
  await edit.began;
  while (edit.target && edit.dragging) {
    const t = edit.target;
    edit.target = null;
    const start = performance.now();
    try {
      applyPatch(await postJson('/api/edit/move', {x: t.x, y: t.y, z: t.z}));
      edit.moves += 1;
      edit.lastMs = performance.now() - start;
      $('edit-status').textContent = `loop ${edit.hole}: vertex ${edit.vertex}, ${edit.lastMs.toFixed(0)} ms per update`;
    } catch (error) {
      showError(error.message);
      break;
    }
  }
  edit.inFlight = false;
}

async function endEdit() {
  const edit = state.edit;
  edit.dragging = false;
  await edit.began;
  while (edit.inFlight) await new Promise((resolve) => setTimeout(resolve, 10));
  try {
    const reply = await postJson('/api/edit/end', {});
    applyPatch(reply);
    state.result.report = reply.report;
    showReport($('report-table'), reply.report);
    $('undo').disabled = reply.undo === 0;
    edit.ends += 1;
  } catch (error) {
    showError(error.message);
  }
}

$('edit').addEventListener('change', () => {
  state.edit.on = $('edit').checked;
  document.body.classList.toggle('editing', state.edit.on);
});

$('undo').addEventListener('click', async () => {
  try {
    const reply = await postJson('/api/undo', {});
    applyPatch(reply);
    state.result.report = reply.report;
    showReport($('report-table'), reply.report);
    $('undo').disabled = reply.undo === 0;
    state.edit.undos += 1;
  } catch (error) {
    showError(error.message);
  }
});

$('download').addEventListener('click', () => {
  window.location.href = `/api/download?format=${$('format').value}`;
});

for (const id of ['show-input', 'show-result']) $(id).addEventListener('change', rebuild);
$('wireframe').addEventListener('change', () => {
  if (wire) wire.visible = $('wireframe').checked;
  requestRender();
});

// The mesh the server was started with, if any, and the obstacles set.
try {
  const reply = await api('/api/mesh');
  if (reply.mesh === null) setDefaults(reply.defaults); else openMesh(reply);
  showObstacles(await api('/api/obstacles'));
} catch (error) {
  showError(error.message);
}
// For the browser tests: where a vertex of the shown mesh is on the page.
state.screenOf = (v) => {
  const p = surface.userData.positions;
  const at = toScreen(p[v * 3], p[v * 3 + 1], p[v * 3 + 2]);
  const rect = canvas.getBoundingClientRect();
  return at && {x: at.x + rect.left, y: at.y + rect.top};
};
state.ready = true;
