// The VTK XML PolyData writers of mesh_io.h (write_vtp, write_vtp_lines,
// write_vtp_beams_and_panels): text arrays formatted in blocks on all threads, or a triangle
// mesh's arrays as VTK's appended raw data.

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"
#include "gridshell/io/mesh_io.h"

namespace gridshell::io {

namespace fs = std::filesystem;

namespace {

// Appends format_number(x) and `sep` to s without a temporary string (field.vtp of a 250 K
// triangle input holds millions of numbers).
void append_number(std::string& s, double x, char sep) {
  if (!std::isfinite(x)) throw Error("", "internal: refusing to write a non-finite number");
  fmt::format_to(std::back_inserter(s), "{}{}", x, sep);
}

/// Appends rows 0 … rows−1, each formatted by `row(s, i)`, to `out`: blocks of rows are
/// formatted on all threads and written in order (the same bytes as one thread), a batch of
/// blocks at a time (a few MB of text in memory, whatever the file's size).
template <class Row>
void append_rows(AtomicFileWriter& out, Eigen::Index rows, const Row& row) {
  constexpr Eigen::Index kBlock = 4096, kBlocks = 16;
  std::vector<std::string> parts(kBlocks);
  for (Eigen::Index first = 0; first < rows; first += kBlock * kBlocks) {
    const Eigen::Index end = std::min(rows, first + kBlock * kBlocks);
    const auto blocks = static_cast<int>((end - first + kBlock - 1) / kBlock);
    tbb::parallel_for(0, blocks, [&](int b) {
      std::string& s = parts[b];
      s.clear();
      const Eigen::Index from = first + b * kBlock, to = std::min(end, from + kBlock);
      for (Eigen::Index i = from; i < to; ++i) row(s, i);
    });
    for (int b = 0; b < blocks; ++b) out.append(parts[b]);
  }
}

void check_rows(const Attributes& attrs, Eigen::Index rows) {
  for (const auto& [name, values] : attrs)
    if (values.rows() != rows)
      throw Error(name,
                  fmt::format("internal: attribute has {} rows, expected {}", values.rows(), rows));
}

void append_data_arrays(AtomicFileWriter& out, const Attributes& attrs, Eigen::Index rows) {
  check_rows(attrs, rows);
  for (const auto& [name, values] : attrs) {
    out.append(fmt::format(
        "<DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">\n",
        name, values.cols()));
    const Eigen::MatrixXd& m = values;
    append_rows(out, m.rows(), [&m](std::string& s, Eigen::Index i) {
      for (Eigen::Index c = 0; c < m.cols(); ++c) append_number(s, m(i, c), ' ');
      s += '\n';
    });
    out.append("</DataArray>\n");
  }
}

void append_points(AtomicFileWriter& out, const Points& V) {
  out.append("<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
  append_rows(out, V.rows(), [&V](std::string& s, Eigen::Index v) {
    for (int c = 0; c < 3; ++c) append_number(s, V(v, c), c < 2 ? ' ' : '\n');
  });
  out.append("</DataArray>\n</Points>\n");
}

/// The polygons of a piece: how many, each one's vertex count, and its connectivity row.
struct Polys {
  Eigen::Index count = 0;
  std::function<std::size_t(Eigen::Index)> size;
  std::function<void(std::string&, Eigen::Index)> row;  ///< "v0 v1 … \n"
};

Polys polys_of(const std::vector<std::vector<int>>& faces) {
  return {static_cast<Eigen::Index>(faces.size()),
          [&faces](Eigen::Index i) { return faces[i].size(); },
          [&faces](std::string& s, Eigen::Index i) {
            for (int v : faces[i]) fmt::format_to(std::back_inserter(s), "{} ", v);
            s += '\n';
          }};
}

/// VTK XML PolyData with any of line segments and polygons (VTK orders cells lines first).
void write_polydata(const fs::path& path, const Points& V,
                    const std::vector<std::array<int, 2>>& lines, const Polys& polys,
                    const Attributes& point_data, const Attributes& cell_data) {
  const auto cells = static_cast<Eigen::Index>(lines.size()) + polys.count;
  check_rows(point_data, V.rows());
  check_rows(cell_data, cells);
  AtomicFileWriter out(path);
  std::string& s = out.buffer();
  s += "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" "
       "byte_order=\"LittleEndian\">\n<PolyData>\n";
  s += fmt::format("<Piece NumberOfPoints=\"{}\"", V.rows());
  if (!lines.empty()) s += fmt::format(" NumberOfLines=\"{}\"", lines.size());
  if (polys.count > 0 || lines.empty()) s += fmt::format(" NumberOfPolys=\"{}\"", polys.count);
  s += ">\n";
  append_points(out, V);
  if (!lines.empty()) {
    out.append("<Lines>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    append_rows(out, static_cast<Eigen::Index>(lines.size()), [&lines](std::string& t, Eigen::Index i) {
      fmt::format_to(std::back_inserter(t), "{} {}\n", lines[i][0], lines[i][1]);
    });
    out.append("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    append_rows(out, static_cast<Eigen::Index>(lines.size()), [](std::string& t, Eigen::Index i) {
      fmt::format_to(std::back_inserter(t), "{}\n", 2 * (static_cast<std::size_t>(i) + 1));
    });
    out.append("</DataArray>\n</Lines>\n");
  }
  if (polys.count > 0 || lines.empty()) {
    out.append("<Polys>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    append_rows(out, polys.count, polys.row);
    out.append("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    std::vector<std::size_t> offset(polys.count);
    std::size_t sum = 0;
    for (Eigen::Index i = 0; i < polys.count; ++i) offset[i] = sum += polys.size(i);
    append_rows(out, polys.count, [&offset](std::string& t, Eigen::Index i) {
      fmt::format_to(std::back_inserter(t), "{}\n", offset[i]);
    });
    out.append("</DataArray>\n</Polys>\n");
  }
  out.append("<PointData>\n");
  append_data_arrays(out, point_data, V.rows());
  out.append("</PointData>\n<CellData>\n");
  append_data_arrays(out, cell_data, cells);
  out.append("</CellData>\n</Piece>\n</PolyData>\n</VTKFile>\n");
  out.commit();
}

/// One array of the appended data block: its DataArray element (with the array's offset in
/// the block) and a writer of its bytes (length, then values).
struct AppendedArray {
  std::string element;
  std::uint64_t bytes = 0;
  std::function<void(AtomicFileWriter&)> write;
};

/// Appends the little-endian bytes of n values of type T, value(i) each, in blocks.
static_assert(
    std::endian::native == std::endian::little,
    "the binary VTP writer copies values as they are in memory (byte_order=LittleEndian)");
template <class T, class Value>
void append_values(AtomicFileWriter& out, Eigen::Index n, const Value& value) {
  constexpr Eigen::Index kBlock = 1 << 16;
  std::string& s = out.buffer();
  for (Eigen::Index first = 0; first < n; first += kBlock) {
    const Eigen::Index end = std::min(n, first + kBlock);
    const std::size_t at = s.size();
    s.resize(at + static_cast<std::size_t>(end - first) * sizeof(T));
    char* p = s.data() + at;
    for (Eigen::Index i = first; i < end; ++i, p += sizeof(T)) {
      const T v = value(i);
      std::memcpy(p, &v, sizeof(T));
    }
    out.flush_if_large();
  }
}

/// `m`: any dense matrix (the mesh's row-major points or a column-major attribute), read in
/// place; it must outlive the array's `write`.
template <class Matrix>
AppendedArray float_array(const std::string& attributes, const Matrix& m) {
  if (!m.allFinite()) throw Error("", "internal: refusing to write a non-finite number");
  AppendedArray a;
  a.element = fmt::format(
      "<DataArray type=\"Float64\"{} NumberOfComponents=\"{}\" "
      "format=\"appended\" offset=\"{{}}\"/>\n",
      attributes, m.cols());
  a.bytes = static_cast<std::uint64_t>(m.size()) * sizeof(double);
  a.write = [&m](AtomicFileWriter& out) {  // row by row, as the ascii rows
    const Eigen::Index cols = m.cols();
    append_values<double>(out, m.size(),
                          [&m, cols](Eigen::Index i) { return m(i / cols, i % cols); });
  };
  return a;
}

/// VTK XML PolyData of a triangle mesh with its arrays in the appended raw data block.
void write_binary_vtp(const fs::path& path, const TriMesh& mesh, const Attributes& point_data,
                      const Attributes& cell_data) {
  check_rows(point_data, mesh.num_vertices());
  check_rows(cell_data, mesh.num_faces());
  std::vector<AppendedArray> arrays;
  std::string xml;
  std::uint64_t offset = 0;  // of the next array in the appended block
  const auto add = [&](AppendedArray a) {
    xml += fmt::format(fmt::runtime(a.element), offset);
    offset += sizeof(std::uint64_t) + a.bytes;
    arrays.push_back(std::move(a));
  };
  const Triangles& F = mesh.F;
  const Eigen::Index nf = F.rows();
  xml += fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfPolys=\"{}\">\n<Points>\n",
                     mesh.num_vertices(), nf);
  add(float_array("", mesh.V));
  xml += "</Points>\n<Polys>\n";
  add({"<DataArray type=\"Int64\" Name=\"connectivity\" format=\"appended\" offset=\"{}\"/>\n",
       static_cast<std::uint64_t>(3 * nf) * sizeof(std::int64_t), [&F, nf](AtomicFileWriter& out) {
         append_values<std::int64_t>(
             out, 3 * nf, [&F](Eigen::Index i) { return std::int64_t{F(i / 3, i % 3)}; });
       }});
  add({"<DataArray type=\"Int64\" Name=\"offsets\" format=\"appended\" offset=\"{}\"/>\n",
       static_cast<std::uint64_t>(nf) * sizeof(std::int64_t), [nf](AtomicFileWriter& out) {
         append_values<std::int64_t>(out, nf,
                                     [](Eigen::Index i) { return std::int64_t{3 * (i + 1)}; });
       }});
  xml += "</Polys>\n<PointData>\n";
  for (const auto& [name, values] : point_data)
    add(float_array(fmt::format(" Name=\"{}\"", name), values));
  xml += "</PointData>\n<CellData>\n";
  for (const auto& [name, values] : cell_data)
    add(float_array(fmt::format(" Name=\"{}\"", name), values));
  xml += "</CellData>\n</Piece>\n";
  AtomicFileWriter out(path);
  out.append(
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" "
      "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<PolyData>\n");
  out.append(xml);
  out.append("</PolyData>\n<AppendedData encoding=\"raw\">\n_");
  for (const AppendedArray& a : arrays) {
    append_values<std::uint64_t>(out, 1, [&a](Eigen::Index) { return a.bytes; });
    a.write(out);
  }
  out.append("\n</AppendedData>\n</VTKFile>\n");
  out.commit();
}

}  // namespace

void write_vtp(const fs::path& path, const PolyMesh& mesh, const Attributes& point_data,
               const Attributes& cell_data) {
  write_polydata(path, mesh.V, {}, polys_of(mesh.faces), point_data, cell_data);
}

void write_vtp(const fs::path& path, const TriMesh& mesh, const Attributes& point_data,
               const Attributes& cell_data, VtpEncoding encoding) {
  if (encoding == VtpEncoding::binary) return write_binary_vtp(path, mesh, point_data, cell_data);
  const Triangles& F = mesh.F;
  const Polys polys{F.rows(), [](Eigen::Index) { return std::size_t{3}; },
                    [&F](std::string& s, Eigen::Index i) {
                      fmt::format_to(std::back_inserter(s), "{} {} {} \n", F(i, 0), F(i, 1),
                                     F(i, 2));
                    }};
  write_polydata(path, mesh.V, {}, polys, point_data, cell_data);
}

void write_vtp_lines(const fs::path& path, const Points& V,
                     const std::vector<std::array<int, 2>>& lines, const Attributes& point_data,
                     const Attributes& cell_data) {
  write_polydata(path, V, lines, Polys{}, point_data, cell_data);
}

void write_vtp_beams_and_panels(const fs::path& path, const PolyMesh& mesh,
                                const std::vector<std::array<int, 2>>& lines,
                                const Attributes& point_data, const Attributes& line_data,
                                const Attributes& panel_data) {
  const auto nl = static_cast<Eigen::Index>(lines.size());
  const Eigen::Index nf = mesh.num_faces();
  Attributes cells;
  auto place = [&](const Attributes& attrs, Eigen::Index rows, Eigen::Index first) {
    check_rows(attrs, rows);
    for (const auto& [name, values] : attrs) {
      Eigen::MatrixXd& all = cells[name];
      if (all.size() == 0) all = Eigen::MatrixXd::Zero(nl + nf, values.cols());
      if (all.cols() != values.cols())
        throw Error(name, "internal: beam and panel attributes differ in components");
      all.middleRows(first, rows) = values;
    }
  };
  place(line_data, nl, 0);
  place(panel_data, nf, nl);
  Eigen::MatrixXd is_beam = Eigen::MatrixXd::Zero(nl + nf, 1);
  is_beam.topRows(nl).setOnes();
  cells["is_beam"] = is_beam;
  write_polydata(path, mesh.V, lines, polys_of(mesh.faces), point_data, cells);
}

}  // namespace gridshell::io
