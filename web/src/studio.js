// The studio page (`gridshell studio`, docs/studio.md): controls → GET /api/design → the
// grid-shell redrawn with the scene code it shares with report.html (gridshell_scene.js).
//
// Only the answer of the newest request is drawn: each request carries a number, an older
// fetch is aborted when a newer one starts, and an answer whose number is not the newest is
// dropped (the server answers 409 to requests superseded while they waited).
//
// State for tests, on <html>: data-ready (first design drawn), data-draws (designs drawn),
// data-request (query of the drawn design), data-status (busy | ready | error), data-frames.
// A link can set the controls and script changes after the first drawing:
//   /#surface=builtin:funicular&D=2&A=1&cells=200&colour=density&then=cells:400&burst=20
// (then=ID:VALUE sets a control as a user would, with an input event; burst=N moves the cells
// slider N times in quick succession before that).

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import {
  buildGridObjects, cellsText, colourModes, createScene, escapeHtml, fmt, legendHtml, overlapsText,
} from './gridshell_scene.js';

const root = document.documentElement;
const $ = (id) => document.getElementById(id);

// The server's per-run token, written into the page it served (docs/studio.md, "What the
// studio protects"): every /api request carries it in a header, which a page of another origin
// cannot send to the studio without the browser asking the studio first (it does not agree).
const token = document.querySelector('meta[name="gridshell-token"]')?.content || '';
const api = (path, init = {}) =>
  fetch(path, { ...init, headers: { ...(init.headers || {}), 'X-Gridshell-Token': token } });

// A file answer of the API saved through a link (a plain link cannot carry the token).
async function download(path, name) {
  const response = await api(path);
  const body = await response.blob();
  if (!response.ok) { showError((await body.text()).trim()); return; }
  const a = document.createElement('a');
  a.href = URL.createObjectURL(body);
  a.download = name;
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 60000);
}

// ---------------------------------------------------------------------------------------------
// Scene

const view = $('view');
const { renderer, scene } = createScene(view);
const camera = new THREE.PerspectiveCamera(35, 1, 0.01, 1000);
camera.up.set(0, 0, 1);
const controls = new OrbitControls(camera, renderer.domElement);

let grid = null;        // buildGridObjects of the drawn design
let modes = [];
let mode = null;
let drawnSurface = '';  // the camera is reset when the surface changes
let needsRender = true;
const requestRender = () => { needsRender = true; };

function resetView() {
  if (!grid) return;
  const { center, radius } = grid.bounds;
  camera.near = radius / 100;
  camera.far = radius * 100;
  camera.updateProjectionMatrix();
  const dist = radius / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2)) * 0.95;
  const dir = new THREE.Vector3(0.9, -1.4, 0.85).normalize();
  camera.position.copy(center).addScaledVector(dir, dist);
  controls.target.copy(center);
  controls.update();
  requestRender();
}

function resize() {
  const w = view.clientWidth, h = view.clientHeight;
  renderer.setSize(w, h, false);
  renderer.domElement.style.width = `${w}px`;
  renderer.domElement.style.height = `${h}px`;
  camera.aspect = w / Math.max(1, h);
  camera.updateProjectionMatrix();
  if (grid) grid.beamMaterial.resolution.set(w, h);
  requestRender();
}

function applyColours() {
  if (!grid || !mode) return;
  grid.panelMesh.visible = $('show-panels').checked;
  grid.applyColours(mode);
  $('legend').innerHTML = legendHtml(mode);
  requestRender();
}

function row(name, value) { return `<tr><th>${name}</th><td>${value}</td></tr>`; }

