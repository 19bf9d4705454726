// The 3D viewer of report.html: reads the grid-shell from the page's
// <script type="application/json" id="gridshell-data"> and draws it with three.js.
//
// Ids shown on hover/click are the ids of the output files: joint = mesh vertex index (joints.csv,
// nodes.csv), beam = topology edge index (beams.csv), panel = face index (panels.csv, cells.csv).
// Bundled with esbuild into one minified script that the executable inlines into the page, so
// the page needs no network and no server.

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { LineSegments2 } from 'three/addons/lines/LineSegments2.js';
import { LineSegmentsGeometry } from 'three/addons/lines/LineSegmentsGeometry.js';
import { LineMaterial } from 'three/addons/lines/LineMaterial.js';

// ---------------------------------------------------------------------------------------------
// Colour maps: a sequential one (dark blue → green → yellow) and a diverging one for axial
// forces (compression red, 0 light grey, tension blue).

const SEQUENTIAL = [
  [0.267, 0.005, 0.329], [0.229, 0.322, 0.546], [0.128, 0.567, 0.551],
  [0.369, 0.789, 0.383], [0.993, 0.906, 0.144],
];
const DIVERGING = [[0.70, 0.05, 0.12], [0.88, 0.38, 0.30], [0.58, 0.58, 0.58],
  [0.33, 0.53, 0.86], [0.08, 0.22, 0.62]];

function sample(stops, t) {
  const x = Math.min(1, Math.max(0, Number.isFinite(t) ? t : 0)) * (stops.length - 1);
  const i = Math.min(stops.length - 2, Math.floor(x));
  const f = x - i;
  const a = stops[i], b = stops[i + 1];
  return [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])];
}

function cssGradient(stops) {
  const parts = stops.map((c, i) => {
    const rgb = c.map((v) => Math.round(v * 255)).join(',');
    return `rgb(${rgb}) ${(100 * i / (stops.length - 1)).toFixed(0)}%`;
  });
  return `linear-gradient(to right, ${parts.join(', ')})`;
}

// ---------------------------------------------------------------------------------------------
// Data

const data = JSON.parse(document.getElementById('gridshell-data').textContent);
const joints = new Float32Array(data.joints || []);
const nJoints = joints.length / 3;
const beams = data.beams || [];
const nBeams = beams.length / 2;
const panels = data.panels || [];
const supports = data.supports || [];
const report = data.report || {};
const config = data.config || {};

function fmt(x, digits = 4) {
  if (x == null) return '–';
  if (typeof x !== 'number') return String(x);
  if (x === 0) return '0';
  const a = Math.abs(x);
  if (a >= 1e5 || a < 1e-3) return x.toExponential(digits - 1);
  return Number(x.toPrecision(digits)).toString();
}

// Per-joint displacement magnitude.
let dispMag = null;
if (nJoints && data.displacement && data.displacement.length === 3 * nJoints) {
  dispMag = new Float64Array(nJoints);
  for (let v = 0; v < nJoints; ++v) {
    const d = data.displacement;
    dispMag[v] = Math.hypot(d[3 * v], d[3 * v + 1], d[3 * v + 2]);
  }
}

