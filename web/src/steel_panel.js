// The "Steel" section of report.html's side panel, from report.json: the steel mass (kg, kg/m² of
// plan), its embodied carbon and factor, the distinct sections (`mass` block, every analysed
// design); and for a sized design (`sizing` block, docs/sizing.md) the verdict, the iterations
// and their history (mass and largest utilisation per iteration, as a plot and a table).

import { cssColour, escapeHtml, fmt, sectionCategories } from './gridshell_scene.js';

function row(name, value, id) {
  return `<tr><th>${name}</th><td${id ? ` id="${id}"` : ''}>${value}</td></tr>`;
}

function isNum(x) {
  return typeof x === 'number' && Number.isFinite(x);
}

// Mass, plan area, carbon and the number of distinct sections.
function massTable(m) {
  let html = '<table>';
  if (isNum(m.mass_kg)) html += row('steel mass', `${fmt(m.mass_kg)} kg`, 'steel-mass');
  if (isNum(m.mass_kg_per_m2)) {
    html += row('per plan area', `${fmt(m.mass_kg_per_m2)} kg/m²` +
      (isNum(m.plan_area_m2) ? ` (plan ${fmt(m.plan_area_m2)} m²)` : ''));
  }
  if (isNum(m.carbon_kgCO2e)) {
    html += row('embodied carbon (A1–A3)', `${fmt(m.carbon_kgCO2e)} kgCO2e` +
      (isNum(m.carbon_factor_kgCO2e_per_kg) ? ` (${fmt(m.carbon_factor_kgCO2e_per_kg)} kgCO2e/kg)`
        : ''), 'steel-carbon');
  }
  if (m.distinct_sections != null) html += row('distinct sections', m.distinct_sections);
  return `${html}</table>`;
}

// The distinct sections, lightest per metre first, with the section colouring's swatches when
// the page has per-beam sections.
function sectionsTable(m, data) {
  const list = Array.isArray(m.sections) ? m.sections.slice() : [];
  if (!list.length) return '';
  const colour = new Map(sectionCategories(data).map((c) => [c.designation, c.colour]));
  const perM = (s) => (s.length_m > 0 ? s.mass_kg / s.length_m : Infinity);
  list.sort((a, b) => perM(a) - perM(b));
  let html = '<table id="steel-sections"><tr><th>section</th><td>members</td><td>length</td>' +
    '<td>mass</td></tr>';
  for (const s of list) {
    const c = colour.get(s.designation);
    const swatch = c ? `<span class="swatch" style="background:${cssColour(c)}"></span> ` : '';
    html += `<tr><th>${swatch}${escapeHtml(s.designation)}</th><td>${s.members ?? '–'}</td>` +
      `<td>${fmt(s.length_m, 3)} m</td><td>${fmt(s.mass_kg, 3)} kg</td></tr>`;
  }
  return `${html}</table>`;
}

