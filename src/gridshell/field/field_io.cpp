#include "gridshell/field/field_io.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <string_view>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <Eigen/Eigenvalues>

#include "gridshell/core/error.h"
#include "gridshell/field/field.h"
#include "gridshell/io/files.h"
#include "gridshell/mesh/nearest.h"

namespace gridshell {

namespace {

/// Splits a line at commas, tabs and spaces into numbers; false when a token is not a number.
bool parse_numbers(std::string_view line, std::vector<double>& out) {
  out.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ',' || line[i] == ' ' || line[i] == '\t' ||
                               line[i] == '\r' || line[i] == ';'))
      ++i;
    if (i >= line.size()) break;
    std::size_t j = i;
    while (j < line.size() && line[j] != ',' && line[j] != ' ' && line[j] != '\t' &&
           line[j] != '\r' && line[j] != ';')
      ++j;
    std::string_view tok = line.substr(i, j - i);
    if (!tok.empty() && tok[0] == '+') tok.remove_prefix(1);
    double v = 0;
    auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (ec != std::errc() || p != tok.data() + tok.size()) return false;
    out.push_back(v);
    i = j;
  }
  return true;
}

std::vector<std::vector<double>> read_rows(const std::string& path, std::size_t min_columns) {
  const std::string text = io::read_file(path);
  std::vector<std::vector<double>> rows;
  std::vector<double> nums;
  std::size_t pos = 0;
  int line_no = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (line.find_first_not_of(" \t\r") == std::string_view::npos) continue;
    if (!parse_numbers(line, nums)) {
      if (rows.empty() && line_no == 1) continue;  // header line
      throw Error(path, fmt::format("line {}: not a list of numbers", line_no));
    }
    if (nums.size() < min_columns)
      throw Error(path, fmt::format("line {}: expected {} columns, found {}", line_no, min_columns,
                                    nums.size()));
    for (double v : nums)
      if (!std::isfinite(v)) throw Error(path, fmt::format("line {}: non-finite value", line_no));
    rows.push_back(nums);
  }
  if (rows.empty()) throw Error(path, "no data rows");
  return rows;
}

Eigen::Matrix3d tensor(double s1, const Vec3& d1, double s2, const Vec3& d2) {
  const Vec3 a = d1.norm() > 0 ? Vec3(d1.normalized()) : Vec3::Zero();
  const Vec3 b = d2.norm() > 0 ? Vec3(d2.normalized()) : Vec3::Zero();
  return s1 * a * a.transpose() + s2 * b * b.transpose();
}

}  // namespace

StressField principal_stress_from_vertex_tensors(const TriMesh& mesh,
                                                 const std::vector<Eigen::Matrix3d>& tensors) {
  if (static_cast<int>(tensors.size()) != mesh.num_vertices())
    throw Error("field", "one stress tensor per vertex expected");
  const FaceFrames fr = face_frames(mesh);
  StressField out(mesh.num_faces());
  std::vector<char> bad(mesh.num_faces(), 0);
  // Each face on its own (in parallel: a frame response on a 2 M-triangle input); the first
  // non-finite one, whatever the threads, is the one reported.
  tbb::parallel_for(
      tbb::blocked_range<int>(0, mesh.num_faces(), 4096),
      [&](const tbb::blocked_range<int>& range) {
        for (int f = range.begin(); f < range.end(); ++f) {
          const Eigen::Matrix3d s =
              (tensors[mesh.F(f, 0)] + tensors[mesh.F(f, 1)] + tensors[mesh.F(f, 2)]) / 3.0;
          Eigen::Matrix<double, 3, 2> T;
          T.col(0) = fr.t1[f];
          T.col(1) = fr.t2[f];
          const Eigen::Matrix2d s2 = T.transpose() * (0.5 * (s + s.transpose())) * T;
          Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(s2);  // ascending eigenvalues
          PrincipalStress p;
          p.s1 = es.eigenvalues()[1];
          p.s2 = es.eigenvalues()[0];
          p.d1 = (T * es.eigenvectors().col(1)).normalized();
          p.d2 = fr.n[f].cross(p.d1);
          bad[f] = !std::isfinite(p.s1) || !std::isfinite(p.s2) || !p.d1.allFinite();
          out[f] = p;
        }
      });
  for (int f = 0; f < mesh.num_faces(); ++f)
    if (bad[f]) throw Error("field", fmt::format("non-finite stress at face {}", f));
  return out;
}

StressField read_field_file(const std::string& path, const TriMesh& mesh) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  const int nv = mesh.num_vertices();
  std::vector<Eigen::Matrix3d> tensors(nv, Eigen::Matrix3d::Zero());
  if (ext == ".csv") {
    const auto rows = read_rows(path, 6);
    // Vertex normals (area weighted) give the second direction n × d1.
    const FaceFrames fr = face_frames(mesh);
    std::vector<Vec3> normal(nv, Vec3::Zero());
    for (int f = 0; f < mesh.num_faces(); ++f)
      for (int k = 0; k < 3; ++k) normal[mesh.F(f, k)] += fr.area[f] * fr.n[f];
    std::vector<char> seen(nv, 0);
    for (const auto& r : rows) {
      const double id = r[0];
      if (id != std::floor(id) || id < 0 || id >= nv)
        throw Error(path, fmt::format("vertex id {} out of range [0, {})", id, nv));
      const int v = static_cast<int>(id);
      const Vec3 d1(r[3], r[4], r[5]);
      if (!(d1.norm() > 0)) throw Error(path, fmt::format("zero direction at vertex {}", v));
      Vec3 n = normal[v].normalized();
      Vec3 d1t = d1 - d1.dot(n) * n;
      if (!(d1t.norm() > 1e-12 * d1.norm())) d1t = d1;  // normal direction: keep as given
      const Vec3 d2 = n.cross(d1t.normalized());
      tensors[v] = tensor(r[1], d1t, r[2], d2);
      seen[v] = 1;
    }
    const auto missing = std::count(seen.begin(), seen.end(), 0);
    if (missing > 0)
      throw Error(path, fmt::format("{} of {} vertices have no stress row", missing, nv));
  } else {
    const auto rows = read_rows(path, 11);
    Points pts(static_cast<Eigen::Index>(rows.size()), 3);
    for (std::size_t i = 0; i < rows.size(); ++i)
      pts.row(static_cast<Eigen::Index>(i)) << rows[i][0], rows[i][1], rows[i][2];
    const auto nearest = nearest_points(pts, mesh.V);
    for (int v = 0; v < nv; ++v) {
      const auto& r = rows[nearest[v].front()];
      tensors[v] = tensor(r[3], Vec3(r[4], r[5], r[6]), r[7], Vec3(r[8], r[9], r[10]));
    }
  }
  return principal_stress_from_vertex_tensors(mesh, tensors);
}

}  // namespace gridshell