// The colour modes present in the data. `on`: what carries the value (beam, joint or panel).
const MODES = [{ key: 'plain', label: 'plain', on: 'none' }];
if (nBeams && data.axial_force && data.axial_force.length === nBeams) {
  MODES.push({ key: 'axial', label: 'axial force', unit: 'kN', on: 'beam', diverging: true,
    values: data.axial_force.map((n) => n / 1000),
    note: 'compression < 0 (red), tension > 0 (blue)' });
}
if (dispMag) {
  MODES.push({ key: 'displacement', label: 'displacement', unit: 'mm', on: 'joint',
    values: Array.from(dispMag, (d) => d * 1000), note: 'linear, under the reference load' });
}
if (data.density && data.density.length === panels.length && panels.length) {
  MODES.push({ key: 'density', label: 'cell density d_target', unit: '–', on: 'panel',
    values: data.density, note: '1 = the sparsest cells the field asks for' });
}
if (data.planarity && data.planarity.length === panels.length && panels.length) {
  MODES.push({ key: 'planarity', label: 'panel planarity', unit: '–', on: 'panel',
    values: data.planarity, note: 'mean distance to the plane / half perimeter; 0 = flat' });
}
if (nBeams && data.utilisation && data.utilisation.length === nBeams) {
  MODES.push({ key: 'utilisation', label: 'utilisation', unit: '–', on: 'beam',
    values: data.utilisation, note: '1 = the member check is just met' });
}
for (const m of MODES) {
  if (!m.values) continue;
  let lo = Infinity, hi = -Infinity;
  for (const x of m.values) { if (x < lo) lo = x; if (x > hi) hi = x; }
  m.min = lo; m.max = hi;
  if (m.diverging) {
    // Symmetric about 0; the few largest forces (at supports, typically) saturate, so that the
    // rest of the structure is not all one grey.
    const mags = m.values.map(Math.abs).sort((x, y) => x - y);
    const a = mags[Math.min(mags.length - 1, Math.floor(0.98 * mags.length))] || mags[mags.length - 1] || 1;
    lo = -a; hi = a;
  }
  if (m.key === 'utilisation') { lo = 0; hi = Math.max(1, hi); }
  if (m.key === 'planarity') lo = 0;
  if (!(hi > lo)) hi = lo + 1;
  m.lo = lo; m.hi = hi;
  m.stops = m.diverging ? DIVERGING : SEQUENTIAL;
}

// ---------------------------------------------------------------------------------------------
// Scene

const view = document.getElementById('view');
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio || 1);
renderer.setClearColor(0xf6f6f3, 1);
view.appendChild(renderer.domElement);

const scene = new THREE.Scene();
scene.add(new THREE.HemisphereLight(0xffffff, 0x888880, 2.2));
const sun = new THREE.DirectionalLight(0xffffff, 1.2);
sun.position.set(1, -1, 2);
scene.add(sun);

const box = new THREE.Box3();
for (let v = 0; v < nJoints; ++v) {
  box.expandByPoint(new THREE.Vector3(joints[3 * v], joints[3 * v + 1], joints[3 * v + 2]));
}
if (box.isEmpty()) box.set(new THREE.Vector3(-1, -1, -1), new THREE.Vector3(1, 1, 1));
const center = box.getCenter(new THREE.Vector3());
const size = box.getSize(new THREE.Vector3());
const radius = Math.max(1e-6, 0.5 * size.length());
const span = Math.max(size.x, size.y, size.z, 1e-6);

const camera = new THREE.PerspectiveCamera(35, 1, radius / 100, radius * 100);
camera.up.set(0, 0, 1);
const controls = new OrbitControls(camera, renderer.domElement);
function resetView() {
  const dist = radius / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2)) * 0.95;
  const dir = new THREE.Vector3(0.9, -1.4, 0.85).normalize();
  camera.position.copy(center).addScaledVector(dir, dist);
  controls.target.copy(center);
  controls.update();
}

// Current joint positions (base + animated buckling mode).
const pos = new Float32Array(joints);

// Beams: fat line segments, two colours per beam (its ends).
const beamPositions = new Float32Array(6 * nBeams);
const beamColors = new Float32Array(6 * nBeams);
const beamGeometry = new LineSegmentsGeometry();
const beamMaterial = new LineMaterial({ vertexColors: true, linewidth: 2.2, worldUnits: false });
let beamLines = null;
if (nBeams > 0) {
  beamGeometry.setPositions(beamPositions);
  beamGeometry.setColors(beamColors);
  beamLines = new LineSegments2(beamGeometry, beamMaterial);
  scene.add(beamLines);
}

// Panels: fan triangles, not indexed, so that a panel can carry its own colour.
let nCorners = 0;
for (const f of panels) nCorners += 3 * Math.max(0, f.length - 2);
const cornerJoint = new Int32Array(nCorners);
const triPanel = new Int32Array(nCorners / 3);
{
  let c = 0;
  panels.forEach((f, p) => {
    for (let k = 1; k + 1 < f.length; ++k) {
      triPanel[c / 3] = p;
      cornerJoint[c++] = f[0]; cornerJoint[c++] = f[k]; cornerJoint[c++] = f[k + 1];
    }
  });
}
const panelGeometry = new THREE.BufferGeometry();
panelGeometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * nCorners), 3));
panelGeometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(3 * nCorners), 3));
const panelMaterial = new THREE.MeshLambertMaterial({
  vertexColors: true, transparent: true, opacity: 0.55, side: THREE.DoubleSide,
  depthWrite: false, polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
});
const panelMesh = new THREE.Mesh(panelGeometry, panelMaterial);
if (nCorners > 0) scene.add(panelMesh);

