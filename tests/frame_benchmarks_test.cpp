// Classic frame-stability benchmarks given to `gridshell analyze` as MODEL.json files without
// any option: the default path must reach each one's first limit point or bifurcation, within
// 2 % of the published or closed-form value, and classify it (docs/frame.md, validation table).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "gridshell/io/files.h"
#include "test_support.h"

using namespace gridshell;
using nlohmann::json;

namespace {
constexpr double kPi = std::numbers::pi;

// A planar frame in the x–z plane: bending about y is the benchmark's; out of plane the
// sections are stiff and the supports hold rx and rz, so nothing leaves the plane.
json planar_model(const std::vector<std::array<double, 2>>& xz, double E, double A, double I) {
  json m;
  m["nodes"] = json::array();
  for (const auto& p : xz) m["nodes"].push_back({p[0], 0.0, p[1]});
  m["sections"]["s"] = {{"A", A}, {"Iy", I}, {"Iz", 50 * I}, {"J", 50 * I}};
  m["materials"]["m"] = {{"E", E}};
  m["members"] = json::array();
  return m;
}

json support(int node, bool clamped) {
  json fix = {"ux", "uy", "uz", "rx", "rz"};
  if (clamped) fix.push_back("ry");
  return {{"node", node}, {"fix", fix}};
}

struct Outcome {
  double lambda = 0;
  std::string limit_type, stop_reason;
};

// Runs `gridshell analyze MODEL.json` with no option but the output folder.
Outcome analyze(const std::string& name, const json& model) {
  const auto dir = test::temp_dir("bench_" + name);
  io::write_file_atomic(dir / "model.json", model.dump());
  const auto r =
      test::run_gridshell(fmt::format("analyze '{}' -o '{}' --quiet --figures none",
                                      (dir / "model.json").string(), (dir / "out").string()));
  EXPECT_EQ(r.status, 0) << r.err;
  if (r.status != 0) return {};
  const json s = json::parse(io::read_file(dir / "out" / "report.json"))["structure"];
  return {s["lambda_perfect"].get<double>(), s["limit_type"].get<std::string>(),
          s["nonlinear_stop_reason"].get<std::string>()};
}

/// The benchmark's first critical point: within 2 % of `reference`, of the published `type`.
void expect_critical(const char* what, double value, double reference, const char* type,
                     const Outcome& o) {
  std::printf("%s = %.6f, reference %.6f (%s; %s)\n", what, value, reference,
              o.limit_type.c_str(), o.stop_reason.c_str());
  EXPECT_EQ(o.limit_type, type) << what;
  EXPECT_NEAR(value / reference, 1.0, 0.02) << what;
}
}  // namespace

// Lee's frame (Lee, Manuel & Rossow 1968; Schweizerhof & Wriggers 1986): columns and beam of
// length L = 120, hinged ends, load at L/5 from the knee; limit load P L²/EI = 18.5–18.6 (the
// literature's 18.55). The old automatic stop (span / 5) cut the path at P L²/EI ≈ 13.5.
TEST(FrameBenchmarks, LeesFrameLimitPoint) {
  const double L = 120, E = 720, I = 2;
  json m = planar_model({{0, 0}, {0, L}, {L / 5, L}, {L, L}}, E, 6, I);
  m["members"] = {{{"nodes", {0, 1}}, {"elements", 10}},
                  {{"nodes", {1, 2}}, {"elements", 2}},
                  {{"nodes", {2, 3}}, {"elements", 8}}};
  m["supports"] = {support(0, false), support(3, false)};
  m["loads"] = {{{"node", 2}, {"force", {0, 0, -1}}}};
  const Outcome o = analyze("lee", m);
  const double p = o.lambda * L * L / (E * I);
  expect_critical("Lee's frame P L^2/EI", p, 18.55, "limit point", o);
}

