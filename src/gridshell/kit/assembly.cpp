#include "gridshell/kit/assembly.h"

#include <algorithm>
#include <set>
#include <tuple>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace gridshell::kit {

namespace {

/// Joints next to be placed, best first: most rods into the assembled part, lowest, smallest id.
struct Frontier {
  const KitFrame& frame;
  std::vector<int> links;  // per joint: rods into placed joints
  std::set<std::tuple<int, double, int>> queue;  // (−links, z, id)

  void raise(int j) {
    if (links[j] > 0) queue.erase({-links[j], frame.joints[j].position.z(), j});
    ++links[j];
    queue.insert({-links[j], frame.joints[j].position.z(), j});
  }
  void drop(int j) {
    if (links[j] > 0) queue.erase({-links[j], frame.joints[j].position.z(), j});
  }
};

int other_end(const KitBeam& b, int j) {
  return b.joint_i == j ? b.joint_j : b.joint_i;
}

}  // namespace

std::vector<AssemblyStep> assembly_order(const KitFrame& frame, const std::vector<char>& bridged) {
  const int n = static_cast<int>(frame.joints.size());
  const auto is_bridge = [&bridged](int b) {
    return static_cast<std::size_t>(b) < bridged.size() && bridged[b];
  };
  std::vector<char> placed(n, 0);
  Frontier frontier{frame, std::vector<int>(n, 0), {}};
  std::vector<int> glue;  // joints glued to placed ones, next to place (a stack: chains in order)
  std::vector<AssemblyStep> steps;
  const auto place = [&](int j) {
    AssemblyStep s{j, {}, {}};
    for (int b : frame.joints[j].beams)
      if (placed[other_end(frame.beams[b], j)]) (is_bridge(b) ? s.glued : s.rods).push_back(b);
    std::sort(s.rods.begin(), s.rods.end());
    std::sort(s.glued.begin(), s.glued.end());
    placed[j] = 1;
    frontier.drop(j);
    std::vector<int> beams = frame.joints[j].beams;
    std::sort(beams.rbegin(), beams.rend());  // the smallest beam id's partner first
    for (int b : beams) {
      const int o = other_end(frame.beams[b], j);
      if (placed[o]) continue;
      frontier.raise(o);
      if (is_bridge(b)) glue.push_back(o);
    }
    steps.push_back(std::move(s));
  };
  for (int j = 0; j < n; ++j)
    if (frame.joints[j].support && !frame.joints[j].beams.empty() && !placed[j]) place(j);
  for (;;) {
    if (!glue.empty()) {
      const int j = glue.back();
      glue.pop_back();
      if (!placed[j]) place(j);
      continue;
    }
    if (!frontier.queue.empty()) {
      place(std::get<2>(*frontier.queue.begin()));
      continue;
    }
    // A part not joined to what stands: start it at its lowest joint.
    int start = -1;
    for (int j = 0; j < n; ++j)
      if (!placed[j] && !frame.joints[j].beams.empty() &&
          (start < 0 || frame.joints[j].position.z() < frame.joints[start].position.z()))
        start = j;
    if (start < 0) break;
    place(start);
  }
  return steps;
}

