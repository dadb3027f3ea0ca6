// The script of a `foldfill view` page. The page holds a JSON header
// (#foldfill-meta), the meshes as one base64 binary blob (#foldfill-blob) that
// the header's buffers are views into, and three.js as text
// (#foldfill-three), imported from a blob: URL so that the page works from
// file:// without any other file.

// Milliseconds since navigation at each step of the start (the benchmark reads them).
const timings = {script: performance.now()};
const meta = JSON.parse(document.getElementById('foldfill-meta').textContent);
const threeText = document.getElementById('foldfill-three').textContent;
const THREE = await import(URL.createObjectURL(new Blob([threeText], {type: 'text/javascript'})));
timings.three = performance.now();

const BACKGROUND = 0xf4f4f2;
const INPUT_COLOUR = 0xc9c4b8;
const UNKNOWN_HOLE_COLOUR = 0xd0308f;
const UNKNOWN_HOLE = -2;
const NO_CURVATURE_COLOUR = [150, 150, 150];

function showMessage(text) {
  const box = document.getElementById('message');
  box.textContent = text;
  box.hidden = false;
}

function decodeBase64(text) {
  if (typeof Uint8Array.fromBase64 === 'function') return Uint8Array.fromBase64(text);
  const binary = atob(text);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
  return bytes;
}

const blob = decodeBase64(document.getElementById('foldfill-blob').textContent).buffer;
timings.decoded = performance.now();
const ARRAY_TYPES = {float32: Float32Array, uint32: Uint32Array, uint8: Uint8Array};
function bufferView(desc) {
  return new ARRAY_TYPES[desc.type](blob, desc.offset, desc.length);
}

// One colour per hole, by its place among the page's holes: hues a golden
// angle apart, starting at orange.
function holeColour(hole) {
  if (hole === UNKNOWN_HOLE) return new THREE.Color(UNKNOWN_HOLE_COLOUR);
  const place = Math.max(0, meta.holes.indexOf(hole));
  return new THREE.Color().setHSL((0.07 + place * 0.381966) % 1, 0.8, 0.52);
}
function cssColour(hole) { return '#' + holeColour(hole).getHexString(); }

// Diverging blue, grey, red for curvature bytes 1..255 (0: no value), as
// the legend's sRGB gradient, stored linear as three.js takes vertex colours.
const CURVATURE_LUT = (() => {
  const stops = [[0x3b, 0x4c, 0xc0], [0xdd, 0xdd, 0xdd], [0xb4, 0x04, 0x26]];
  const linear = (srgb) => {
    const c = srgb / 255;
    return Math.round(255 * (c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4));
  };
  const lut = new Uint8Array(256 * 3);
  lut.set(NO_CURVATURE_COLOUR.map(linear), 0);
  for (let q = 1; q < 256; ++q) {
    const t = (q - 1) / 254 * 2;
    const [a, b] = t < 1 ? [stops[0], stops[1]] : [stops[1], stops[2]];
    const s = t < 1 ? t : t - 1;
    for (let c = 0; c < 3; ++c) lut[q * 3 + c] = linear(a[c] + (b[c] - a[c]) * s);
  }
  return lut;
})();

// Area-weighted vertex normals over the first `indexCount` entries of `index`.
function vertexNormals(positions, index, indexCount, vertexCount) {
  const normals = new Float32Array(vertexCount * 3);
  for (let i = 0; i < indexCount; i += 3) {
    const a = index[i] * 3, b = index[i + 1] * 3, c = index[i + 2] * 3;
    const ux = positions[b] - positions[a], uy = positions[b + 1] - positions[a + 1],
          uz = positions[b + 2] - positions[a + 2];
    const vx = positions[c] - positions[a], vy = positions[c + 1] - positions[a + 1],
          vz = positions[c + 2] - positions[a + 2];
    const nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    for (const v of [a, b, c]) {
      normals[v] += nx;
      normals[v + 1] += ny;
      normals[v + 2] += nz;
    }
  }
  for (let v = 0; v < normals.length; v += 3) {
    const length = Math.hypot(normals[v], normals[v + 1], normals[v + 2]) || 1;
    normals[v] /= length;
    normals[v + 1] /= length;
    normals[v + 2] /= length;
  }
  return normals;
}

