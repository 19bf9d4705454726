// What report.html's viewer (viewer.js) and the studio page (studio.js) share: colour maps, the
// colour modes a grid-shell's data offers, the legend, number formatting, and the three.js
// objects of a grid-shell (beams as fat lines, panels, joints, supports) built from the data
// block of report/report_html.h: { joints: [x,y,z,...], beams: [i,j,...], panels: [[...]...],
// supports: [...], axial_force, displacement, density, planarity, utilisation,
// buckling_utilisation, beam_sections }.

import * as THREE from 'three';
import { LineSegments2 } from 'three/addons/lines/LineSegments2.js';
import { LineSegmentsGeometry } from 'three/addons/lines/LineSegmentsGeometry.js';
import { LineMaterial } from 'three/addons/lines/LineMaterial.js';

/// The renderer (drawn into `view`, pixels kept for screenshots) and the lit scene both pages use.
export function createScene(view) {
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setClearColor(0xf6f6f3, 1);
  view.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.add(new THREE.HemisphereLight(0xffffff, 0x888880, 2.2));
  const sun = new THREE.DirectionalLight(0xffffff, 1.2);
  sun.position.set(1, -1, 2);
  scene.add(sun);
  return { renderer, scene };
}

// ---------------------------------------------------------------------------------------------
// Colour maps: a sequential one (dark blue → green → yellow) and a diverging one for axial
// forces (compression red, 0 light grey, tension blue).

export const SEQUENTIAL = [
  [0.267, 0.005, 0.329], [0.229, 0.322, 0.546], [0.128, 0.567, 0.551],
  [0.369, 0.789, 0.383], [0.993, 0.906, 0.144],
];
export const DIVERGING = [[0.70, 0.05, 0.12], [0.88, 0.38, 0.30], [0.58, 0.58, 0.58],
  [0.33, 0.53, 0.86], [0.08, 0.22, 0.62]];

export function sample(stops, t) {
  const x = Math.min(1, Math.max(0, Number.isFinite(t) ? t : 0)) * (stops.length - 1);
  const i = Math.min(stops.length - 2, Math.floor(x));
  const f = x - i;
  const a = stops[i], b = stops[i + 1];
  return [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])];
}

export function cssGradient(stops) {
  const parts = stops.map((c, i) => {
    const rgb = c.map((v) => Math.round(v * 255)).join(',');
    return `rgb(${rgb}) ${(100 * i / (stops.length - 1)).toFixed(0)}%`;
  });
  return `linear-gradient(to right, ${parts.join(', ')})`;
}

export function fmt(x, digits = 4) {
  if (x == null) return '–';
  if (typeof x !== 'number') return String(x);
  if (x === 0) return '0';
  const a = Math.abs(x);
  if (a >= 1e5 || a < 1e-3) return x.toExponential(digits - 1);
  return Number(x.toPrecision(digits)).toString();
}

export function escapeHtml(s) {
  return String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' })[c]);
}

// The panel count of a key-figures table: the cells, and when the flat-panel stage glazed some
// as flat triangles (report.json design.flat_panels), how many and into how many panes.
export function cellsText(report, panes) {
  const fp = ((report || {}).design || {}).flat_panels || {};
  const k = Number(fp.triangulated_panels) || 0, cells = Number(fp.cells);
  if (!(k > 0) || !Number.isFinite(cells)) return String(panes);
  return `${cells} (${k} glazed as ${panes - cells + k} triangles)`;
}

// Overlaps (report.json mesh.overlaps: beams that cross without a joint, joints inside a panel
// not their own): a count, red when the grid-shell cannot be built as it is.
export function overlapsText(n) {
  if (n == null) return null;
  const count = Number(n);  // numbers only: nothing from the report reaches the page as markup
  return count > 0 ? `<b style="color:#b00">${count}</b> (not buildable as is)` : String(count);
}

// A qualitative palette for categories (beam sections): Kelly's colours of maximum contrast
// (K. L. Kelly, 1965), ordered so that neighbours differ most and the pale ones come last; beyond
// 20, hues step by the golden angle.
export const QUALITATIVE = [
  '#0067a5', '#be0032', '#008856', '#f38400', '#875692', '#882d17', '#e68fac', '#2b3d26',
  '#f3c300', '#604e97', '#8db600', '#848482', '#b3446c', '#a1caf1', '#e25822', '#654522',
  '#dcd300', '#c2b280', '#f99379', '#f6a600',
].map((h) => [1, 3, 5].map((k) => parseInt(h.slice(k, k + 2), 16) / 255));

