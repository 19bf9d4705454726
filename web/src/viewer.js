// The 3D viewer of report.html: reads the grid-shell from the page's
// <script type="application/json" id="gridshell-data"> and draws it with three.js.
//
// Ids shown on hover/click are the ids of the output files: joint = mesh vertex index (joints.csv,
// nodes.csv), beam = topology edge index (beams.csv), panel = face index (panels.csv, cells.csv).
// Bundled with esbuild into one minified script that the executable inlines into the page, so
// the page needs no network and no server.

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import {
  buildGridObjects, cellsText, colourModes, createScene, displacementMagnitudes, escapeHtml, fmt,
  legendHtml, overlapsText,
} from './gridshell_scene.js';
import { steelPanel } from './steel_panel.js';

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

// Per-joint displacement magnitude, and the colour modes present in the data.
const dispMag = displacementMagnitudes(data);
const MODES = colourModes(data);

// ---------------------------------------------------------------------------------------------
// Scene

const view = document.getElementById('view');
const { renderer, scene } = createScene(view);

// Current joint positions (base + animated buckling mode).
const pos = new Float32Array(joints);

// The grid-shell's objects (beams, panels, joints, supports): gridshell_scene.js.
const grid = buildGridObjects(data, scene, pos);
const { beamLines, beamMaterial, panelMesh, jointPoints, triPanel, nCorners } = grid;
const { center, radius, span } = grid.bounds;
const updatePositions = grid.updatePositions;

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

// ---------------------------------------------------------------------------------------------
// Colouring

let mode = MODES[0];

function applyColors() {
  grid.applyColours(mode);
  drawLegend();
  requestRender();
}

function drawLegend() {
  document.getElementById('legend').innerHTML = legendHtml(mode);
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
  let s = '';
  if (mode.values && mode.on === kind && !mode.categorical) {
    s += `, ${mode.label} ${fmt(mode.values[id])} ${mode.unit}`;
  }
  if (kind === 'beam' && data.beam_sections && data.beam_sections.length === nBeams) {
    s += `, section ${data.beam_sections[id]}`;
  }
  return s;
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

// The FreeGrid benchmark's buildability figures (report.json `buildability`, docs/buildability.md).
function buildabilityFigures(b) {
  if (!b || typeof b !== 'object') return;
  const byValence = Object.entries(b.joint_clusters_by_valence || {})
    .map(([k, n]) => `${n} of valence ${escapeHtml(k)}`).join(', ');
  let html = '<table>';
  html += row('face planarity (1 = flat)', fmt(b.face_planarity));
  html += row('joints', b.joints);
  html += row('joint types (clusters)', `${b.joint_clusters}${byValence ? ` (${byValence})` : ''}, ` +
    `δ = ${fmt(b.joint_tolerance)}`);
  html += row('beam-length similarity (1 = equal)', fmt(b.beam_length_similarity));
  html += row('distinct sections', b.distinct_sections);
  html += '</table>';
  document.getElementById('buildability').innerHTML = html;
  document.getElementById('buildability-section').hidden = false;
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
  html += row('cells (panels)', cellsText(report, panels.length));
  html += row('beams', nBeams);
  html += row('joints', nJoints);
  html += row('supports', supports.length);
  const overlaps = overlapsText(mesh.overlaps);
  if (overlaps != null) html += row('overlaps', overlaps);
  html += row('total length', `${fmt(length)} m`);
  if (st.section && st.section.designation) {
    html += row('section', escapeHtml(st.section.designation) +
      (st.section.standard === false ? ' (not a catalogue size)' : ''));
  }
  if (mass != null) html += row('steel mass', `${fmt(mass)} kg`);
  // With several load combinations these rows are the primary one's (ULS, undrifted snow); the
  // governing rows below are over all of them.
  const several = st.combinations && Object.keys(st.combinations).length > 1;
  const of = several ? ', primary ULS' : '';
  if (st.delta_max_m != null) html += row(`δ (linear${of})`, `${fmt(st.delta_max_m * 1000)} mm`);
  if (st.lambda_linear_buckling != null) {
    html += row(`λ linear buckling${several ? ' (primary ULS)' : ''}`,
      fmt(st.lambda_linear_buckling));
  }
  if (st.lambda_nonlinear != null) {
    html += row(`λ non-linear${several ? ' (primary ULS)' : ''}`,
      `${fmt(st.lambda_nonlinear)} (${escapeHtml(st.limit_type || '')})`);
  }
  if (st.utilisation_max != null) {
    html += row(`utilisation max${several ? ' (primary ULS)' : ''}`, fmt(st.utilisation_max) +
      (st.utilisation_check ? ` (${escapeHtml(st.utilisation_check)})` : ''));
  }
  if (st.buckling_utilisation_max != null) {
    html += row(`member buckling max${several ? ' (primary ULS)' : ''}`, fmt(st.buckling_utilisation_max) +
      (st.buckling_check ? ` (${escapeHtml(st.buckling_check)})` : ''));
  }
  const gov = st.governing || {};
  if (gov.lambda != null && several) {
    // Each governing figure with its combination and its verdict (fails: red).
    const verdict = (ok) => (ok == null ? '' : ok ? ' — passes' : ' — <b style="color:#b00">fails</b>');
    const g = (name, value, unit, ok) => `${escapeHtml(name)} (${value})${unit}${verdict(ok)}`;
    html += row('governing λ', g(gov.lambda, fmt(gov.lambda_value), '', gov.lambda_pass));
    if (gov.utilisation != null) {
      html += row('governing utilisation',
        g(gov.utilisation, fmt(gov.utilisation_value), '', gov.utilisation_pass));
    }
    if (gov.delta != null) {
      html += row('governing δ', g(gov.delta, fmt(gov.delta_m * 1000), ' mm', gov.delta_pass));
    }
  }
  if (st.imperfection && st.imperfection.note) {
    html += row('λ imperfect > λ perfect', escapeHtml(st.imperfection.note));
  }
  if (mesh.planarity_mean != null) html += row('planarity mean', fmt(mesh.planarity_mean));
  if (mesh.out_of_plane_max_m != null) {
    html += row(`panels (${escapeHtml(mesh.panels || '')}) out of plane`,
      `${fmt(mesh.out_of_plane_max_m * 1000)} mm max, ${fmt(mesh.out_of_plane_median_m * 1000)} mm median`);
  }
  html += '</table>';
  document.getElementById('figures-table').innerHTML = html;
  buildabilityFigures(report.buildability);
  steelPanel(data);

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