const settings = {
  layout: meta.layout,
  overlaid: meta.meshes.length - 1,  // the panel shown when overlaid
  colour: 'holes',
  wireframe: false,
  flat: false,
  loops: true,
};

// One attribute per buffer: a mesh whose buffers are the first part of
// another's (the input's, of a fill that starts with it) draws from the same
// attribute, so that it is uploaded once.
const bufferLengths = new Map();
for (const mesh of meta.meshes) {
  for (const desc of [mesh.positions, mesh.index]) {
    bufferLengths.set(desc.offset, Math.max(bufferLengths.get(desc.offset) || 0, desc.length));
  }
}
const sharedAttributes = new Map();
function sharedAttribute(desc, itemSize) {
  if (!sharedAttributes.has(desc.offset)) {
    const whole = {...desc, length: bufferLengths.get(desc.offset)};
    sharedAttributes.set(desc.offset, new THREE.BufferAttribute(bufferView(whole), itemSize));
  }
  return sharedAttributes.get(desc.offset);
}

class Panel {
  constructor(desc, place) {
    this.desc = desc;
    this.place = place;
    const position = sharedAttribute(desc.positions, 3);
    const index = sharedAttribute(desc.index, 1);
    this.positions = position.array;
    this.index = index.array;
    this.indexCount = desc.face_count * 3;
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', position);
    geometry.setIndex(index);
    geometry.setDrawRange(0, this.indexCount);
    geometry.setAttribute('normal', new THREE.BufferAttribute(
        vertexNormals(this.positions, this.index, this.indexCount, position.count), 3));
    this.holeMaterials = [];
    desc.groups.forEach((group, g) => {
      geometry.addGroup(group.start * 3, group.count * 3, g);
      const colour = group.hole === -1 ? new THREE.Color(INPUT_COLOUR) : holeColour(group.hole);
      this.holeMaterials.push(this.surfaceMaterial({color: colour}));
    });
    this.curvatureMaterial = this.surfaceMaterial({color: 0xffffff, vertexColors: true});
    this.geometry = geometry;
    this.mesh = new THREE.Mesh(geometry, this.holeMaterials);
    this.mesh.frustumCulled = false;
    this.wire = new THREE.Mesh(geometry, new THREE.MeshBasicMaterial(
        {color: 0x222222, wireframe: true, transparent: true, opacity: 0.45}));
    this.wire.frustumCulled = false;
    this.wire.visible = false;
    this.scene = new THREE.Scene();
    this.scene.add(this.mesh, this.wire);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x777068, 1.6));
    this.light = new THREE.DirectionalLight(0xffffff, 1.6);
    this.scene.add(this.light, this.light.target);
    this.loops = this.makeLoops();
    if (this.loops) this.scene.add(this.loops);
    this.curvatureColours = {};
    this.box = this.bounds(false);
    this.newBox = this.bounds(true);
  }

  surfaceMaterial(options) {
    // Pushed back a little so that the loops and the wireframe draw on top.
    return new THREE.MeshPhongMaterial({
      side: THREE.DoubleSide, shininess: 12, specular: 0x181818, flatShading: settings.flat,
      polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1, ...options,
    });
  }

  makeLoops() {
    if (!this.desc.shows_loops || meta.loops.length === 0) return null;
    const loopVertices = bufferView(meta.loop_vertices);
    const segments = [];
    for (const loop of meta.loops) {
      for (let k = 0; k < loop.vertex_count; ++k) {
        segments.push(loopVertices[loop.offset + k],
                      loopVertices[loop.offset + (k + 1) % loop.vertex_count]);
      }
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', this.geometry.getAttribute('position'));
    geometry.setIndex(new THREE.BufferAttribute(new Uint32Array(segments), 1));
    const lines = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({color: 0x111111}));
    lines.frustumCulled = false;
    return lines;
  }

  // The box of the vertices of its faces, or of its new faces only (null
  // when it has none).
  bounds(newOnly) {
    const p = this.positions, index = this.index;
    const low = [Infinity, Infinity, Infinity], high = [-Infinity, -Infinity, -Infinity];
    for (const group of this.desc.groups) {
      if (newOnly && group.hole === -1) continue;
      for (let i = group.start * 3; i < (group.start + group.count) * 3; ++i) {
        const v = index[i] * 3;
        for (let c = 0; c < 3; ++c) {
          if (p[v + c] < low[c]) low[c] = p[v + c];
          if (p[v + c] > high[c]) high[c] = p[v + c];
        }
      }
    }
    if (!(low[0] <= high[0])) return null;
    return new THREE.Box3(new THREE.Vector3(...low), new THREE.Vector3(...high));
  }

  setColour(mode) {
    if (mode === 'holes') {
      this.mesh.material = this.holeMaterials;
      return;
    }
    if (!this.curvatureColours[mode]) {
      const values = bufferView(this.desc[mode]);
      const colours = new Uint8Array(this.positions.length);
      for (let v = 0; v < values.length; ++v) {
        colours[v * 3] = CURVATURE_LUT[values[v] * 3];
        colours[v * 3 + 1] = CURVATURE_LUT[values[v] * 3 + 1];
        colours[v * 3 + 2] = CURVATURE_LUT[values[v] * 3 + 2];
      }
      this.curvatureColours[mode] = new THREE.BufferAttribute(colours, 3, true);
    }
    this.geometry.setAttribute('color', this.curvatureColours[mode]);
    this.mesh.material = this.curvatureMaterial;
  }

  setFlat(flat) {
    for (const material of [...this.holeMaterials, this.curvatureMaterial]) {
      material.flatShading = flat;
      material.needsUpdate = true;
    }
  }
}