// Joints (for picking, drawn small) and supports (dark cubes).
const jointGeometry = new THREE.BufferGeometry();
jointGeometry.setAttribute('position', new THREE.BufferAttribute(pos, 3));
const jointPoints = new THREE.Points(jointGeometry,
  new THREE.PointsMaterial({ color: 0x444444, size: 2, sizeAttenuation: false }));
scene.add(jointPoints);

const supportSize = Math.max(span / 120, 1e-6);
const supportMesh = new THREE.InstancedMesh(
  new THREE.BoxGeometry(supportSize, supportSize, supportSize),
  new THREE.MeshLambertMaterial({ color: 0x202020 }), Math.max(1, supports.length));
supportMesh.count = supports.length;
{
  const m = new THREE.Matrix4();
  supports.forEach((v, i) => {
    m.makeTranslation(joints[3 * v], joints[3 * v + 1], joints[3 * v + 2]);
    supportMesh.setMatrixAt(i, m);
  });
}
if (supports.length) scene.add(supportMesh);

function updatePositions() {
  for (let b = 0; b < nBeams; ++b) {
    const i = beams[2 * b], j = beams[2 * b + 1];
    beamPositions[6 * b] = pos[3 * i]; beamPositions[6 * b + 1] = pos[3 * i + 1];
    beamPositions[6 * b + 2] = pos[3 * i + 2];
    beamPositions[6 * b + 3] = pos[3 * j]; beamPositions[6 * b + 4] = pos[3 * j + 1];
    beamPositions[6 * b + 5] = pos[3 * j + 2];
  }
  if (nBeams > 0) {
    const start = beamGeometry.attributes.instanceStart;
    start.data.array.set(beamPositions);
    start.data.needsUpdate = true;
    beamGeometry.computeBoundingSphere();
    beamGeometry.computeBoundingBox();
  }
  const p = panelGeometry.attributes.position.array;
  for (let c = 0; c < nCorners; ++c) {
    const v = cornerJoint[c];
    p[3 * c] = pos[3 * v]; p[3 * c + 1] = pos[3 * v + 1]; p[3 * c + 2] = pos[3 * v + 2];
  }
  panelGeometry.attributes.position.needsUpdate = true;
  panelGeometry.computeVertexNormals();
  panelGeometry.computeBoundingSphere();
  jointGeometry.attributes.position.needsUpdate = true;
  jointGeometry.computeBoundingSphere();
}

// ---------------------------------------------------------------------------------------------
// Colouring

const BEAM_PLAIN = [0.22, 0.24, 0.27];
const PANEL_PLAIN = [0.70, 0.80, 0.90];
let mode = MODES[0];

function applyColors() {
  const bc = beamColors, pc = panelGeometry.attributes.color.array;
  const t = (x) => (x - mode.lo) / (mode.hi - mode.lo);
  for (let b = 0; b < nBeams; ++b) {
    let ci = BEAM_PLAIN, cj = BEAM_PLAIN;
    if (mode.on === 'beam') ci = cj = sample(mode.stops, t(mode.values[b]));
    // Per-joint values colour the panels; the beams only when no panel is shown.
    if (mode.on === 'joint' && !(nCorners > 0 && panelMesh.visible)) {
      ci = sample(mode.stops, t(mode.values[beams[2 * b]]));
      cj = sample(mode.stops, t(mode.values[beams[2 * b + 1]]));
    }
    bc.set(ci, 6 * b); bc.set(cj, 6 * b + 3);
  }
  if (nBeams > 0) {
    const col = beamGeometry.attributes.instanceColorStart;
    col.data.array.set(bc);
    col.data.needsUpdate = true;
  }
  for (let c = 0; c < nCorners; ++c) {
    let rgb = PANEL_PLAIN;
    if (mode.on === 'panel') rgb = sample(mode.stops, t(mode.values[triPanel[Math.floor(c / 3)]]));
    if (mode.on === 'joint') rgb = sample(mode.stops, t(mode.values[cornerJoint[c]]));
    pc.set(rgb, 3 * c);
  }
  panelGeometry.attributes.color.needsUpdate = true;
  panelMaterial.opacity = mode.on === 'panel' || mode.on === 'joint' ? 0.85 : 0.3;
  drawLegend();
  requestRender();
}