std::string assembly_html(const KitFrame& frame, const std::vector<AssemblyStep>& steps,
                          const std::vector<Rod>& rods, const KitOptions& options) {
  nlohmann::json data = {{"scale", options.scale},
                         {"joints", nlohmann::json::array()},
                         {"beams", nlohmann::json::array()},
                         {"steps", nlohmann::json::array()}};
  for (const KitJoint& j : frame.joints)
    data["joints"].push_back({1000 * j.position.x() / options.scale,
                              -1000 * j.position.y() / options.scale, j.support});
  for (const KitBeam& b : frame.beams) data["beams"].push_back({b.joint_i, b.joint_j});
  std::vector<int> bridges;
  for (const AssemblyStep& s : steps) bridges.insert(bridges.end(), s.glued.begin(), s.glued.end());
  data["bridges"] = bridges;
  std::vector<double> length(frame.beams.size(), 0.0);
  for (const Rod& r : rods) length[r.beam] = r.length_mm;
  data["rod_mm"] = length;
  for (const AssemblyStep& s : steps)
    data["steps"].push_back({{"joint", s.joint}, {"rods", s.rods}, {"glued", s.glued}});
  // The page: plan view (x right, y up; model millimetres), controls and the table.
  return fmt::format(R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>gridshell kit: assembly</title>
<style>
body{{font-family:sans-serif;margin:1em}} svg{{width:100%;height:60vh;border:1px solid #ccc}}
line{{stroke:#ddd;stroke-width:var(--w)}} line.bridge{{stroke-dasharray:calc(2*var(--w))}} line.done{{stroke:#333}} line.now{{stroke:#d22}}
circle{{fill:#ccc}} circle.done{{fill:#333}} circle.now{{fill:#d22}} circle.support{{stroke:#27c}}
table{{border-collapse:collapse}} td,th{{border:1px solid #ccc;padding:2px 6px;text-align:left}}
tr.now{{background:#fdd}} @media print{{svg,#controls{{display:none}}}}
</style></head><body>
<h1>Assembly: {0} joints, {1} rods, {4} bridges (1:{2:g})</h1>
<p>Place the joints in this order. Supported joints (blue ring) stand on the base board; every
other joint goes in with the rods that join it to what already stands (rod lengths from
rods.csv, joint J&lt;id&gt; is joints/J&lt;id&gt;.stl, its id engraved in its flat base). A beam too
short for a rod is a printed bridge (bridges.csv, dashed): glue the joint's flat face to its
partner's, which is placed just before it.</p>
<div id="controls"><button id="prev">&#9664;</button> <input id="step" type="range" min="1"
max="{0}" value="1" style="width:50%"> <button id="next">&#9654;</button> <b id="say"></b></div>
<svg id="plan"></svg>
<table><thead><tr><th>step</th><th>joint</th><th>rods to insert (length mm)</th><th>glue to</th></tr></thead>
<tbody id="list"></tbody></table>
<script>
const D = {3};
const svg = document.getElementById('plan'), NS = 'http://www.w3.org/2000/svg';
let lo = [1e300, 1e300], hi = [-1e300, -1e300];
for (const j of D.joints) for (const k of [0, 1]) {{ lo[k] = Math.min(lo[k], j[k]); hi[k] = Math.max(hi[k], j[k]); }}
const pad = 0.05 * Math.max(hi[0] - lo[0], hi[1] - lo[1], 1);
svg.setAttribute('viewBox', [lo[0] - pad, lo[1] - pad, hi[0] - lo[0] + 2 * pad, hi[1] - lo[1] + 2 * pad].join(' '));
svg.style.setProperty('--w', pad / 25);
const lines = D.beams.map(([a, b]) => {{ const l = document.createElementNS(NS, 'line');
  [['x1', D.joints[a][0]], ['y1', D.joints[a][1]], ['x2', D.joints[b][0]], ['y2', D.joints[b][1]]].forEach(([k, v]) => l.setAttribute(k, v));
  svg.appendChild(l); return l; }});
const dots = D.joints.map((j) => {{ const c = document.createElementNS(NS, 'circle');
  c.setAttribute('cx', j[0]); c.setAttribute('cy', j[1]); c.setAttribute('r', pad / 12);
  if (j[2]) c.classList.add('support'); svg.appendChild(c); return c; }});
const list = document.getElementById('list');
const rows = D.steps.map((s, k) => {{ const tr = document.createElement('tr');
  const rods = s.rods.map((r) => `rod ${{r}} (${{D.rod_mm[r].toFixed(1)}})`).join(', ');
  const glue = s.glued.map((b) => `J${{D.beams[b][0] === s.joint ? D.beams[b][1] : D.beams[b][0]}} (bridge ${{b}})`).join(', ');
  tr.innerHTML = `<td>${{k + 1}}</td><td>J${{s.joint}}${{D.joints[s.joint][2] ? ' (support)' : ''}}</td><td>${{rods || '&ndash;'}}</td><td>${{glue || '&ndash;'}}</td>`;
  list.appendChild(tr); return tr; }});
const slider = document.getElementById('step');
function show(n) {{
  n = Math.max(1, Math.min(D.steps.length, n)); slider.value = n;
  lines.forEach((l, b) => l.setAttribute('class', D.bridges.includes(b) ? 'bridge' : '')); dots.forEach((c) => c.classList.remove('done', 'now'));
  rows.forEach((r) => r.classList.remove('now'));
  for (let k = 0; k < n; ++k) {{ const s = D.steps[k], now = k === n - 1;
    dots[s.joint].classList.add(now ? 'now' : 'done');
    for (const r of s.rods) lines[r].setAttribute('class', now ? 'now' : 'done');
    for (const r of s.glued) lines[r].setAttribute('class', (now ? 'now' : 'done') + ' bridge'); }}
  rows[n - 1].classList.add('now');
  const s = D.steps[n - 1];
  document.getElementById('say').textContent = `step ${{n}} of ${{D.steps.length}}: joint J${{s.joint}}` +
    (s.rods.length ? `, rods ${{s.rods.join(', ')}}` : '');
}}
document.getElementById('prev').onclick = () => show(+slider.value - 1);
document.getElementById('next').onclick = () => show(+slider.value + 1);
slider.oninput = () => show(+slider.value);
if (D.steps.length) show(1);
</script></body></html>
)",
                     steps.size(), rods.size(), options.scale, data.dump(), bridges.size());
}

}  // namespace gridshell::kit