// An SVG plot of the sizing history: mass [kg] (solid, left axis) and the largest utilisation
// (dashed, right axis, with the line u = 1) against the iteration.
function historyPlot(h) {
  const W = 300, H = 150, L = 46, R = 34, T = 10, B = 26;
  const it = h.map((e) => e.iteration);
  const mass = h.map((e) => e.mass_kg);
  const util = h.map((e) => e.utilisation_max);
  if (!it.every(isNum) || !mass.every(isNum) || !util.every(isNum)) return '';
  const x0 = Math.min(...it), x1 = Math.max(x0 + 1, ...it);
  let m0 = Math.min(...mass), m1 = Math.max(...mass);
  if (!(m1 > m0)) { m0 -= 1; m1 += 1; }
  const u1 = Math.max(1.1, ...util);
  const X = (x) => L + (x - x0) / (x1 - x0) * (W - L - R);
  const Ym = (m) => T + (1 - (m - m0) / (m1 - m0)) * (H - T - B);
  const Yu = (u) => T + (1 - u / u1) * (H - T - B);
  const path = (ys) => ys.map((y, k) => `${k ? 'L' : 'M'}${X(it[k]).toFixed(1)},${y.toFixed(1)}`)
    .join('');
  const text = (x, y, s, anchor, colour) => `<text x="${x}" y="${y}" text-anchor="${anchor}" ` +
    `fill="${colour}" font-size="10">${s}</text>`;
  let svg = `<svg id="sizing-plot" width="${W}" height="${H}" viewBox="0 0 ${W} ${H}" ` +
    'role="img" aria-label="sizing history">';
  svg += `<rect x="${L}" y="${T}" width="${W - L - R}" height="${H - T - B}" fill="none" ` +
    'stroke="#bbb"/>';
  svg += `<line x1="${L}" x2="${W - R}" y1="${Yu(1)}" y2="${Yu(1)}" stroke="#c33" ` +
    'stroke-width="0.8" stroke-dasharray="2,2"/>';
  svg += `<path d="${path(util.map(Yu))}" fill="none" stroke="#c60" stroke-width="1.5" ` +
    'stroke-dasharray="5,3"/>';
  svg += `<path d="${path(mass.map(Ym))}" fill="none" stroke="#14a" stroke-width="1.8"/>`;
  svg += text(L - 3, T + 8, fmt(m1, 3), 'end', '#14a');
  svg += text(L - 3, H - B, fmt(m0, 3), 'end', '#14a');
  svg += text(W - R + 3, T + 8, fmt(u1, 2), 'start', '#c60');
  svg += text(W - R + 3, Yu(1) + 3, '1', 'start', '#c33');
  svg += text(W - R + 3, H - B, '0', 'start', '#c60');
  svg += text(L, H - 12, String(x0), 'middle', '#555');
  svg += text(W - R, H - 12, String(x1), 'middle', '#555');
  svg += text((L + W - R) / 2, H - 2, 'iteration', 'middle', '#555');
  svg += text(L - 3, H / 2, 'kg', 'end', '#14a');
  svg += text(W - R + 3, H / 2 + 12, 'u max', 'start', '#c60');
  return `${svg}</svg><div class="legend-note">mass (solid, kg) and largest utilisation ` +
    '(dashed; red: 1) per iteration</div>';
}

function historyTable(h) {
  let html = '<table id="sizing-history"><tr><th>it.</th><td>phase</td><td>mass kg</td>' +
    '<td>u max</td><td>λ</td><td>changed</td></tr>';
  for (const e of h) {
    html += `<tr><th>${e.iteration}</th><td>${escapeHtml(e.phase ?? '')}</td>` +
      `<td>${fmt(e.mass_kg)}</td><td>${fmt(e.utilisation_max, 3)}</td>` +
      `<td>${fmt(e.lambda, 3)}</td>` +
      `<td>${e.changed ?? '–'}</td></tr>`;
  }
  return `${html}</table>`;
}

// The verdict of a sized design: sized (with how it converged) or not (the failure, in red).
function verdictHtml(s) {
  return s.sized
    ? `<p id="sizing-verdict"><b style="color:#161">sized</b>${s.convergence
      ? `: ${escapeHtml(s.convergence)}` : ''}</p>`
    : `<p id="sizing-verdict" style="color:#b00"><b>not sized</b>${s.failure
      ? `: ${escapeHtml(s.failure)}` : ''}</p>`;
}

// The iterations of a sized design and their history.
function historyHtml(s) {
  let html = '<table>';
  if (s.iterations != null) html += row('sizing iterations', s.iterations);
  if (isNum(s.lambda_min)) html += row('λ required (imperfect)', `≥ ${fmt(s.lambda_min)}`);
  html += '</table>';
  const h = Array.isArray(s.history) ? s.history.filter((e) => e && typeof e === 'object') : [];
  if (h.length > 1) html += historyPlot(h);
  if (h.length) {
    html += `<details${h.length <= 12 ? ' open' : ''}><summary>history</summary>` +
      `${historyTable(h)}</details>`;
  }
  return html;
}

// Fills #steel (and shows #steel-section) when report.json has a `mass` or `sizing` block.
export function steelPanel(data) {
  const report = data.report || {};
  const obj = (x) => (x && typeof x === 'object' && !Array.isArray(x) ? x : null);
  const s = obj(report.sizing);
  const m = obj(report.mass) || s;
  if (!m) return;
  let html = s ? verdictHtml(s) : '';
  html += massTable(m) + sectionsTable(m, data);
  if (s) html += historyHtml(s);
  document.getElementById('steel').innerHTML = html;
  document.getElementById('steel-section').hidden = false;
}