function drawLegend() {
  const legend = document.getElementById('legend');
  if (!mode.values) {
    legend.innerHTML = '<div class="legend-title">beams dark, panels light blue, ' +
      'supports as black cubes</div>';
    return;
  }
  const mid = mode.diverging ? 0 : 0.5 * (mode.lo + mode.hi);
  legend.innerHTML =
    `<div class="legend-title">${mode.label} [${mode.unit}] — on the ${mode.on}s</div>` +
    `<div class="legend-bar" style="background:${cssGradient(mode.stops)}"></div>` +
    `<div class="legend-ticks"><span>${fmt(mode.lo, 3)}</span><span>${fmt(mid, 3)}</span>` +
    `<span>${fmt(mode.hi, 3)}</span></div>` +
    `<div class="legend-note">${mode.note}; range ${fmt(mode.min, 3)} … ${fmt(mode.max, 3)}` +
    `${mode.min < mode.lo || mode.max > mode.hi ? ' (colours saturate at the ends)' : ''}</div>`;
}

// ---------------------------------------------------------------------------------------------
// Buckling modes: pos = joints + s · amplitude · span · mode, s = sin(ωt) while playing.

const modes = (data.buckling && data.buckling.modes) || [];
const lambdas = (data.buckling && data.buckling.lambdas) || [];
let modeIndex = -1;
let playing = false;
let phase = 0;
let amplitude = 0.05;

function setDeformed(s) {
  pos.set(joints);
  if (modeIndex >= 0) {
    const m = modes[modeIndex];
    const k = s * amplitude * span;
    const n = Math.min(pos.length, m.length);
    for (let i = 0; i < n; ++i) pos[i] += k * m[i];
  }
  updatePositions();
  requestRender();
}

// ---------------------------------------------------------------------------------------------
// Picking: the joint, beam or panel under the pointer, with its id as in the CSV files.

const raycaster = new THREE.Raycaster();
raycaster.params.Points.threshold = span / 150;
raycaster.params.Line2 = { threshold: 6 };
const pointer = new THREE.Vector2();

function valueText(kind, id) {
  if (!mode.values || mode.on !== kind) return '';
  return `, ${mode.label} ${fmt(mode.values[id])} ${mode.unit}`;
}

function pick(ev) {
  const rect = renderer.domElement.getBoundingClientRect();
  pointer.set(((ev.clientX - rect.left) / rect.width) * 2 - 1,
    -((ev.clientY - rect.top) / rect.height) * 2 + 1);
  raycaster.setFromCamera(pointer, camera);
  const hitJoint = raycaster.intersectObject(jointPoints)[0];
  if (hitJoint) {
    const v = hitJoint.index;
    const sup = supports.includes(v) ? ' (support)' : '';
    let extra = valueText('joint', v);
    if (dispMag && mode.on !== 'joint') extra += `, displacement ${fmt(dispMag[v] * 1000)} mm`;
    return `joint ${v}${sup}: (${fmt(joints[3 * v])}, ${fmt(joints[3 * v + 1])}, ` +
      `${fmt(joints[3 * v + 2])}) m${extra}`;
  }
  if (beamLines) {
    const hitBeam = raycaster.intersectObject(beamLines)[0];
    if (hitBeam) {
      const b = hitBeam.faceIndex;
      const i = beams[2 * b], j = beams[2 * b + 1];
      const len = Math.hypot(joints[3 * i] - joints[3 * j], joints[3 * i + 1] - joints[3 * j + 1],
        joints[3 * i + 2] - joints[3 * j + 2]);
      let extra = valueText('beam', b);
      if (data.axial_force && data.axial_force.length === nBeams && mode.key !== 'axial') {
        extra += `, axial force ${fmt(data.axial_force[b] / 1000)} kN`;
      }
      return `beam ${b}: joints ${i}–${j}, length ${fmt(len)} m${extra}`;
    }
  }
  if (nCorners > 0) {
    const hitPanel = raycaster.intersectObject(panelMesh)[0];
    if (hitPanel) {
      const p = triPanel[hitPanel.faceIndex];
      return `panel ${p}: ${panels[p].length} sides, joints ${panels[p].join(' ')}` +
        valueText('panel', p);
    }
  }
  return '';
}

