#include "gridshell/io/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>

#include <CGAL/IO/OBJ.h>
#include <CGAL/IO/PLY.h>
#include <CGAL/Simple_cartesian.h>
#include <fmt/format.h>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"

namespace gridshell::io {

namespace fs = std::filesystem;
using Kernel = CGAL::Simple_cartesian<double>;
using CgalPoint = Kernel::Point_3;

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

/// Size in bytes of a PLY scalar type, 0 if unknown.
int ply_type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32")
    return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

/// Checks a PLY header before CGAL reads it: magic, format, known property types, x/y/z on the
/// vertex element, a face element, and declared counts that can fit in the rest of the file.
void check_ply_header(const std::string& data, const std::string& name) {
  if (data.compare(0, 3, "ply") != 0) throw Error(name, "not a PLY file (missing 'ply' magic)");
  auto end = data.find("end_header");
  if (end == std::string::npos) throw Error(name, "truncated PLY header (no end_header)");
  auto body = data.find('\n', end);
  const std::size_t remaining = body == std::string::npos ? 0 : data.size() - body - 1;
  std::istringstream header(data.substr(0, end));
  std::string line, format;
  struct Element {
    std::string name;
    unsigned long long count = 0;
    std::vector<std::string> props;
    unsigned long long min_bytes = 0;
  };
  std::vector<Element> elements;
  while (std::getline(header, line)) {
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "format") {
      ls >> format;
      if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
        throw Error(name, fmt::format("unknown PLY format '{}'", format));
    } else if (word == "element") {
      Element e;
      std::string count;
      ls >> e.name >> count;
      if (count.empty() || count.find_first_not_of("0123456789") != std::string::npos ||
          count.size() > 15)
        throw Error(name, fmt::format("bad count '{}' for PLY element '{}'", count, e.name));
      e.count = std::stoull(count);
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) throw Error(name, "PLY property before any element");
      std::string type;
      ls >> type;
      auto& e = elements.back();
      if (type == "list") {
        std::string ctype, itype, pname;
        ls >> ctype >> itype >> pname;
        if (!ply_type_size(ctype) || !ply_type_size(itype))
          throw Error(name, fmt::format("unknown PLY list type in '{}'", line));
        e.props.push_back(pname);
        e.min_bytes += format == "ascii" ? 2 : ply_type_size(ctype);
      } else {
        std::string pname;
        ls >> pname;
        if (!ply_type_size(type)) throw Error(name, fmt::format("unknown PLY type '{}'", type));
        e.props.push_back(pname);
        e.min_bytes += format == "ascii" ? 2 : ply_type_size(type);
      }
    }
  }
  if (format.empty()) throw Error(name, "PLY header has no format line");
  unsigned long long needed = 0;
  bool has_vertex = false, has_face = false;
  for (const auto& e : elements) {
    if (e.name == "vertex") {
      has_vertex = true;
      for (const char* c : {"x", "y", "z"})
        if (std::find(e.props.begin(), e.props.end(), c) == e.props.end())
          throw Error(name, fmt::format("PLY vertex element has no '{}' property", c));
    }
    if (e.name == "face" && e.count > 0) has_face = true;
    // Ascii: each value needs at least one character and one separator (the last may be the
    // end of the file).
    unsigned long long per = std::max<unsigned long long>(e.min_bytes, 1);
    if (e.count > (remaining + 1) / per + 1)
      throw Error(name, fmt::format("PLY declares {} '{}' elements but the file is too short "
                                    "for them (truncated or corrupt)",
                                    e.count, e.name));
    needed += e.count * (format == "ascii" ? 0 : e.min_bytes);
  }
  if (!has_vertex) throw Error(name, "PLY has no vertex element");
  if (!has_face) throw Error(name, "PLY has no faces");
  if (needed > remaining) throw Error(name, "binary PLY is truncated");
}

