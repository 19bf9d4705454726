#include "gridshell/surfaces/builtin.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <numbers>
#include <sstream>

#include <fmt/format.h>

#include "gridshell/core/error.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/surfaces/force_density.h"

namespace gridshell {

namespace {

constexpr double kPi = std::numbers::pi;

/// A structured (nx+1)×(ny+1) grid, mapped by `map(i, j)`, triangulated with diagonals that
/// point to the grid centre ("union jack"), so the mesh is symmetric about both mid-lines.
TriMesh make_grid(int nx, int ny, const std::function<Vec3(int, int)>& map) {
  TriMesh m;
  m.V.resize((nx + 1) * (ny + 1), 3);
  auto id = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.V.row(id(i, j)) = map(i, j).transpose();
  m.F.resize(2 * nx * ny, 3);
  int f = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      const bool left = 2 * i + 1 < nx, low = 2 * j + 1 < ny;
      if (left == low) {  // diagonal a–c
        m.F.row(f++) << a, b, c;
        m.F.row(f++) << a, c, d;
      } else {  // diagonal b–d
        m.F.row(f++) << a, b, d;
        m.F.row(f++) << b, c, d;
      }
    }
  return m;
}

/// The boundary vertices of make_grid(nx, ny, …) in increasing order: the rim of the grid (what
/// boundary_vertices(build_topology(mesh)) finds, without the topology of up to 2 M triangles).
std::vector<int> grid_boundary(int nx, int ny) {
  std::vector<int> out;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      if (i == 0 || i == nx || j == 0 || j == ny) out.push_back(j * (nx + 1) + i);
  return out;
}

double or_default(double v, double d) {
  return v > 0 ? v : d;
}

void require(bool ok, const std::string& what) {
  if (!ok) throw Error("builtin", what);
}

/// Refuses a mesh of more than kMaxBuiltinVertices vertices before anything is allocated
/// (`count` in double: the product of two sizes cannot wrap).
void require_vertices(const char* name, double count) {
  if (!(count <= static_cast<double>(kMaxBuiltinVertices)))
    throw Error("builtin",
                fmt::format("{}: these parameters make {:.0f} vertices, more than the {} a built-in "
                            "may make (lower res, or the ratio of length or width to span)",
                            name, count, kMaxBuiltinVertices));
}

Surface paraboloid(const BuiltinOptions& o) {
  const double span = or_default(o.span, 20), rise = or_default(o.rise, 4);
  const int n = o.res > 0 ? o.res : 32;
  require(n >= 2 && n % 2 == 0, "paraboloid: res must be even and ≥ 2");
  require_vertices("paraboloid", (n + 1.0) * (n + 1.0));
  const double h = span / 2;
  Surface s;
  s.mesh = make_grid(n, n, [&](int i, int j) {
    const double x = -h + span * i / n, y = -h + span * j / n;
    return Vec3(x, y, rise * (1 - (x * x + y * y) / (2 * h * h)));
  });
  s.supports = grid_boundary(n, n);
  return s;
}

Surface dome(const BuiltinOptions& o) {
  const double span = or_default(o.span, 20), rise = or_default(o.rise, 5);
  const int n = o.res > 0 ? o.res / 2 : 16;  // rings
  require(n >= 1, "dome: res must be ≥ 2");
  require_vertices("dome", 1.0 + 3.0 * n * (n + 1.0));
  const double a = span / 2;
  require(rise <= a,
          "dome: rise must not exceed half the span (a cap, not more than a hemisphere)");
  const double R = (a * a + rise * rise) / (2 * rise);
  TriMesh m;
  std::vector<Vec3> pts{Vec3(0, 0, rise)};
  std::vector<std::array<int, 3>> tris;
  auto ring_start = [](int k) { return k == 0 ? 0 : 1 + 3 * k * (k - 1); };
  for (int k = 1; k <= n; ++k)
    for (int i = 0; i < 6 * k; ++i) {
      const double r = a * k / n, th = 2 * kPi * i / (6 * k);
      pts.emplace_back(r * std::cos(th), r * std::sin(th), std::sqrt(R * R - r * r) - (R - rise));
    }
  // Hexagonal disk triangulation: ring k-1 (6(k-1) vertices) to ring k (6k vertices).
  for (int k = 1; k <= n; ++k) {
    const int inner = ring_start(k - 1), outer = ring_start(k);
    const int ni = std::max(1, 6 * (k - 1)), no = 6 * k;
    for (int side = 0; side < 6; ++side)
      for (int j = 0; j < k; ++j) {
        const int o0 = side * k + j, o1 = (o0 + 1) % no;
        const int i0 = k == 1 ? 0 : (side * (k - 1) + j) % ni;
        tris.push_back({inner + i0, outer + o0, outer + o1});
        if (j < k - 1) {
          const int i1 = (side * (k - 1) + j + 1) % ni;
          tris.push_back({inner + i0, outer + o1, inner + i1});
        }
      }
  }
  m.V = to_points(pts);
  m.F.resize(static_cast<int>(tris.size()), 3);
  for (std::size_t i = 0; i < tris.size(); ++i)
    m.F.row(static_cast<int>(i)) << tris[i][0], tris[i][1], tris[i][2];
  Surface s;
  s.mesh = std::move(m);
  s.supports = boundary_vertices(build_topology(s.mesh));
  return s;
}

Surface barrel(const BuiltinOptions& o) {
  const double span = or_default(o.span, 12), rise = or_default(o.rise, 4);
  const double length = or_default(o.length, 20);
  const int n = o.res > 0 ? o.res : 24;
  require(n >= 2 && n % 2 == 0, "barrel: res must be even and ≥ 2");
  require(rise <= span / 2, "barrel: rise must not exceed half the span");
  const double c = span / 2, R = (c * c + rise * rise) / (2 * rise);
  const double half_angle = std::asin(c / R);
  const double rows = std::max(2.0, 2 * std::round(n * length / span / 2));
  require_vertices("barrel", (n + 1.0) * (rows + 1));
  const int nl = static_cast<int>(rows);
  Surface s;
  s.mesh = make_grid(n, nl, [&](int i, int j) {
    const double th = -half_angle + 2 * half_angle * i / n;
    return Vec3(R * std::sin(th), -length / 2 + length * j / nl, R * std::cos(th) - (R - rise));
  });
  for (int j = 0; j <= nl; ++j) {
    s.supports.push_back(j * (n + 1));
    s.supports.push_back(j * (n + 1) + n);
  }
  std::sort(s.supports.begin(), s.supports.end());
  return s;
}

Surface court(const BuiltinOptions& o) {
  const double span = or_default(o.span, 30), width = or_default(o.width, 0.7 * span);
  const double rise = or_default(o.rise, 3), hole = or_default(o.hole, 0.22 * width);
  const int n = o.res > 0 ? o.res : 48;  // samples along the long side
  require(hole < 0.5 * std::min(span, width), "court: hole must fit inside the rectangle");
  require(n >= 4 && n % 2 == 0, "court: res must be even and ≥ 4");
  // Perimeter samples, corners included, walking counter-clockwise from (+span/2, 0).
  const double hx = span / 2, hy = width / 2;
  const double rows = std::max(2.0, 2 * std::round(n * width / span / 2));
  require_vertices("court", 2.0 * (n + rows));  // perimeter samples, before the layers
  const int nx = n, ny = static_cast<int>(rows);
  std::vector<Eigen::Vector2d> per;
  for (int j = 0; j < ny / 2; ++j) per.emplace_back(hx, width * j / ny);
  for (int i = 0; i < nx; ++i) per.emplace_back(hx - span * i / nx, hy);
  for (int j = 0; j < ny; ++j) per.emplace_back(-hx, hy - width * j / ny);
  for (int i = 0; i < nx; ++i) per.emplace_back(-hx + span * i / nx, -hy);
  for (int j = 0; j < ny / 2; ++j) per.emplace_back(hx, -hy + width * j / ny);
  const int np = static_cast<int>(per.size());
  // Radial layers: enough that triangles are not too stretched.
  const double dr = 2 * (span + width) / np;
  const double layers = std::max(2.0, std::ceil((std::min(hx, hy) - hole) / dr));
  require_vertices("court", np * (layers + 1));
  const int nr = static_cast<int>(layers);
  TriMesh m;
  m.V.resize(np * (nr + 1), 3);
  for (int k = 0; k <= nr; ++k)
    for (int i = 0; i < np; ++i) {
      const Eigen::Vector2d P = per[i], H = hole * P.normalized();
      const double t = static_cast<double>(k) / nr;
      const Eigen::Vector2d X = H + t * (P - H);
      m.V.row(k * np + i) << X.x(), X.y(), rise * 4 * t * (1 - t);
    }
  m.F.resize(2 * np * nr, 3);
  int f = 0;
  for (int k = 0; k < nr; ++k)
    for (int i = 0; i < np; ++i) {
      const int a = k * np + i, b = k * np + (i + 1) % np;
      const int c = (k + 1) * np + (i + 1) % np, d = (k + 1) * np + i;
      // Shorter diagonal; ties broken by index parity for symmetry.
      const double ac = (m.V.row(a) - m.V.row(c)).norm(), bd = (m.V.row(b) - m.V.row(d)).norm();
      // (a, b) runs counter-clockwise around the hole, so (a, d, c) faces up.
      if (ac < bd - 1e-12 || (std::abs(ac - bd) <= 1e-12 && i % 2 == 0)) {
        m.F.row(f++) << a, c, b;
        m.F.row(f++) << a, d, c;
      } else {
        m.F.row(f++) << a, d, b;
        m.F.row(f++) << b, d, c;
      }
    }
  Surface s;
  s.mesh = std::move(m);
  s.supports = boundary_vertices(build_topology(s.mesh));
  return s;
}

}  // namespace