// ---------------------------------------------------------------------------------------------
// Side panel: key figures, options, timings, figures.

function row(name, value) {
  return `<tr><th>${name}</th><td>${value}</td></tr>`;
}

function escapeHtml(s) {
  return String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' })[c]);
}

function keyFigures() {
  const mesh = report.mesh || {};
  const st = report.structure || {};
  const fab = report.fabrication || {};
  let length = mesh.total_length_m ?? st.total_length_m ?? fab.total_length_m;
  if (length == null) {
    length = 0;
    for (let b = 0; b < nBeams; ++b) {
      const i = beams[2 * b], j = beams[2 * b + 1];
      length += Math.hypot(joints[3 * i] - joints[3 * j], joints[3 * i + 1] - joints[3 * j + 1],
        joints[3 * i + 2] - joints[3 * j + 2]);
    }
  }
  const mass = st.mass_kg ?? fab.mass_kg;
  let html = '<table>';
  html += row('cells (panels)', panels.length);
  html += row('beams', nBeams);
  html += row('joints', nJoints);
  html += row('supports', supports.length);
  html += row('total length', `${fmt(length)} m`);
  if (mass != null) html += row('steel mass', `${fmt(mass)} kg`);
  if (st.delta_max_m != null) html += row('δ (linear)', `${fmt(st.delta_max_m * 1000)} mm`);
  if (st.lambda_linear_buckling != null) {
    html += row('λ linear buckling', fmt(st.lambda_linear_buckling));
  }
  if (st.lambda_nonlinear != null) {
    html += row('λ non-linear', `${fmt(st.lambda_nonlinear)} (${escapeHtml(st.limit_type || '')})`);
  }
  if (st.utilisation_max != null) html += row('utilisation max', fmt(st.utilisation_max));
  if (mesh.planarity_mean != null) html += row('planarity mean', fmt(mesh.planarity_mean));
  html += '</table>';
  document.getElementById('figures-table').innerHTML = html;

  const timings = report.timings_s || {};
  let t = '<table>';
  for (const [k, v] of Object.entries(timings)) {
    if (typeof v === 'number') t += row(escapeHtml(k), `${fmt(v, 3)} s`);
  }
  document.getElementById('timings').innerHTML = t + '</table>';

  let o = '<table>';
  if (config.command) o += row('command', escapeHtml(config.command));
  for (const p of config.positional || []) o += row('input', escapeHtml(p));
  for (const [k, v] of Object.entries(config.options || {})) {
    o += row(escapeHtml(k), escapeHtml(typeof v === 'string' ? v : JSON.stringify(v)));
  }
  document.getElementById('options').innerHTML = o + '</table>';
  document.getElementById('report-json').textContent = JSON.stringify(report, null, 1);

  const figs = document.getElementById('figures');
  for (const f of data.figures || []) {
    const fig = document.createElement('figure');
    const img = document.createElement('img');
    img.src = f.src;
    img.alt = f.name;
    img.addEventListener('click', () => {
      const big = document.getElementById('big');
      big.querySelector('img').src = f.src;
      big.hidden = false;
    });
    const cap = document.createElement('figcaption');
    cap.textContent = f.name;
    fig.append(img, cap);
    figs.appendChild(fig);
  }
  if (!(data.figures || []).length) figs.textContent = 'no figures in this folder';
}

// ---------------------------------------------------------------------------------------------
// Controls and the render loop

let needsRender = true;
function requestRender() { needsRender = true; }

function resize() {
  const w = view.clientWidth, h = view.clientHeight;
  renderer.setSize(w, h, false);
  renderer.domElement.style.width = `${w}px`;
  renderer.domElement.style.height = `${h}px`;
  camera.aspect = w / Math.max(1, h);
  camera.updateProjectionMatrix();
  beamMaterial.resolution.set(w, h);
  requestRender();
}