/// The whitespace-separated tokens of one line, without its `#` comment.
std::vector<std::string_view> off_tokens(std::string_view line) {
  if (auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    std::size_t j = i;
    while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

/// A whole token as a number; false when it is not one.
template <class T>
bool parse_token(std::string_view token, T& value) {
  if (!token.empty() && token[0] == '+') token.remove_prefix(1);
  auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && end == token.data() + token.size();
}

/// Reads an ascii OFF file (Geomview's format: a header word `[ST][C][N]OFF`, the counts
/// `vertices faces [edges]`, one vertex per line, then one face per line `n i1 … in`; extra
/// values on a line — normals, colours, texture coordinates — are skipped; `#` starts a comment).
/// Our own reader rather than CGAL's, whose scanner converts indices and colours from doubles
/// without range checks (undefined behaviour on hostile files, found by fuzz/fuzz_mesh).
/// 4D, nD and binary OFF are refused with an Error.
void read_off(const std::string& data, const std::string& name, std::vector<CgalPoint>& points,
              std::vector<std::vector<std::size_t>>& polygons) {
  std::size_t pos = 0;
  int line_no = 0;
  // The next line with something on it (tokens empty at the end of the file).
  auto next_line = [&](std::vector<std::string_view>& tokens) {
    tokens.clear();
    while (tokens.empty() && pos < data.size()) {
      std::size_t end = data.find('\n', pos);
      if (end == std::string::npos) end = data.size();
      tokens = off_tokens(std::string_view(data).substr(pos, end - pos));
      pos = end + 1;
      ++line_no;
    }
    return !tokens.empty();
  };
  std::vector<std::string_view> tokens;
  if (!next_line(tokens)) throw Error(name, "not an OFF file");
  const std::string_view keyword = tokens[0];
  if (keyword.size() < 3 || keyword.substr(keyword.size() - 3) != "OFF" ||
      keyword.find_first_not_of("STCN4nOF") != std::string_view::npos)
    throw Error(name, "not an OFF file (no OFF header word)");
  if (keyword.find_first_of("4n") != std::string_view::npos)
    throw Error(name, fmt::format("{} (4D or nD) files are not supported", keyword));
  if (tokens.size() > 1 && tokens[1] == "BINARY")
    throw Error(name, "binary OFF is not supported (save it as ascii OFF or PLY)");
  // The counts may follow the header word on its line.
  tokens.erase(tokens.begin());
  if (tokens.empty() && !next_line(tokens))
    throw Error(name, "OFF header has no valid vertex/face counts");
  long long nv = -1, nf = -1;
  if (tokens.size() < 2 || tokens.size() > 3 || !parse_token(tokens[0], nv) ||
      !parse_token(tokens[1], nf) || nv < 0 || nf < 0)
    throw Error(name, "OFF header has no valid vertex/face counts");
  // Each vertex needs at least "0 0 0\n" (6 bytes), each face "3 0 0 0\n" (8 bytes).
  const std::size_t rest = pos < data.size() ? data.size() - pos : 0;
  if (static_cast<double>(nv) * 6 + static_cast<double>(nf) * 8 > static_cast<double>(rest) + 1)
    throw Error(name, fmt::format("OFF declares {} vertices and {} faces but the file is too "
                                  "short for them (truncated or corrupt)",
                                  nv, nf));
  if (nf == 0) throw Error(name, "OFF has no faces");

  points.reserve(static_cast<std::size_t>(nv));
  for (long long v = 0; v < nv; ++v) {
    if (!next_line(tokens))
      throw Error(name, fmt::format("truncated OFF file: {} of {} vertices", v, nv));
    double xyz[3];
    for (int c = 0; c < 3; ++c)
      if (c >= static_cast<int>(tokens.size()) || !parse_token(tokens[c], xyz[c]))
        throw Error(name, fmt::format("line {}: vertex {} needs three coordinates", line_no, v));
    points.emplace_back(xyz[0], xyz[1], xyz[2]);
  }
  polygons.reserve(static_cast<std::size_t>(nf));
  for (long long f = 0; f < nf; ++f) {
    if (!next_line(tokens))
      throw Error(name, fmt::format("truncated OFF file: {} of {} faces", f, nf));
    long long n = -1;
    if (!parse_token(tokens[0], n) || n < 0 || n > static_cast<long long>(tokens.size()) - 1)
      throw Error(name, fmt::format("line {}: face {} does not start with its number of "
                                    "corners followed by that many vertex ids",
                                    line_no, f));
    std::vector<std::size_t> poly(static_cast<std::size_t>(n));
    for (long long k = 0; k < n; ++k) {
      long long id = -1;
      if (!parse_token(tokens[static_cast<std::size_t>(k) + 1], id) || id < 0 || id >= nv)
        throw Error(name, fmt::format("line {}: face {} refers to vertex '{}' but there are {} "
                                      "vertices",
                                      line_no, f, tokens[static_cast<std::size_t>(k) + 1], nv));
      poly[static_cast<std::size_t>(k)] = static_cast<std::size_t>(id);
    }
    polygons.push_back(std::move(poly));
  }
}

std::string detect_format(const fs::path& path, const std::string& data) {
  std::string ext = lower(path.extension().string());
  if (ext == ".ply" || ext == ".obj" || ext == ".off") return ext.substr(1);
  if (data.compare(0, 3, "ply") == 0) return "ply";
  if (data.find("OFF") != std::string::npos && data.find("OFF") < 8) return "off";
  return "obj";
}

}  // namespace

MeshFile read_mesh(const fs::path& path) {
  const std::string name = path.string();
  std::string data = read_file(path);
  if (data.find_first_not_of(" \t\r\n") == std::string::npos) throw Error(name, "empty file");
  const std::string format = detect_format(path, data);

  std::vector<CgalPoint> points;
  std::vector<std::vector<std::size_t>> polygons;
  std::vector<CGAL::IO::Color> fcolors, vcolors;
  bool ok = false;
  {
    std::istringstream in(data, std::ios::in | std::ios::binary);
    if (format == "ply") {
      check_ply_header(data, name);
      ok = CGAL::IO::read_PLY(in, points, polygons, fcolors, vcolors, false);
    } else if (format == "off") {
      read_off(data, name, points, polygons);
      ok = true;
    } else {
      ok = CGAL::IO::read_OBJ(in, points, polygons);
    }
  }
  if (!ok && polygons.empty() && !points.empty()) throw Error(name, "no faces");
  if (!ok) throw Error(name, fmt::format("malformed or truncated {} file", lower(format)));
  if (points.empty()) throw Error(name, "no vertices");
  if (polygons.empty()) throw Error(name, "no faces");

  MeshFile out;
  const std::size_t nv = points.size();
  out.mesh.V.resize(static_cast<Eigen::Index>(nv), 3);
  for (std::size_t i = 0; i < nv; ++i) {
    for (int c = 0; c < 3; ++c) out.mesh.V(static_cast<Eigen::Index>(i), c) = points[i][c];
    if (!out.mesh.V.row(static_cast<Eigen::Index>(i)).allFinite())
      throw Error(name, fmt::format("vertex {} has a NaN or infinite coordinate", i));
  }
  out.mesh.faces.reserve(polygons.size());
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    const auto& poly = polygons[f];
    if (poly.size() < 3)
      throw Error(name, fmt::format("face {} has {} vertices (at least 3 needed)", f, poly.size()));
    std::vector<int> face;
    face.reserve(poly.size());
    for (std::size_t v : poly) {
      if (v >= nv)
        throw Error(name, fmt::format("face {} refers to vertex {} but there are only {} vertices",
                                      f, static_cast<long long>(v), nv));
      face.push_back(static_cast<int>(v));
    }
    out.mesh.faces.push_back(std::move(face));
  }
  if (vcolors.size() == nv) {
    out.vertex_colors.resize(nv);
    for (std::size_t i = 0; i < nv; ++i)
      out.vertex_colors[i] = {vcolors[i].red(), vcolors[i].green(), vcolors[i].blue()};
  }
  return out;
}