namespace {

/// One key of the spec: where it goes and the values it may take (builtin.h's table).
struct BuiltinKey {
  const char* name;
  double low, high;
  bool integer;
  double BuiltinOptions::*real = nullptr;
  int BuiltinOptions::*whole = nullptr;
};

const std::vector<BuiltinKey>& builtin_keys() {
  static const std::vector<BuiltinKey> keys = {
      {"span", kBuiltinMinSize, kBuiltinMaxSize, false, &BuiltinOptions::span},
      {"rise", kBuiltinMinRise, kBuiltinMaxSize, false, &BuiltinOptions::rise},
      {"width", kBuiltinMinSize, kBuiltinMaxSize, false, &BuiltinOptions::width},
      {"length", kBuiltinMinSize, kBuiltinMaxSize, false, &BuiltinOptions::length},
      {"hole", kBuiltinMinHole, kBuiltinMaxSize / 2, false, &BuiltinOptions::hole},
      {"edge_q", 0.01, 100, false, &BuiltinOptions::edge_q},
      {"res", 2, kBuiltinMaxRes, true, nullptr, &BuiltinOptions::res},
      {"corner", 0, kBuiltinMaxRes, true, nullptr, &BuiltinOptions::corner},
  };
  return keys;
}

std::string bounds_message(const BuiltinKey& key, const std::string& value) {
  return fmt::format("{} must be {} in [{}, {}], got {}", key.name,
                     key.integer ? "a whole number" : "a positive number", key.low, key.high,
                     value);
}

/// A key's value: a whole number in digits for an integer key, else a finite decimal number;
/// within the key's bounds.
double parse_builtin_value(const std::string& spec, const BuiltinKey& key,
                           const std::string& value) {
  double x = 0;
  if (key.integer) {
    long long n = 0;
    const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), n);
    if (value.empty() || ec != std::errc{} || end != value.data() + value.size())
      throw Error("builtin:" + spec,
                  fmt::format("{} must be a whole number, got '{}'", key.name, value));
    x = static_cast<double>(n);
  } else {
    std::size_t used = 0;
    try {
      x = std::stod(value, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    // stod also reads hexadecimal, "inf" and "nan": only plain decimal numbers are taken.
    const bool plain = value.find_first_not_of("0123456789.eE+-") == std::string::npos;
    if (value.empty() || used != value.size() || !plain || !std::isfinite(x))
      throw Error("builtin:" + spec, fmt::format("'{}' is not a number", value));
  }
  if (!(x >= key.low && x <= key.high))
    throw Error("builtin:" + spec, bounds_message(key, value));
  return x;
}

/// Refuses options outside builtin.h's bounds (0 and corner −1 mean the default).
void check_builtin_options(const BuiltinOptions& o) {
  for (const BuiltinKey& key : builtin_keys()) {
    const double x = key.integer ? o.*(key.whole) : o.*(key.real);
    const double unset = key.whole == &BuiltinOptions::corner ? -1 : 0;
    if (x != unset && !(x >= key.low && x <= key.high))
      throw Error("builtin", bounds_message(key, fmt::format("{}", x)));
  }
}

}  // namespace

