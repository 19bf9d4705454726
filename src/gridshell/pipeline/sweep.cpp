#include "gridshell/pipeline/sweep.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"

namespace gridshell {

std::vector<double> parse_range(const std::string& text, const std::string& option) {
  std::vector<double> parts;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ':')) {
    try {
      std::size_t used = 0;
      parts.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw Error(option, fmt::format("'{}' is not a range a:b[:step]", text));
    }
  }
  if (parts.empty() || parts.size() > 3)
    throw Error(option, fmt::format("'{}' is not a range a:b[:step]", text));
  for (double p : parts)
    if (!std::isfinite(p)) throw Error(option, "range values must be finite");
  if (parts.size() == 1) return parts;
  const double step = parts.size() == 3 ? parts[2] : 1.0;
  if (!(step > 0) || parts[1] < parts[0])
    throw Error(option, fmt::format("'{}' must run upwards with a positive step", text));
  std::vector<double> out;
  for (int k = 0;; ++k) {
    const double v = parts[0] + k * step;
    if (v > parts[1] + 1e-9 * step) break;
    out.push_back(v);
    if (out.size() > 1000) throw Error(option, "range has more than 1000 values");
  }
  return out;
}

std::vector<SweepCase> sweep_cases(const std::vector<double>& D, const std::vector<double>& A,
                                   int repeats, std::uint64_t base_seed) {
  if (repeats < 1) throw Error("--repeats", "must be at least 1");
  std::vector<SweepCase> out;
  for (double d : D)
    for (double a : A)
      for (int r = 0; r < repeats; ++r) {
        SweepCase c;
        c.index = static_cast<int>(out.size());
        c.D = d, c.A = a, c.repeat = r;
        // splitmix64 of (base, D, A, repeat): independent of how the cases are split.
        std::uint64_t z = base_seed ^ (static_cast<std::uint64_t>(std::llround(d * 1000)) << 40) ^
                          (static_cast<std::uint64_t>(std::llround(a * 1000)) << 20) ^
                          static_cast<std::uint64_t>(r);
        z += 0x9e3779b97f4a7c15ULL;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        c.seed = (z ^ (z >> 31)) & 0x7fffffffULL;
        out.push_back(c);
      }
  return out;
}

std::vector<SweepCase> shard_cases(const std::vector<SweepCase>& cases, const std::string& shard) {
  int k = 0, n = 0;
  char slash = 0;
  std::istringstream ss(shard);
  if (!(ss >> k >> slash >> n) || slash != '/' || !ss.eof() || n < 1 || k < 1 || k > n)
    throw Error("--shard", fmt::format("'{}' is not K/N with 1 ≤ K ≤ N", shard));
  std::vector<SweepCase> out;
  for (const auto& c : cases)
    if (c.index % n == k - 1) out.push_back(c);
  return out;
}

std::vector<SweepRow> run_sweep(const std::vector<SweepCase>& cases,
                                const std::function<SweepRow(const SweepCase&)>& run_case,
                                bool parallel) {
  std::vector<SweepRow> rows(cases.size());
  if (parallel) {
    tbb::parallel_for(std::size_t(0), cases.size(),
                      [&](std::size_t i) { rows[i] = run_case(cases[i]); });
  } else {
    for (std::size_t i = 0; i < cases.size(); ++i) rows[i] = run_case(cases[i]);
  }
  return rows;
}

namespace {
/// The governing block's keys of each figure: its combination, value and verdict.
struct FigureKeys {
  const char* name;
  const char* value;
  const char* pass;
};
constexpr FigureKeys kUtilisation{"utilisation", "utilisation_value", "utilisation_pass"};
constexpr FigureKeys kLambda{"lambda", "lambda_value", "lambda_pass"};
constexpr FigureKeys kDelta{"delta", "delta_m", "delta_pass"};

SweepGoverning::Figure read_figure(const nlohmann::json& g, const FigureKeys& k) {
  SweepGoverning::Figure f;
  if (!g.contains(k.name)) return f;
  const std::string name = g.at(k.name).get<std::string>();
  if (name.size() >= SweepGoverning::kNameSize)
    throw Error("--load-case", fmt::format("combination name '{}' is longer than {} characters",
                                           name, SweepGoverning::kNameSize - 1));
  std::memcpy(f.combination, name.c_str(), name.size() + 1);
  f.known = true;
  f.value = g.at(k.value).get<double>();
  f.judged = g.contains(k.pass);
  if (f.judged) f.pass = g.at(k.pass).get<bool>();
  return f;
}

void write_figure(nlohmann::json& g, const SweepGoverning::Figure& f, const FigureKeys& k) {
  if (!f.known) return;
  g[k.name] = std::string(f.combination);
  g[k.value] = f.value;
  if (f.judged) g[k.pass] = f.pass;
}

/// A CSV cell: the number, or empty when it was not computed.
std::string cell(const SweepGoverning::Figure& f) {
  return f.known ? io::format_number(f.value) : std::string();
}
}  // namespace

SweepGoverning sweep_governing(const nlohmann::json& governing) {
  SweepGoverning g;
  g.judged = true;
  g.utilisation = read_figure(governing, kUtilisation);
  g.lambda = read_figure(governing, kLambda);
  g.delta = read_figure(governing, kDelta);
  g.pass = governing.at("pass").get<bool>();
  return g;
}

nlohmann::json governing_json(const SweepGoverning& g) {
  nlohmann::json j = nlohmann::json::object();
  write_figure(j, g.utilisation, kUtilisation);
  write_figure(j, g.lambda, kLambda);
  write_figure(j, g.delta, kDelta);
  j["pass"] = g.pass;
  return j;
}