void write_obj(const fs::path& path, const PolyMesh& mesh, const std::vector<int>& supports) {
  std::string s;
  s += "# gridshell polygon mesh: faces are panels, edges are beams, vertices are joints\n";
  if (!supports.empty()) {
    s += "# supports";
    for (int v : supports) s += fmt::format(" {}", v);
    s += "\n";
  }
  for (int v = 0; v < mesh.num_vertices(); ++v)
    s += fmt::format("v {} {} {}\n", format_number(mesh.V(v, 0)), format_number(mesh.V(v, 1)),
                     format_number(mesh.V(v, 2)));
  for (const auto& f : mesh.faces) {
    s += "f";
    for (int v : f) s += fmt::format(" {}", v + 1);
    s += "\n";
  }
  write_file_atomic(path, s);
}

void write_ply(const fs::path& path, const PolyMesh& mesh, const std::vector<int>& supports,
               bool binary) {
  std::vector<char> is_support(mesh.num_vertices(), 0);
  for (int v : supports) is_support.at(v) = 1;
  std::string s;
  s += fmt::format(
      "ply\nformat {} 1.0\ncomment gridshell\nelement vertex {}\nproperty double x\n"
      "property double y\nproperty double z\nproperty uchar red\nproperty uchar green\n"
      "property uchar blue\nproperty uchar support\nelement face {}\n"
      "property list uchar int vertex_indices\nend_header\n",
      binary ? "binary_little_endian" : "ascii", mesh.num_vertices(), mesh.num_faces());
  auto put = [&s](const auto& value) {
    char buf[sizeof(value)];
    std::memcpy(buf, &value, sizeof(value));  // the machines we build for are little endian
    s.append(buf, sizeof(value));
  };
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const std::uint8_t r = is_support[v] ? 255 : 192, g = is_support[v] ? 0 : 192;
    if (binary) {
      for (int c = 0; c < 3; ++c) {
        format_number(mesh.V(v, c));  // refuses NaN
        put(mesh.V(v, c));
      }
      put(r), put(g), put(g), put(static_cast<std::uint8_t>(is_support[v]));
    } else {
      s += fmt::format("{} {} {} {} {} {} {}\n", format_number(mesh.V(v, 0)),
                       format_number(mesh.V(v, 1)), format_number(mesh.V(v, 2)), r, g, g,
                       static_cast<int>(is_support[v]));
    }
  }
  for (const auto& f : mesh.faces) {
    if (f.size() > 255) throw Error(path.string(), "face with more than 255 vertices");
    if (binary) {
      put(static_cast<std::uint8_t>(f.size()));
      for (int v : f) put(static_cast<std::int32_t>(v));
    } else {
      s += fmt::format("{}", f.size());
      for (int v : f) s += fmt::format(" {}", v);
      s += "\n";
    }
  }
  write_file_atomic(path, s);
}