FunicularResult make_funicular(const BuiltinOptions& o) {
  check_builtin_options(o);
  const double span = or_default(o.span, 20), rise = or_default(o.rise, 5);
  const int n = o.res > 0 ? o.res : 32;
  const double edge_q = or_default(o.edge_q, 4.0);
  const int corner = o.corner >= 0 ? o.corner : std::max(1, n / 16);
  require(n >= 4 && n % 2 == 0, "funicular: res must be even and ≥ 4");
  require(2 * corner < n, "funicular: corner supports would cover a whole edge");
  require_vertices("funicular", (n + 1.0) * (n + 1.0));
  const double h = span / 2;
  TriMesh grid =
      make_grid(n, n, [&](int i, int j) { return Vec3(-h + span * i / n, -h + span * j / n, 0); });
  Topology topo = build_topology(grid);
  ForceDensityProblem pb;
  pb.X = grid.V;
  pb.edges = topo.edges;
  pb.fixed.assign(grid.num_vertices(), 0);
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  std::vector<int> supports;
  for (int ci : {0, n})
    for (int cj : {0, n})
      for (int k = 0; k <= corner; ++k) {
        const int di = ci == 0 ? k : -k, dj = cj == 0 ? k : -k;
        supports.push_back(id(ci + di, cj));
        supports.push_back(id(ci, cj + dj));
      }
  std::sort(supports.begin(), supports.end());
  supports.erase(std::unique(supports.begin(), supports.end()), supports.end());
  for (int v : supports) pb.fixed[v] = 1;
  pb.q.resize(pb.edges.size());
  for (std::size_t e = 0; e < pb.edges.size(); ++e)
    pb.q[e] = topo.edge_faces[e].size() == 1 ? edge_q : 1.0;
  // Upward load proportional to each node's tributary plan area: the inverted hanging net.
  pb.loads = Points::Zero(grid.num_vertices(), 3);
  for (int f = 0; f < grid.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) pb.loads(grid.F(f, c), 2) += span * span / (2.0 * n * n) / 3;
  ForceDensityResult r = solve_force_density(pb);
  // z is linear in the load: scale loads so the crown reaches `rise`; re-solve for exactness.
  const double zmax = r.X.col(2).maxCoeff();
  require(zmax > 0, "funicular: form finding failed");
  pb.loads *= rise / zmax;
  r = solve_force_density(pb);
  FunicularResult out;
  out.surface.mesh.V = r.X;
  out.surface.mesh.F = grid.F;
  out.surface.supports = supports;
  out.residual = r.residual;
  return out;
}