export function categoryColour(k) {
  if (k < QUALITATIVE.length) return QUALITATIVE[k];
  const c = new THREE.Color().setHSL(((k * 137.508) % 360) / 360, 0.65, 0.45);
  return [c.r, c.g, c.b];
}

export function cssColour(rgb) {
  return `rgb(${rgb.map((v) => Math.round(v * 255)).join(',')})`;
}

// The distinct beam sections of `data` (data.beam_sections, one designation per beam), lightest
// per metre first, each { designation, members, mass_kg, length_m, kg_per_m, colour }; the
// section with the most members gets the palette's first colour, the next the second, …. Mass and
// length come from report.json's `mass` (or `sizing`) section list; without it (or for a name it
// lacks) they are unknown and the sections follow their names in natural order. [] when the
// data has no per-beam sections.
export function sectionCategories(data) {
  const nBeams = (data.beams || []).length / 2;
  const names = data.beam_sections;
  if (!nBeams || !names || names.length !== nBeams) return [];
  const report = data.report || {};
  const listed = new Map();
  for (const s of (report.mass && report.mass.sections) ||
    (report.sizing && report.sizing.sections) || []) {
    if (s && typeof s.designation === 'string') listed.set(s.designation, s);
  }
  const byName = new Map();
  for (const n of names) {
    if (!byName.has(n)) {
      const s = listed.get(n) || {};
      const kgPerM = s.length_m > 0 ? s.mass_kg / s.length_m : null;
      byName.set(n, { designation: n, members: 0, mass_kg: s.mass_kg ?? null,
        length_m: s.length_m ?? null, kg_per_m: kgPerM });
    }
    byName.get(n).members += 1;
  }
  const cats = Array.from(byName.values());
  const natural = (a, b) => a.designation.localeCompare(b.designation, 'en', { numeric: true });
  cats.sort((a, b) => {
    if (a.kg_per_m != null && b.kg_per_m != null && a.kg_per_m !== b.kg_per_m) {
      return a.kg_per_m - b.kg_per_m;
    }
    if ((a.kg_per_m == null) !== (b.kg_per_m == null)) return a.kg_per_m == null ? 1 : -1;
    return natural(a, b);
  });
  // Colours go by number of members, so that the sections most of the grid-shell is made of get
  // the palette's most distinct colours (ties: lighter first).
  const byMembers = cats.map((c, k) => [c.members, k]).sort((x, y) => y[0] - x[0] || x[1] - y[1]);
  byMembers.forEach(([, k], rank) => {
    const c = categoryColour(rank);
    cats[k].colour = c;  // sRGB, as the legend's swatch shows it
    // The same colour in three.js's linear working space: the renderer converts it back to sRGB,
    // so the beams show the swatch's colour.
    const lin = new THREE.Color().setRGB(c[0], c[1], c[2], THREE.SRGBColorSpace);
    cats[k].linear = [lin.r, lin.g, lin.b];
  });
  return cats;
}

// ---------------------------------------------------------------------------------------------
// Colour modes

// Per-joint displacement magnitude [m], or null when the data has none.
export function displacementMagnitudes(data) {
  const nJoints = (data.joints || []).length / 3;
  const d = data.displacement;
  if (!nJoints || !d || d.length !== 3 * nJoints) return null;
  const mag = new Float64Array(nJoints);
  for (let v = 0; v < nJoints; ++v) mag[v] = Math.hypot(d[3 * v], d[3 * v + 1], d[3 * v + 2]);
  return mag;
}