// ---- the page ----

const canvas = document.getElementById('canvas');
const stage = document.getElementById('stage');
const largest = Math.max(...meta.meshes.map((m) => m.face_count));
const renderer = new THREE.WebGLRenderer(
    {canvas, antialias: largest < 300000, preserveDrawingBuffer: true});
renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
renderer.setClearColor(BACKGROUND);
renderer.setScissorTest(true);

const panels = meta.meshes.map((desc, place) => new Panel(desc, place));
timings.panels = performance.now();
document.title = meta.title || document.title;
document.getElementById('title').textContent = meta.title;

// ---- camera: orbit about a target, y up, shared by every panel ----

const camera = new THREE.PerspectiveCamera(35, 1, 0.01, 100);
const view = {target: new THREE.Vector3(), distance: 1, azimuth: 0, elevation: 0};

function frameView() {
  const last = panels[panels.length - 1];
  const focus = last.newBox || panels.find((p) => p.newBox)?.newBox;
  const box = focus || last.box || new THREE.Box3(new THREE.Vector3(-1, -1, -1),
                                                  new THREE.Vector3(1, 1, 1));
  const sphere = box.getBoundingSphere(new THREE.Sphere());
  let radius = Math.max(sphere.radius, 1e-9);
  if (focus) {
    const whole = last.box.getBoundingSphere(new THREE.Sphere()).radius;
    radius = Math.min(radius * 2.5, whole);
  }
  view.target.copy(sphere.center);
  view.distance = radius / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2)) * 1.05;
  view.azimuth = THREE.MathUtils.degToRad(30);
  view.elevation = THREE.MathUtils.degToRad(35);
  requestRender();
}