// The shallow von Mises truss: two bars of half-span a and rise h. The closed form of the load
// at the apex deflection w, P(w) = 2 EA (l0 − l)/l0 · (h − w)/l with l = √(a² + (h − w)²),
// maximised over w (a fine scan) is the limit load.
TEST(FrameBenchmarks, VonMisesTrussLimitPoint) {
  const double a = 10, h = 0.5, EA = 1e5;
  json m = planar_model({{-a, 0}, {0, h}, {a, 0}}, EA, 1, 1);
  m["members"] = {{{"nodes", {0, 1}}, {"type", "truss"}}, {{"nodes", {2, 1}}, {"type", "truss"}}};
  m["supports"] = {{{"node", 0}}, {{"node", 2}}, {{"node", 1}, {"fix", {"uy"}}}};
  m["loads"] = {{{"node", 1}, {"force", {0, 0, -1}}}};
  const double l0 = std::hypot(a, h);
  double closed = 0;
  for (int i = 0; i <= 400000; ++i) {
    const double w = 2 * h * i / 400000.0, l = std::hypot(a, h - w);
    closed = std::max(closed, 2 * EA * (l0 - l) / l0 * (h - w) / l);
  }
  const Outcome o = analyze("von_mises", m);
  expect_critical("von Mises truss limit", o.lambda, closed, "limit point", o);
}

// A portal frame (columns and beam of length L, equal EI, hinged feet, rigid knees) with a load
// P on each column's axis: the fundamental path is pure compression and the frame bifurcates
// into sway. Each column is a pinned-foot column whose top may sway and is restrained by the
// beam bent in double curvature (6EI/L): u = L√(P/EI) solves u tan u = 6, P L²/EI = 1.821
// (effective length 2.33 L; Timoshenko & Gere §2.6 give the same equation).
TEST(FrameBenchmarks, PortalFrameSwayBifurcation) {
  double lo = 1e-9, hi = kPi / 2 - 1e-12;  // u tan u grows from 0 to ∞ here
  for (int k = 0; k < 200; ++k) {
    const double u = 0.5 * (lo + hi);
    (u * std::tan(u) < 6 ? lo : hi) = u;
  }
  const double closed = lo * lo;
  const double L = 120, E = 720, I = 2;
  json m = planar_model({{0, 0}, {0, L}, {L, L}, {L, 0}}, E, 6, I);
  m["members"] = {{{"nodes", {0, 1}}, {"elements", 10}},
                  {{"nodes", {1, 2}}, {"elements", 10}},
                  {{"nodes", {2, 3}}, {"elements", 10}}};
  m["supports"] = {support(0, false), support(3, false)};
  m["loads"] = {{{"node", 1}, {"force", {0, 0, -1}}}, {{"node", 2}, {"force", {0, 0, -1}}}};
  const Outcome o = analyze("portal", m);
  const double p = o.lambda * L * L / (E * I);
  expect_critical("portal frame P L^2/EI", p, closed, "bifurcation", o);
}

// The deep circular arch of DaDeppo & Schmidt (1975): radius R, opening 215°, one end clamped,
// the other hinged, a point load at the crown; limit load P R²/EI = 8.97 (Simo & Vu-Quoc 1986
// find 897 for R = 100, EI = 10⁶). Faceted into 60 straight members.
TEST(FrameBenchmarks, DeepArchLimitPoint) {
  const double R = 100, E = 1e6, I = 1, half = 107.5 * kPi / 180;
  const int n = 60;
  std::vector<std::array<double, 2>> xz;
  for (int k = 0; k <= n; ++k) {
    const double phi = -half + 2 * half * k / n;
    xz.push_back({R * std::sin(phi), R * std::cos(phi)});
  }
  json m = planar_model(xz, E, 10, I);  // R / r = 316: slender, nearly inextensible
  for (int k = 0; k < n; ++k) m["members"].push_back({{"nodes", {k, k + 1}}});
  m["supports"] = {support(0, false), support(n, true)};
  m["loads"] = {{{"node", n / 2}, {"force", {0, 0, -1}}}};
  const Outcome o = analyze("deep_arch", m);
  const double p = o.lambda * R * R / (E * I);
  expect_critical("deep arch P R^2/EI", p, 8.97, "limit point", o);
}