// The colour modes present in the data. `on`: what carries the value (beam, joint or panel);
// lo/hi: the colour range, min/max: the values' range.
export function colourModes(data) {
  const nBeams = (data.beams || []).length / 2;
  const panels = data.panels || [];
  const dispMag = displacementMagnitudes(data);
  const modes = [{ key: 'plain', label: 'plain', on: 'none' }];
  if (nBeams && data.axial_force && data.axial_force.length === nBeams) {
    modes.push({ key: 'axial', label: 'axial force', unit: 'kN', on: 'beam', diverging: true,
      values: data.axial_force.map((n) => n / 1000),
      note: 'compression < 0 (red), tension > 0 (blue)' });
  }
  if (dispMag) {
    modes.push({ key: 'displacement', label: 'displacement', unit: 'mm', on: 'joint',
      values: Array.from(dispMag, (d) => d * 1000), note: 'linear, under the reference load' });
  }
  if (data.density && data.density.length === panels.length && panels.length) {
    modes.push({ key: 'density', label: 'cell density d_target', unit: '–', on: 'panel',
      values: data.density, note: '1 = the sparsest cells the field asks for' });
  }
  if (data.planarity && data.planarity.length === panels.length && panels.length) {
    modes.push({ key: 'planarity', label: 'panel planarity', unit: '–', on: 'panel',
      values: data.planarity, note: 'mean distance to the plane / half perimeter; 0 = flat' });
  }
  if (data.out_of_plane_mm && data.out_of_plane_mm.length === panels.length && panels.length) {
    modes.push({ key: 'out_of_plane', label: 'panel out of plane', unit: 'mm', on: 'panel',
      values: data.out_of_plane_mm,
      note: 'largest corner distance to the panel\'s best-fit plane; flat glass needs ≲ 0.5 mm' });
  }
  if (nBeams && data.utilisation && data.utilisation.length === nBeams) {
    modes.push({ key: 'utilisation', label: 'utilisation, cross-section', unit: '–', on: 'beam',
      values: data.utilisation,
      note: 'EN 1993-1-1 §6.2, primary combination (sized: worst ULS combination); 1 = the ' +
        'check is just met' });
    const bu = data.buckling_utilisation;
    if (bu && bu.length === nBeams) {
      modes.push({ key: 'governing', label: 'utilisation, governing check', unit: '–', on: 'beam',
        values: data.utilisation.map((u, b) => Math.max(u, bu[b])),
        note: 'larger of cross-section (§6.2) and member buckling (§6.3), primary ' +
          'combination (sized: worst ULS combination); 1 = just met' });
    }
  }
  const cats = sectionCategories(data);
  if (cats.length) {
    const index = new Map(cats.map((c, k) => [c.designation, k]));
    modes.push({ key: 'section', label: 'section', unit: '', on: 'beam', categorical: true,
      categories: cats, values: data.beam_sections.map((n) => index.get(n)),
      note: 'lightest per metre first' });
  }
  for (const m of modes) {
    if (!m.values || m.categorical) continue;
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
    if (m.key === 'utilisation' || m.key === 'governing') { lo = 0; hi = Math.max(1, hi); }
    if (m.key === 'planarity' || m.key === 'out_of_plane') lo = 0;
    if (!(hi > lo)) hi = lo + 1;
    m.lo = lo; m.hi = hi;
    m.stops = m.diverging ? DIVERGING : SEQUENTIAL;
  }
  return modes;
}

// The legend of a colour mode, as HTML.
export function legendHtml(mode) {
  if (!mode.values) {
    return '<div class="legend-title">beams dark, panels light blue, supports as black cubes</div>';
  }
  if (mode.categorical) return categoryLegendHtml(mode);
  const mid = mode.diverging ? 0 : 0.5 * (mode.lo + mode.hi);
  return `<div class="legend-title">${mode.label} [${mode.unit}] — on the ${mode.on}s</div>` +
    `<div class="legend-bar" style="background:${cssGradient(mode.stops)}"></div>` +
    `<div class="legend-ticks"><span>${fmt(mode.lo, 3)}</span><span>${fmt(mid, 3)}</span>` +
    `<span>${fmt(mode.hi, 3)}</span></div>` +
    `<div class="legend-note">${mode.note}; range ${fmt(mode.min, 3)} … ${fmt(mode.max, 3)}` +
    `${mode.min < mode.lo || mode.max > mode.hi ? ' (colours saturate at the ends)' : ''}</div>`;
}

// The legend of the section colouring: one row per section (swatch, designation, members, mass).
function categoryLegendHtml(mode) {
  let rows = '';
  for (const c of mode.categories) {
    rows += `<tr class="legend-entry"><td><span class="swatch" style="background:` +
      `${cssColour(c.colour)}"></span></td><th>${escapeHtml(c.designation)}</th>` +
      `<td>${c.members}</td><td>${c.mass_kg == null ? '–' : `${fmt(c.mass_kg, 3)} kg`}</td></tr>`;
  }
  return `<div class="legend-title">${mode.label} — on the beams, ${mode.categories.length} ` +
    `distinct, ${mode.note}</div><div class="legend-table"><table><tr class="legend-head">` +
    `<td></td><th>designation</th><td>members</td><td>mass</td></tr>${rows}</table></div>`;
}