function setupControls() {
  const select = document.getElementById('colour');
  for (const m of MODES) {
    const o = document.createElement('option');
    o.value = m.key;
    o.textContent = m.unit ? `${m.label} [${m.unit}]` : m.label;
    select.appendChild(o);
  }
  // Open on the most telling quantity present.
  const first = MODES.find((m) => m.key === 'axial') || MODES.find((m) => m.on !== 'none') ||
    MODES[0];
  select.value = first.key;
  mode = first;
  select.addEventListener('change', () => {
    mode = MODES.find((m) => m.key === select.value);
    applyColors();
  });

  const modeSelect = document.getElementById('mode');
  const play = document.getElementById('play');
  const amp = document.getElementById('amplitude');
  const ampLabel = document.getElementById('amplitude-label');
  if (!modes.length) {
    document.getElementById('buckling').innerHTML =
      '<p class="muted">no buckling modes (no linearised buckling analysis in this run)</p>';
  } else {
    modes.forEach((_, k) => {
      const o = document.createElement('option');
      o.value = String(k);
      o.textContent = `mode ${k + 1}: λ = ${fmt(lambdas[k])}`;
      modeSelect.appendChild(o);
    });
    modeSelect.addEventListener('change', () => {
      modeIndex = Number(modeSelect.value);
      if (modeIndex < 0) { playing = false; play.textContent = 'play'; }
      setDeformed(Math.sin(phase));
    });
    play.addEventListener('click', () => {
      if (modeIndex < 0) { modeIndex = 0; modeSelect.value = '0'; }
      playing = !playing;
      play.textContent = playing ? 'pause' : 'play';
    });
    amp.addEventListener('input', () => {
      amplitude = Number(amp.value) / 100;
      ampLabel.textContent = `${amp.value} % of the span`;
      setDeformed(Math.sin(phase));
    });
  }

  document.getElementById('reset').addEventListener('click', resetView);
  document.getElementById('show-panels').addEventListener('change', (e) => {
    panelMesh.visible = e.target.checked;
    applyColors();
  });
  document.getElementById('big').addEventListener('click', (e) => { e.currentTarget.hidden = true; });

  const info = document.getElementById('info');
  let pinned = '';
  renderer.domElement.addEventListener('pointermove', (ev) => {
    const s = pick(ev);
    info.textContent = s || pinned || 'hover a joint, beam or panel; click to keep it';
  });
  renderer.domElement.addEventListener('click', (ev) => {
    pinned = pick(ev);
    info.textContent = pinned || 'hover a joint, beam or panel; click to keep it';
  });
  controls.addEventListener('change', requestRender);
  window.addEventListener('resize', resize);
}

// A link can open a given view: report.html#colour=displacement&mode=2&amplitude=10&click=400,300
// (colour mode key, buckling mode 1.., amplitude in % of the span shown at its largest, and a
// click at that page position, whose id the info line then shows).
function applyLink() {
  const h = new URLSearchParams(window.location.hash.slice(1));
  const colour = MODES.find((m) => m.key === h.get('colour'));
  if (colour) {
    mode = colour;
    document.getElementById('colour').value = colour.key;
  }
  if (h.has('amplitude') && Number.isFinite(Number(h.get('amplitude')))) {
    const amp = document.getElementById('amplitude');
    amp.value = h.get('amplitude');
    amplitude = Number(amp.value) / 100;
    document.getElementById('amplitude-label').textContent = `${amp.value} % of the span`;
  }
  const k = Number(h.get('mode')) - 1;
  if (modes.length && Number.isInteger(k) && k >= 0 && k < modes.length) {
    modeIndex = k;
    phase = Math.PI / 2;
    document.getElementById('mode').value = String(k);
  }
  return h.get('click');
}

function clickAt(where) {
  const [x, y] = where.split(',').map(Number);
  if (!Number.isFinite(x) || !Number.isFinite(y)) return;
  controls.update();
  camera.updateMatrixWorld();
  document.getElementById('info').textContent = pick({ clientX: x, clientY: y }) || 'nothing there';
}

let last = performance.now();
let frames = 0;
function loop(now) {
  const dt = Math.min(0.1, (now - last) / 1000);
  last = now;
  if (playing) {
    phase += dt * Math.PI;  // one cycle in two seconds
    setDeformed(Math.sin(phase));
  }
  if (needsRender) {
    renderer.render(scene, camera);
    needsRender = false;
    frames += 1;
    document.documentElement.setAttribute('data-frames', String(frames));
  }
  requestAnimationFrame(loop);
}

document.getElementById('title').textContent = data.title || 'gridshell report';
keyFigures();
setupControls();
const click = applyLink();
setDeformed(Math.sin(phase));
applyColors();
resize();
resetView();
renderer.render(scene, camera);
if (click) clickAt(click);
document.documentElement.setAttribute('data-ready', '1');
requestAnimationFrame(loop);