namespace {

void append_data_arrays(std::string& s, const Attributes& attrs, Eigen::Index rows) {
  for (const auto& [name, values] : attrs) {
    if (values.rows() != rows)
      throw Error(name,
                  fmt::format("internal: attribute has {} rows, expected {}", values.rows(), rows));
    s += fmt::format(
        "<DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">\n",
        name, values.cols());
    for (Eigen::Index i = 0; i < values.rows(); ++i) {
      for (Eigen::Index c = 0; c < values.cols(); ++c) s += format_number(values(i, c)) + " ";
      s += "\n";
    }
    s += "</DataArray>\n";
  }
}

void append_points(std::string& s, const Points& V) {
  s += "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    s += fmt::format("{} {} {}\n", format_number(V(v, 0)), format_number(V(v, 1)),
                     format_number(V(v, 2)));
  s += "</DataArray>\n</Points>\n";
}

}  // namespace

void write_vtp(const fs::path& path, const PolyMesh& mesh, const Attributes& point_data,
               const Attributes& cell_data) {
  std::string s =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" "
      "byte_order=\"LittleEndian\">\n<PolyData>\n";
  s += fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfPolys=\"{}\">\n", mesh.num_vertices(),
                   mesh.num_faces());
  append_points(s, mesh.V);
  s += "<Polys>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& f : mesh.faces) {
    for (int v : f) s += fmt::format("{} ", v);
    s += "\n";
  }
  s += "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  std::size_t offset = 0;
  for (const auto& f : mesh.faces) s += fmt::format("{}\n", offset += f.size());
  s += "</DataArray>\n</Polys>\n<PointData>\n";
  append_data_arrays(s, point_data, mesh.num_vertices());
  s += "</PointData>\n<CellData>\n";
  append_data_arrays(s, cell_data, mesh.num_faces());
  s += "</CellData>\n</Piece>\n</PolyData>\n</VTKFile>\n";
  write_file_atomic(path, s);
}

void write_vtp_lines(const fs::path& path, const Points& V,
                     const std::vector<std::array<int, 2>>& lines, const Attributes& point_data,
                     const Attributes& cell_data) {
  std::string s =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" "
      "byte_order=\"LittleEndian\">\n<PolyData>\n";
  s += fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfLines=\"{}\">\n", V.rows(), lines.size());
  append_points(s, V);
  s += "<Lines>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& l : lines) s += fmt::format("{} {}\n", l[0], l[1]);
  s += "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < lines.size(); ++i) s += fmt::format("{}\n", 2 * (i + 1));
  s += "</DataArray>\n</Lines>\n<PointData>\n";
  append_data_arrays(s, point_data, V.rows());
  s += "</PointData>\n<CellData>\n";
  append_data_arrays(s, cell_data, static_cast<Eigen::Index>(lines.size()));
  s += "</CellData>\n</Piece>\n</PolyData>\n</VTKFile>\n";
  write_file_atomic(path, s);
}

}  // namespace gridshell::io