function showFigures(answer, data) {
  const report = answer.report || {};
  const mesh = report.mesh || {};
  const st = report.structure || {};
  let html = '<table>';
  html += row('cells (panels)', cellsText(report, (data.panels || []).length));
  html += row('beams', (data.beams || []).length / 2);
  html += row('joints', (data.joints || []).length / 3);
  html += row('supports', (data.supports || []).length);
  const overlaps = overlapsText(mesh.overlaps);
  if (overlaps != null) html += row('overlaps', overlaps);
  if (mesh.total_length_m != null) html += row('total length', `${fmt(mesh.total_length_m)} m`);
  if (st.mass_kg != null) html += row('steel mass', `${fmt(st.mass_kg)} kg`);
  if (st.lambda_linear_buckling != null) html += row('λ linear buckling', fmt(st.lambda_linear_buckling));
  if (st.lambda_nonlinear != null) {
    html += row('λ non-linear', `${fmt(st.lambda_nonlinear)} (${escapeHtml(st.limit_type || '')})`);
  }
  if (st.delta_max_m != null) html += row('δ (linear)', `${fmt(st.delta_max_m * 1000)} mm`);
  if (report.objective && report.objective.chosen_label) {
    html += row('chosen field', escapeHtml(report.objective.chosen_label));
  }
  html += row('design time', `${fmt(answer.seconds, 3)} s`);
  $('figures-table').innerHTML = html + '</table>';
}

function draw(answer) {
  const data = answer.view;
  if (grid) grid.dispose();
  const pos = new Float32Array(data.joints || []);
  grid = buildGridObjects(data, scene, pos);
  grid.updatePositions();
  const keep = mode ? mode.key : ($('colour').value || 'axial');
  modes = colourModes(data);
  const select = $('colour');
  select.innerHTML = '';
  for (const m of modes) {
    const o = document.createElement('option');
    o.value = m.key;
    o.textContent = m.unit ? `${m.label} [${m.unit}]` : m.label;
    select.appendChild(o);
  }
  mode = modes.find((m) => m.key === keep) || modes.find((m) => m.key === 'axial') || modes[0];
  select.value = mode.key;
  resize();
  const surface = new URLSearchParams(answer.request).get('surface');
  if (surface !== drawnSurface) { drawnSurface = surface; resetView(); }
  applyColours();
  showFigures(answer, data);
  renderer.render(scene, camera);
  root.setAttribute('data-request', answer.request);
  root.setAttribute('data-draws', String(Number(root.getAttribute('data-draws') || 0) + 1));
}

// ---------------------------------------------------------------------------------------------
// Requests: only the newest is drawn.

let sequence = 0;
let inflight = null;

// Values a link asked for that a control cannot show (a slider clamps D=0 to 1): sent as they
// are, so that the server judges them, until the user moves that control.
const linkValues = {};

function value(id) { return id in linkValues ? linkValues[id] : $(id).value; }

function query() {
  const q = new URLSearchParams();
  q.set('surface', value('surface'));
  const objective = value('objective');
  if (objective !== 'none') {
    q.set('objective', objective);
  } else {
    q.set('D', value('D'));
    q.set('A', value('A'));
  }
  q.set('cells', value('cells'));
  q.set('symmetry', value('symmetry'));
  q.set('analyze', value('analyze'));
  q.set('seed', value('seed'));
  return q.toString();
}

function setStatus(status, text) {
  root.setAttribute('data-status', status);
  $('status').textContent = text;
}

function showError(message) {
  $('error').textContent = message;
  setStatus('error', 'error');
}

async function redesign() {
  const q = query();
  for (const k of ['D', 'A', 'cells']) $(`${k}-value`).textContent = value(k);
  const objective = $('objective').value !== 'none';
  $('D').disabled = objective;
  $('A').disabled = objective;
  $('export-zip').dataset.path = `/api/export.zip?${q}`;
  $('export-config').dataset.path = `/api/config.json?${q}`;
  const mine = ++sequence;
  if (inflight) inflight.abort();
  const abort = new AbortController();
  inflight = abort;
  setStatus('busy', objective ? 'searching the field settings…' : 'designing…');
  let response, body;
  try {
    response = await api(`/api/design?${q}`, { signal: abort.signal });
    body = await response.text();
  } catch (e) {
    if (mine === sequence) showError(`no answer from the server (${e.message})`);
    return;
  }
  if (mine !== sequence || response.status === 409) return;  // a newer request is under way
  inflight = null;
  if (!response.ok) {
    showError(body.trim());
    return;
  }
  $('error').textContent = '';
  draw(JSON.parse(body));
  setStatus('ready', 'ready');
  root.setAttribute('data-ready', '1');
}