function placeCamera() {
  const c = Math.cos(view.elevation);
  camera.position.set(
      view.target.x + view.distance * c * Math.sin(view.azimuth),
      view.target.y + view.distance * Math.sin(view.elevation),
      view.target.z + view.distance * c * Math.cos(view.azimuth));
  camera.up.set(0, 1, 0);
  camera.lookAt(view.target);
  const size = panels[panels.length - 1].box
      ? panels[panels.length - 1].box.getSize(new THREE.Vector3()).length() : 1;
  camera.near = Math.max(view.distance * 1e-3, (view.distance - size) * 0.5, 1e-9);
  camera.far = view.distance + size * 2;
}

let drag = null;
canvas.addEventListener('contextmenu', (e) => e.preventDefault());
canvas.addEventListener('pointerdown', (e) => {
  canvas.setPointerCapture(e.pointerId);
  drag = {x: e.clientX, y: e.clientY, pan: e.button !== 0 || e.shiftKey};
});
canvas.addEventListener('pointermove', (e) => {
  if (!drag) return;
  const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
  drag.x = e.clientX;
  drag.y = e.clientY;
  const height = canvas.clientHeight || 1;
  if (drag.pan) {
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
});
canvas.addEventListener('pointerup', () => { drag = null; });
canvas.addEventListener('wheel', (e) => {
  e.preventDefault();
  view.distance *= Math.exp(e.deltaY * 0.001);
  requestRender();
}, {passive: false});

// ---- controls ----

function visiblePanels() {
  return settings.layout === 'overlay' ? [panels[settings.overlaid]] : panels;
}

const overlayChoice = document.getElementById('overlay-choice');
const overlayButtons = panels.map((panel, place) => {
  const button = document.createElement('button');
  button.type = 'button';
  button.id = `show-${place}`;
  button.textContent = panel.desc.name;
  button.addEventListener('click', () => {
    settings.overlaid = place;
    update();
  });
  overlayChoice.appendChild(button);
  return button;
});

function bindRadio(name, key) {
  for (const input of document.querySelectorAll(`input[name=${name}]`)) {
    input.checked = input.value === settings[key];
    input.addEventListener('change', () => {
      if (input.checked) {
        settings[key] = input.value;
        update();
      }
    });
  }
}
function bindCheckbox(id, key) {
  const input = document.getElementById(id);
  input.checked = settings[key];
  input.addEventListener('change', () => {
    settings[key] = input.checked;
    update();
  });
}
bindRadio('layout', 'layout');
bindRadio('colour', 'colour');
bindCheckbox('wireframe', 'wireframe');
bindCheckbox('flat', 'flat');
bindCheckbox('loops', 'loops');
document.getElementById('reset').addEventListener('click', frameView);
window.addEventListener('keydown', (e) => {
  if (e.target instanceof HTMLInputElement && e.target.type === 'text') return;
  if (e.key === 't' || e.key === 'T') {
    settings.overlaid = (settings.overlaid + 1) % panels.length;
    update();
  } else if (e.key === 'r' || e.key === 'R') {
    frameView();
  }
});
if (panels.length < 2) document.getElementById('layout-box').hidden = true;

let appliedFlat = false;
function update() {
  for (const panel of panels) {
    panel.setColour(settings.colour);
    panel.wire.visible = settings.wireframe;
    if (panel.loops) panel.loops.visible = settings.loops;
    if (settings.flat !== appliedFlat) panel.setFlat(settings.flat);
  }
  appliedFlat = settings.flat;
  overlayButtons.forEach((button, place) => {
    button.hidden = settings.layout !== 'overlay';
    button.classList.toggle('on', place === settings.overlaid);
  });
  const curvature = settings.colour !== 'holes';
  const legend = document.getElementById('legend');
  legend.hidden = !curvature;
  if (curvature) {
    const range = meta.curvature[settings.colour].range;
    document.getElementById('legend-title').textContent = settings.colour === 'gaussian'
        ? 'Gaussian curvature (1/length²)' : 'mean curvature (1/length)';
    document.getElementById('legend-low').textContent = `≤ ${(-range).toPrecision(3)}`;
    document.getElementById('legend-high').textContent = `≥ ${range.toPrecision(3)}`;
  }
  document.getElementById('holes-key').hidden = curvature;
  requestRender();
}

// ---- labels, keys, report ----

// Where a loop's id goes: a hole's middle; on the loop itself for the
// others (an outer edge's middle is the middle of the cloth), at its vertex
// farthest from its centroid.
function loopAnchor(panel, loop) {
  const centroid = new THREE.Vector3(...loop.centroid);
  if (loop.kind === 'hole') return centroid;
  const loopVertices = bufferView(meta.loop_vertices);
  const p = panel.positions;
  let best = centroid, farthest = -1;
  for (let k = 0; k < loop.vertex_count; ++k) {
    const v = loopVertices[loop.offset + k] * 3;
    const point = new THREE.Vector3(p[v], p[v + 1], p[v + 2]);
    const distance = point.distanceToSquared(centroid);
    if (distance > farthest) {
      farthest = distance;
      best = point;
    }
  }
  return best;
}

const labelLayer = document.getElementById('labels');
const panelLabels = panels.map((panel) => {
  const name = document.createElement('div');
  name.className = 'panel-name';
  name.textContent = panel.desc.name;
  labelLayer.appendChild(name);
  const loops = !panel.loops ? [] : meta.loops.map((loop) => {
    const label = document.createElement('div');
    label.className = 'loop-label';
    label.textContent = loop.id;
    label.title = `loop ${loop.id}: ${loop.kind_text}, ${loop.vertex_count} vertices`;
    labelLayer.appendChild(label);
    return {label, anchor: loopAnchor(panel, loop)};
  });
  return {name, loops};
});

const key = document.getElementById('holes-key');
for (const hole of meta.holes) {
  const row = document.createElement('div');
  row.innerHTML = `<span class="swatch" style="background:${cssColour(hole)}"></span>`;
  row.append(hole === UNKNOWN_HOLE ? 'new faces' : `hole ${hole}`);
  key.appendChild(row);
}

if (meta.report.length > 0) {
  const section = document.getElementById('report');
  section.hidden = false;
  if (meta.report_source) {
    document.getElementById('report-source').textContent = `of ${meta.report_source}`;
  }
  const columns = [
    ['loop_id', 'loop'], ['filled', 'filled'], ['patch_vertex_count', 'vertices'],
    ['patch_face_count', 'faces'], ['iterations', 'iterations'], ['stop_reason', 'stop'],
    ['seconds', 'seconds'], ['energy', 'energy'], ['area_ratio_to_flat', 'area / flat'],
    ['edge_length_rms_rel', 'edge length rms'], ['gaussian_curvature', 'mean |K|'],
    ['min_angle_deg', 'min angle°'], ['min_distance', 'min distance'],
    ['self_intersections', 'crossings'], ['warning', 'warning'],
  ];
  const table = document.getElementById('report-table');
  const head = table.insertRow();
  for (const [, title] of columns) {
    const th = document.createElement('th');
    th.textContent = title;
    head.appendChild(th);
  }
  for (const row of meta.report) {
    const tr = table.insertRow();
    tr.dataset.loop = row.loop_id;
    for (const [field] of columns) {
      const td = tr.insertCell();
      const value = row[field];
      if (field === 'loop_id') {
        td.innerHTML = `<span class="swatch" style="background:${cssColour(value)}"></span>`;
      }
      td.append(value === null || value === undefined ? ''
                : typeof value === 'number' && !Number.isInteger(value) ? value.toPrecision(4)
                : String(value));
    }
  }
}

// ---- drawing ----

function viewports() {
  const width = stage.clientWidth, height = stage.clientHeight;
  const shown = visiblePanels();
  const each = Math.floor(width / shown.length);
  return shown.map((panel, k) => ({panel, x: k * each, y: 0, width: each, height}));
}

function placeLabels(ports) {
  for (const labels of panelLabels) {
    labels.name.hidden = true;
    for (const {label} of labels.loops) label.hidden = true;
  }
  const point = new THREE.Vector3();
  for (const port of ports) {
    const labels = panelLabels[port.panel.place];
    labels.name.hidden = false;
    labels.name.style.left = `${port.x + 6}px`;
    if (!settings.loops) continue;
    for (const {label, anchor} of labels.loops) {
      point.copy(anchor).project(camera);
      if (point.z > 1 || Math.abs(point.x) > 1 || Math.abs(point.y) > 1) continue;
      label.hidden = false;
      label.style.left = `${port.x + (point.x + 1) / 2 * port.width}px`;
      label.style.top = `${(1 - point.y) / 2 * port.height}px`;
    }
  }
}

let frames = 0;
function draw() {
  const width = stage.clientWidth, height = stage.clientHeight;
  const size = renderer.getSize(new THREE.Vector2());
  if (size.x !== width || size.y !== height) renderer.setSize(width, height, false);
  renderer.setScissor(0, 0, width, height);
  renderer.setViewport(0, 0, width, height);
  renderer.clear();
  placeCamera();
  const ports = viewports();
  for (const port of ports) {
    camera.aspect = port.width / Math.max(port.height, 1);
    camera.updateProjectionMatrix();
    camera.updateMatrixWorld();
    port.panel.light.position.copy(camera.position);
    port.panel.light.target.position.copy(view.target);
    renderer.setViewport(port.x, height - port.y - port.height, port.width, port.height);
    renderer.setScissor(port.x, height - port.y - port.height, port.width, port.height);
    renderer.render(port.panel.scene, camera);
  }
  placeLabels(ports);
  ++frames;
  if (frames === 1) {
    // Waits for the GPU, so that the time is that of a frame drawn.
    const gl = renderer.getContext();
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
    window.foldfillView.firstFrameMs = timings.firstFrame = performance.now();
    window.foldfillView.ready = true;
    document.body.dataset.ready = 'true';
  }
  window.foldfillView.frames = frames;
}

let pending = false;
function requestRender() {
  if (pending) return;
  pending = true;
  requestAnimationFrame(() => {
    pending = false;
    draw();
  });
}
new ResizeObserver(requestRender).observe(stage);

// For tests and benchmarks: the state, and where each panel's mesh is on the
// page (CSS pixels: its box projected, clipped to its panel).
window.foldfillView = {
  ready: false,
  frames: 0,
  timings,
  settings,
  screenBoxes() {
    const stageBox = stage.getBoundingClientRect();
    return viewports().map((port) => {
      camera.aspect = port.width / Math.max(port.height, 1);
      camera.updateProjectionMatrix();
      const box = port.panel.box;
      let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
      for (let corner = 0; corner < 8; ++corner) {
        const p = new THREE.Vector3(corner & 1 ? box.max.x : box.min.x,
                                    corner & 2 ? box.max.y : box.min.y,
                                    corner & 4 ? box.max.z : box.min.z).project(camera);
        const x = port.x + (p.x + 1) / 2 * port.width, y = (1 - p.y) / 2 * port.height;
        x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y);
      }
      const clip = (v, lo, hi) => Math.min(Math.max(v, lo), hi);
      return {
        name: port.panel.desc.name,
        x0: stageBox.left + clip(x0, port.x, port.x + port.width),
        x1: stageBox.left + clip(x1, port.x, port.x + port.width),
        y0: stageBox.top + clip(y0, 0, port.height),
        y1: stageBox.top + clip(y1, 0, port.height),
      };
    });
  },
};

try {
  frameView();
  update();
} catch (error) {
  showMessage(`This page could not show the meshes: ${error.message}`);
  throw error;
}