std::vector<std::string> builtin_names() {
  return {"funicular", "paraboloid", "dome", "barrel", "court"};
}

Surface make_builtin(const std::string& name, const BuiltinOptions& o) {
  check_builtin_options(o);
  if (name == "paraboloid") return paraboloid(o);
  if (name == "dome") return dome(o);
  if (name == "barrel") return barrel(o);
  if (name == "court") return court(o);
  if (name == "funicular") return make_funicular(o).surface;
  throw Error("builtin:" + name,
              "unknown built-in surface (choose funicular, paraboloid, dome, barrel, court)");
}

namespace {

/// A spec's name and its keys' values (the last of a repeated key), checked against the bounds.
struct ParsedSpec {
  std::string name;
  std::map<std::string, double> values;
};

ParsedSpec parse_spec(const std::string& spec) {
  const auto colon = spec.find(':');
  ParsedSpec p;
  p.name = spec.substr(0, colon);
  if (colon == std::string::npos) return p;
  std::stringstream ss(spec.substr(colon + 1));
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto eq = item.find('=');
    if (eq == std::string::npos)
      throw Error("builtin:" + spec, fmt::format("expected key=value, got '{}'", item));
    const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
    const auto& keys = builtin_keys();
    const auto it = std::find_if(keys.begin(), keys.end(),
                                 [&key](const BuiltinKey& k) { return key == k.name; });
    if (it == keys.end())
      throw Error("builtin:" + spec, fmt::format("unknown key '{}' (span, rise, res, width, "
                                                 "length, hole, edge_q, corner)",
                                                 key));
    p.values[key] = parse_builtin_value(spec, *it, value);
  }
  return p;
}

void require_known_name(const std::string& name) {
  const auto names = builtin_names();
  if (std::find(names.begin(), names.end(), name) == names.end())
    throw Error("builtin:" + name,
                "unknown built-in surface (choose funicular, paraboloid, dome, barrel, court)");
}

}  // namespace

Surface make_builtin(const std::string& spec) {
  const ParsedSpec p = parse_spec(spec);
  BuiltinOptions o;
  for (const BuiltinKey& key : builtin_keys()) {
    const auto it = p.values.find(key.name);
    if (it == p.values.end()) continue;
    if (key.integer)
      o.*(key.whole) = static_cast<int>(it->second);
    else
      o.*(key.real) = it->second;
  }
  return make_builtin(p.name, o);
}

std::string canonical_builtin(const std::string& spec) {
  const ParsedSpec p = parse_spec(spec);
  require_known_name(p.name);
  std::string text = p.name;
  char sep = ':';
  for (const auto& [key, value] : p.values) {  // sorted by key
    text += fmt::format("{}{}={}", sep, key, value);
    sep = ',';
  }
  return text;
}

}  // namespace gridshell