async function upload(file) {
  setStatus('busy', `reading ${file.name}…`);
  const response = await api(`/api/surface?name=${encodeURIComponent(file.name)}`,
    { method: 'POST', body: file });
  const body = await response.text();
  if (!response.ok) { showError(body.trim()); return; }
  const s = JSON.parse(body);
  const o = document.createElement('option');
  o.value = s.surface;
  o.textContent = `${s.name} (${s.triangles} triangles)`;
  $('surface').appendChild(o);
  $('surface').value = s.surface;
  redesign();
}

// ---------------------------------------------------------------------------------------------
// Controls

function setupControls(surfaces) {
  const select = $('surface');
  for (const s of surfaces.surfaces) {
    const o = document.createElement('option');
    o.value = s.id;
    o.textContent = s.name;
    select.appendChild(o);
  }
  select.value = surfaces.initial;
  const changed = (id) => () => { delete linkValues[id]; redesign(); };
  for (const id of ['surface', 'objective', 'symmetry', 'analyze', 'seed']) {
    $(id).addEventListener('change', changed(id));
  }
  // Sliders: a design per change while dragging; superseded ones are dropped.
  for (const id of ['D', 'A', 'cells']) $(id).addEventListener('input', changed(id));
  $('colour').addEventListener('change', () => {
    mode = modes.find((m) => m.key === $('colour').value) || mode;
    applyColours();
  });
  $('show-panels').addEventListener('change', applyColours);
  $('reset').addEventListener('click', resetView);
  for (const [id, name] of [['export-zip', 'gridshell_design.zip'], ['export-config', 'config.json']]) {
    $(id).addEventListener('click', (e) => {
      e.preventDefault();
      if ($(id).dataset.path) download($(id).dataset.path, name);
    });
  }
  $('file').addEventListener('change', (e) => { if (e.target.files[0]) upload(e.target.files[0]); });
  view.addEventListener('dragover', (e) => { e.preventDefault(); view.classList.add('drop'); });
  view.addEventListener('dragleave', () => view.classList.remove('drop'));
  view.addEventListener('drop', (e) => {
    e.preventDefault();
    view.classList.remove('drop');
    if (e.dataTransfer.files[0]) upload(e.dataTransfer.files[0]);
  });
  controls.addEventListener('change', requestRender);
  window.addEventListener('resize', resize);
}

// The link's settings (see the top of this file).
function applyLink() {
  const h = new URLSearchParams(window.location.hash.slice(1));
  for (const id of ['surface', 'objective', 'D', 'A', 'cells', 'symmetry', 'analyze', 'seed']) {
    if (!h.has(id)) continue;
    const el = $(id);
    if (el.tagName === 'SELECT' && ![...el.options].some((o) => o.value === h.get(id))) {
      const o = document.createElement('option');  // e.g. an unknown surface: the server says
      o.value = h.get(id);
      o.textContent = h.get(id);
      el.appendChild(o);
    }
    el.value = h.get(id);
    if (el.value !== h.get(id)) linkValues[id] = h.get(id);
  }
  if (h.has('colour')) mode = { key: h.get('colour') };
  return h;
}

function userInput(id, value) {
  const el = $(id);
  el.value = value;
  el.dispatchEvent(new Event(el.tagName === 'SELECT' ? 'change' : 'input'));
}

async function scripted(h) {
  const burst = Number(h.get('burst') || 0);
  const then = h.get('then');
  if (!burst && !then) return;
  for (let k = 0; k < burst; ++k) {
    userInput('cells', String(100 + 10 * k));
    await new Promise((r) => setTimeout(r, 5));
  }
  if (then) {
    const [id, value] = then.split(':');
    userInput(id, value);
  }
}

let frames = 0;
function loop() {
  if (needsRender) {
    renderer.render(scene, camera);
    needsRender = false;
    frames += 1;
    root.setAttribute('data-frames', String(frames));
  }
  requestAnimationFrame(loop);
}

async function main() {
  setStatus('busy', 'loading');
  const surfaces = await (await api('/api/surfaces')).json();
  setupControls(surfaces);
  const h = applyLink();
  resize();
  requestAnimationFrame(loop);
  await redesign();  // the first design is drawn (or its error shown) before any scripted change
  if (root.getAttribute('data-status') === 'error') root.setAttribute('data-ready', '1');
  await scripted(h);
}

main();