std::string sweep_csv(const std::vector<SweepRow>& rows) {
  const bool judged = std::any_of(rows.begin(), rows.end(),
                                  [](const SweepRow& r) { return r.governing.judged; });
  std::string s = "D,A,repeat,seed,cells,total_length,lambda,delta";
  if (judged)
    s += ",governing_utilisation,governing_lambda,governing_delta,pass,"
         "governing_utilisation_combination,governing_lambda_combination,"
         "governing_delta_combination";
  s += "\n";
  for (const auto& r : rows) {
    s +=
        fmt::format("{},{},{},{},{},{},{},{}", io::format_number(r.c.D), io::format_number(r.c.A),
                    r.c.repeat, r.c.seed, r.cells, io::format_number(r.total_length),
                    io::format_number(r.lambda), io::format_number(r.delta));
    const SweepGoverning& g = r.governing;
    if (judged)
      s += fmt::format(",{},{},{},{},{},{},{}", cell(g.utilisation), cell(g.lambda),
                       cell(g.delta), g.pass ? "true" : "false", g.utilisation.combination,
                       g.lambda.combination, g.delta.combination);
    s += "\n";
  }
  return s;
}

nlohmann::json sweep_points_json(const std::vector<SweepRow>& rows) {
  nlohmann::json points = nlohmann::json::array();
  for (const auto& r : rows) {
    nlohmann::json p;
    p["D"] = r.c.D;
    p["A"] = r.c.A;
    p["repeat"] = r.c.repeat;
    p["seed"] = r.c.seed;
    p["cells"] = r.cells;
    p["total_length_m"] = r.total_length;
    p["lambda"] = r.lambda;
    p["delta_m"] = r.delta;
    if (r.governing.judged) p["governing"] = governing_json(r.governing);
    points.push_back(std::move(p));
  }
  return points;
}

SweepGrid sweep_grid(const std::vector<SweepRow>& rows,
                     const std::function<double(const SweepRow&)>& value) {
  SweepGrid g;
  for (const auto& r : rows) g.D.push_back(r.c.D), g.A.push_back(r.c.A);
  for (auto* v : {&g.D, &g.A}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
  const auto at = [](const std::vector<double>& v, double x) {
    return static_cast<int>(std::lower_bound(v.begin(), v.end(), x) - v.begin());
  };
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(g.A.size(), g.D.size());
  g.count = Eigen::MatrixXi::Zero(g.A.size(), g.D.size());
  for (const auto& r : rows) {
    const int j = at(g.A, r.c.A), i = at(g.D, r.c.D);
    sum(j, i) += value(r);
    g.count(j, i) += 1;
  }
  g.mean = sum.array() / g.count.cast<double>().array();
  for (int j = 0; j < g.mean.rows(); ++j)
    for (int i = 0; i < g.mean.cols(); ++i)
      if (g.count(j, i) == 0) g.mean(j, i) = std::numeric_limits<double>::quiet_NaN();
  return g;
}

std::string sweep_heatmap_svg(const std::vector<SweepRow>& rows, const std::string& title,
                              const std::function<double(const SweepRow&)>& value) {
  const SweepGrid grid = sweep_grid(rows, value);
  const std::vector<double>& Ds = grid.D;
  const std::vector<double>& As = grid.A;
  double lo = 1e300, hi = -1e300;
  for (int j = 0; j < grid.mean.rows(); ++j)
    for (int i = 0; i < grid.mean.cols(); ++i)
      if (grid.count(j, i) > 0)
        lo = std::min(lo, grid.mean(j, i)), hi = std::max(hi, grid.mean(j, i));
  const int cell = 70, left = 60, top = 50;
  const int w = left + cell * static_cast<int>(Ds.size()) + 20;
  const int h = top + cell * static_cast<int>(As.size()) + 50;
  std::string s = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" "
      "font-family=\"sans-serif\" font-size=\"12\">\n<text x=\"{}\" y=\"25\" "
      "font-size=\"15\">{}</text>\n",
      w, h, left, title);
  for (std::size_t i = 0; i < Ds.size(); ++i)
    for (std::size_t j = 0; j < As.size(); ++j) {
      if (grid.count(static_cast<int>(j), static_cast<int>(i)) == 0) continue;
      const double m = grid.mean(static_cast<int>(j), static_cast<int>(i));
      const double t = hi > lo ? (m - lo) / (hi - lo) : 0.5;
      // Blue (low) to yellow (high).
      const int r = static_cast<int>(40 + 215 * t), g = static_cast<int>(60 + 160 * t),
                b = static_cast<int>(160 - 120 * t);
      const int x = left + cell * static_cast<int>(i);
      const int y = top + cell * static_cast<int>(As.size() - 1 - j);
      s += fmt::format(
          "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"rgb({},{},{})\"/>\n", x, y,
          cell, cell, r, g, b);
      s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{:.3g}</text>\n",
                       x + cell / 2, y + cell / 2 + 4, m);
    }
  for (std::size_t i = 0; i < Ds.size(); ++i)
    s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">D={:g}</text>\n",
                     left + cell * static_cast<int>(i) + cell / 2,
                     top + cell * static_cast<int>(As.size()) + 18, Ds[i]);
  for (std::size_t j = 0; j < As.size(); ++j)
    s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"end\">A={:g}</text>\n", left - 6,
                     top + cell * static_cast<int>(As.size() - 1 - j) + cell / 2 + 4, As[j]);
  s += "</svg>\n";
  return s;
}

}  // namespace gridshell