// ---------------------------------------------------------------------------------------------
// The three.js objects of a grid-shell

const BEAM_PLAIN = [0.22, 0.24, 0.27];
const PANEL_PLAIN = [0.70, 0.80, 0.90];

// The bounding box of the joints: { center, radius, span } (a unit box when there are none).
export function jointBounds(joints) {
  const box = new THREE.Box3();
  for (let v = 0; v < joints.length / 3; ++v) {
    box.expandByPoint(new THREE.Vector3(joints[3 * v], joints[3 * v + 1], joints[3 * v + 2]));
  }
  if (box.isEmpty()) box.set(new THREE.Vector3(-1, -1, -1), new THREE.Vector3(1, 1, 1));
  const size = box.getSize(new THREE.Vector3());
  return { center: box.getCenter(new THREE.Vector3()), radius: Math.max(1e-6, 0.5 * size.length()),
    span: Math.max(size.x, size.y, size.z, 1e-6) };
}

// Builds the objects of `data` and adds them to `group` (a THREE.Group or Scene). `pos`: the
// joints' current positions (Float32Array, 3 per joint), read by updatePositions(). Returns the
// objects and:
//   updatePositions()          after `pos` changed
//   applyColours(mode)         colour by a mode of colourModes(data)
//   dispose()                  removes the objects from `group` and frees their GPU buffers
export function buildGridObjects(data, group, pos) {
  const joints = data.joints || [];
  const nJoints = joints.length / 3;
  const beams = data.beams || [];
  const nBeams = beams.length / 2;
  const panels = data.panels || [];
  const supports = data.supports || [];
  const bounds = jointBounds(joints);

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
    group.add(beamLines);
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
  if (nCorners > 0) group.add(panelMesh);

  // Joints (for picking, drawn small) and supports (dark cubes).
  const jointGeometry = new THREE.BufferGeometry();
  jointGeometry.setAttribute('position', new THREE.BufferAttribute(pos, 3));
  const jointMaterial = new THREE.PointsMaterial({ color: 0x444444, size: 2, sizeAttenuation: false });
  const jointPoints = new THREE.Points(jointGeometry, jointMaterial);
  group.add(jointPoints);

  const supportSize = Math.max(bounds.span / 120, 1e-6);
  const supportGeometry = new THREE.BoxGeometry(supportSize, supportSize, supportSize);
  const supportMaterial = new THREE.MeshLambertMaterial({ color: 0x202020 });
  const supportMesh = new THREE.InstancedMesh(supportGeometry, supportMaterial,
    Math.max(1, supports.length));
  supportMesh.count = supports.length;
  {
    const m = new THREE.Matrix4();
    supports.forEach((v, i) => {
      m.makeTranslation(joints[3 * v], joints[3 * v + 1], joints[3 * v + 2]);
      supportMesh.setMatrixAt(i, m);
    });
  }
  if (supports.length) group.add(supportMesh);

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

  function applyColours(mode) {
    const bc = beamColors, pc = panelGeometry.attributes.color.array;
    const t = (x) => (x - mode.lo) / (mode.hi - mode.lo);
    for (let b = 0; b < nBeams; ++b) {
      let ci = BEAM_PLAIN, cj = BEAM_PLAIN;
      if (mode.on === 'beam') {
        ci = cj = mode.categorical ? mode.categories[mode.values[b]].linear
          : sample(mode.stops, t(mode.values[b]));
      }
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
  }

  function dispose() {
    for (const o of [beamLines, panelMesh, jointPoints, supportMesh]) if (o) group.remove(o);
    for (const x of [beamGeometry, beamMaterial, panelGeometry, panelMaterial, jointGeometry,
      jointMaterial, supportGeometry, supportMaterial]) x.dispose();
    supportMesh.dispose();
  }

  return { nJoints, nBeams, nCorners, bounds, beamLines, beamMaterial, panelMesh, jointPoints,
    supportMesh, cornerJoint, triPanel, updatePositions, applyColours, dispose };
}
