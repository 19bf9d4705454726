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
#include <CGAL/IO/STL.h>
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

// ---- PLY ------------------------------------------------------------------------------------
// Our own reader rather than CGAL's: fuzz/fuzz_mesh found that CGAL's PLY reader dereferences a
// null pointer when a coordinate is not float/double (e.g. `property short y`), and it casts list
// lengths to size_t unchecked (a negative or huge length is undefined behaviour or a huge
// allocation). This one reads every element and property the header declares (extra ones are
// skipped), checks each value as it goes, and keeps what we use: x y z (any numeric type), the
// vertex colour (red green blue, r g b or diffuse_red …; integer types as 0–255, float types as
// 0–1), and the faces' vertex_indices (or vertex_index) lists.

/// Size in bytes of a PLY scalar type, 0 if unknown.
int ply_type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32")
    return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

bool ply_is_float(const std::string& t) {
  return t == "float" || t == "float32" || t == "double" || t == "float64";
}

struct PlyProperty {
  std::string name;
  std::string type;        ///< the scalar type, or a list's item type
  std::string count_type;  ///< a list's length type; empty for a scalar
  bool is_list() const { return !count_type.empty(); }
};

struct PlyElement {
  std::string name;
  unsigned long long count = 0;
  std::vector<PlyProperty> props;
  const PlyProperty* find(const std::string& prop) const {
    for (const auto& p : props)
      if (p.name == prop) return &p;
    return nullptr;
  }
};

struct PlyHeader {
  std::string format;  ///< ascii, binary_little_endian or binary_big_endian
  std::vector<PlyElement> elements;
  std::size_t body = 0;  ///< offset of the first byte after the header
  int vertex = -1;       ///< index of the vertex element ("vertex", or CGAL's "vertices")
  int face = -1;         ///< index of the face element ("face" or "faces")
};

/// Reads and checks a PLY header: magic, format, known types, x/y/z on the vertex element, a face
/// element with a vertex index list, and declared counts that can fit in the rest of the file.
PlyHeader read_ply_header(const std::string& data, const std::string& name) {
  if (data.compare(0, 3, "ply") != 0) throw Error(name, "not a PLY file (missing 'ply' magic)");
  PlyHeader h;
  std::size_t pos = 0;
  bool ended = false;
  while (!ended && pos < data.size()) {
    std::size_t eol = data.find('\n', pos);
    if (eol == std::string::npos) eol = data.size();
    std::istringstream ls(data.substr(pos, eol - pos));
    pos = eol + 1;
    std::string word;
    ls >> word;
    if (word == "end_header") {
      ended = true;
    } else if (word == "format") {
      ls >> h.format;
      if (h.format != "ascii" && h.format != "binary_little_endian" &&
          h.format != "binary_big_endian")
        throw Error(name, fmt::format("unknown PLY format '{}'", h.format));
    } else if (word == "element") {
      PlyElement e;
      std::string count;
      ls >> e.name >> count;
      if (count.empty() || count.find_first_not_of("0123456789") != std::string::npos ||
          count.size() > 15)
        throw Error(name, fmt::format("bad count '{}' for PLY element '{}'", count, e.name));
      e.count = std::stoull(count);
      h.elements.push_back(e);
    } else if (word == "property") {
      if (h.elements.empty()) throw Error(name, "PLY property before any element");
      PlyProperty p;
      ls >> p.type;
      if (p.type == "list") ls >> p.count_type >> p.type;
      ls >> p.name;
      if (!ply_type_size(p.type) || (p.is_list() && !ply_type_size(p.count_type)))
        throw Error(name,
                    fmt::format("unknown PLY type in 'property {}{} {}'",
                                p.is_list() ? "list " + p.count_type + " " : "", p.type, p.name));
      if (p.is_list() && ply_is_float(p.count_type))
        throw Error(name, fmt::format("PLY list '{}' has a non-integer length type '{}'", p.name,
                                      p.count_type));
      h.elements.back().props.push_back(p);
    }
  }
  if (!ended) throw Error(name, "truncated PLY header (no end_header)");
  if (h.format.empty()) throw Error(name, "PLY header has no format line");
  h.body = std::min(pos, data.size());
  const bool ascii = h.format == "ascii";
  const std::size_t remaining = data.size() - h.body;

  for (int i = 0; i < static_cast<int>(h.elements.size()); ++i) {
    const PlyElement& e = h.elements[i];
    if (h.vertex < 0 && (e.name == "vertex" || e.name == "vertices")) h.vertex = i;
    if (h.face < 0 && (e.name == "face" || e.name == "faces")) h.face = i;
  }
  if (h.vertex < 0) throw Error(name, "PLY has no vertex element");
  for (const char* c : {"x", "y", "z"}) {
    const PlyProperty* p = h.elements[h.vertex].find(c);
    if (!p) throw Error(name, fmt::format("PLY vertex element has no '{}' property", c));
    if (p->is_list()) throw Error(name, fmt::format("PLY vertex property '{}' is a list", c));
  }
  if (h.face < 0 || h.elements[h.face].count == 0) throw Error(name, "PLY has no faces");
  const PlyElement& faces = h.elements[h.face];
  const PlyProperty* ids = faces.find("vertex_indices");
  if (!ids) ids = faces.find("vertex_index");
  if (!ids || !ids->is_list()) throw Error(name, "PLY face element has no 'vertex_indices' list");
  if (ply_is_float(ids->type))
    throw Error(name,
                fmt::format("PLY vertex indices of type '{}' (integers expected)", ids->type));

  // Every value needs at least one byte (binary: its size; ascii: a character and a separator,
  // the last may be the end of the file), so the declared counts must fit what follows.
  unsigned long long needed = 0;
  for (const auto& e : h.elements) {
    unsigned long long per = 0;
    for (const auto& p : e.props)
      per += ascii ? 2 : ply_type_size(p.is_list() ? p.count_type : p.type);
    per = std::max<unsigned long long>(per, 1);
    if (e.count > (remaining + 1) / per + 1)
      throw Error(name, fmt::format("PLY declares {} '{}' elements but the file is too short "
                                    "for them (truncated or corrupt)",
                                    e.count, e.name));
    needed += ascii ? 0 : e.count * per;
  }
  if (needed > remaining) throw Error(name, "binary PLY is truncated");
  return h;
}

/// The values after a PLY header, one at a time, as doubles (exact for every PLY integer type).
class PlyValues {
 public:
  PlyValues(const std::string& data, const PlyHeader& h, const std::string& name)
      : data_(data), pos_(h.body), name_(name), format_(h.format) {}

  double next(const std::string& type) {
    return format_ == "ascii" ? next_ascii(type == "float" || type == "float32") : next_binary(type);
  }

  /// A list length, checked against what is left of the file before anything is allocated.
  std::size_t next_length(const PlyProperty& p, const std::string& where) {
    const double n = next(p.count_type);
    const double item = format_ == "ascii" ? 2 : ply_type_size(p.type);
    const double left = static_cast<double>(data_.size() - pos_);
    if (!(n >= 0) || n != std::floor(n) || n * item > left + 1)
      throw Error(name_, fmt::format("{}: list '{}' has length {}, which the file cannot hold",
                                     where, p.name, n));
    return static_cast<std::size_t>(n);
  }

 private:
  /// `single`: the property is a 32-bit float, so the value is the nearest float, as a reader
  /// that stores the declared type (CGAL's, which this replaced) gives it — designs on ascii
  /// files keep their bits.
  double next_ascii(bool single) {
    while (pos_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[pos_]))) ++pos_;
    std::size_t end = pos_;
    while (end < data_.size() && !std::isspace(static_cast<unsigned char>(data_[end]))) ++end;
    if (end == pos_)
      throw Error(name_, "truncated PLY file: fewer values than the header declares");
    std::string_view token(data_.data() + pos_, end - pos_);
    pos_ = end;
    if (token[0] == '+') token.remove_prefix(1);
    double v = 0;
    float f = 0;
    auto [stop, ec] = single ? std::from_chars(token.data(), token.data() + token.size(), f)
                             : std::from_chars(token.data(), token.data() + token.size(), v);
    if (ec != std::errc() || stop != token.data() + token.size())
      throw Error(name_, fmt::format("malformed PLY value '{}'", token));
    return single ? static_cast<double>(f) : v;
  }

  double next_binary(const std::string& type) {
    const int size = ply_type_size(type);
    if (pos_ + size > data_.size()) throw Error(name_, "binary PLY is truncated");
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, size);
    pos_ += size;
    if (format_ == "binary_big_endian") std::reverse(b, b + size);  // we run on little endian
    auto as = [&b](auto value) {
      std::memcpy(&value, b, sizeof(value));
      return static_cast<double>(value);
    };
    if (type == "char" || type == "int8") return as(std::int8_t{});
    if (type == "uchar" || type == "uint8") return as(std::uint8_t{});
    if (type == "short" || type == "int16") return as(std::int16_t{});
    if (type == "ushort" || type == "uint16") return as(std::uint16_t{});
    if (type == "int" || type == "int32") return as(std::int32_t{});
    if (type == "uint" || type == "uint32") return as(std::uint32_t{});
    if (type == "float" || type == "float32") return as(float{});
    return as(double{});
  }

  const std::string& data_;
  std::size_t pos_;
  const std::string& name_;
  std::string format_;
};

/// A colour channel from a PLY value: integer types as 0–255, float types as 0–1 (clamped).
std::uint8_t colour_channel(double v, const std::string& type) {
  if (ply_is_float(type)) v *= 255;
  if (!(v > 0)) return 0;
  return static_cast<std::uint8_t>(std::lround(std::min(v, 255.0)));
}

/// Reads a PLY file whose header `read_ply_header` accepted.
void read_ply(const std::string& data, const std::string& name, std::vector<CgalPoint>& points,
              std::vector<std::vector<std::size_t>>& polygons,
              std::vector<std::array<std::uint8_t, 3>>& colours) {
  const PlyHeader h = read_ply_header(data, name);
  PlyValues in(data, h, name);
  // Which vertex property carries what: 0–2 = x y z, 3–5 = red green blue, -1 = nothing we use.
  const PlyElement& ve = h.elements[h.vertex];
  std::vector<int> role(ve.props.size(), -1);
  const char* const kAxes[3] = {"x", "y", "z"};
  const char* const kColourNames[3][3] = {
      {"red", "green", "blue"}, {"r", "g", "b"}, {"diffuse_red", "diffuse_green", "diffuse_blue"}};
  for (std::size_t k = 0; k < ve.props.size(); ++k)
    for (int c = 0; c < 3; ++c)
      if (ve.props[k].name == kAxes[c]) role[k] = c;
  for (const auto& names : kColourNames) {
    const PlyProperty* p[3] = {ve.find(names[0]), ve.find(names[1]), ve.find(names[2])};
    if (!p[0] || !p[1] || !p[2] || p[0]->is_list() || p[1]->is_list() || p[2]->is_list()) continue;
    for (std::size_t k = 0; k < ve.props.size(); ++k)
      for (int c = 0; c < 3; ++c)
        if (&ve.props[k] == p[c]) role[k] = 3 + c;
    break;
  }
  const bool has_colour = std::find(role.begin(), role.end(), 3) != role.end();
  const unsigned long long vertex_count = ve.count;
  const PlyElement& fe = h.elements[h.face];
  const PlyProperty* ids = fe.find("vertex_indices");
  if (!ids) ids = fe.find("vertex_index");

  for (int e = 0; e < static_cast<int>(h.elements.size()); ++e) {
    const PlyElement& el = h.elements[e];
    for (unsigned long long i = 0; i < el.count; ++i) {
      double xyz[3] = {0, 0, 0};
      std::array<std::uint8_t, 3> rgb{};
      for (std::size_t k = 0; k < el.props.size(); ++k) {
        const PlyProperty& p = el.props[k];
        if (p.is_list()) {
          const std::size_t n = in.next_length(p, fmt::format("{} {}", el.name, i));
          const bool corners = e == h.face && &p == ids;
          // Refused as read, so memory stays proportional to the file: an empty face is one
          // byte in a binary file but a vector in memory.
          if (corners && n < 3)
            throw Error(name, fmt::format("face {} has {} vertices (at least 3 needed)", i, n));
          if (corners) polygons.emplace_back().reserve(n);
          for (std::size_t j = 0; j < n; ++j) {
            const double v = in.next(p.type);
            if (!corners) continue;
            if (!(v >= 0) || v != std::floor(v) || v >= static_cast<double>(vertex_count))
              throw Error(name, fmt::format("face {} refers to vertex {} but there are only {} "
                                            "vertices",
                                            i, v, vertex_count));
            polygons.back().push_back(static_cast<std::size_t>(v));
          }
        } else {
          const double v = in.next(p.type);
          if (e != h.vertex || role[k] < 0) continue;
          if (role[k] < 3) {
            xyz[role[k]] = v;
          } else {
            rgb[role[k] - 3] = colour_channel(v, p.type);
          }
        }
      }
      if (e == h.vertex) {
        points.emplace_back(xyz[0], xyz[1], xyz[2]);
        if (has_colour) colours.push_back(rgb);
      }
    }
  }
}

// ---- OFF ------------------------------------------------------------------------------------

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
    if (n < 3)  // refused as read (an empty face is two bytes in the file, a vector in memory)
      throw Error(name, fmt::format("line {}: face {} has {} vertices (at least 3 needed)",
                                    line_no, f, n));
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
  if (ext == ".ply" || ext == ".obj" || ext == ".off" || ext == ".stl") return ext.substr(1);
  if (data.compare(0, 3, "ply") == 0) return "ply";
  if (data.compare(0, 6, "solid ") == 0) return "stl";
  if (data.find("OFF") != std::string::npos && data.find("OFF") < 8) return "off";
  return "obj";
}

}  // namespace

/// Refuses an OBJ face line (`f …`) with fewer than 3 corners before CGAL's reader turns each
/// such two-byte line into a vector: memory stays proportional to the file.
void check_obj_faces(const std::string& data, const std::string& name) {
  std::size_t line_no = 0;
  for (std::size_t at = 0; at < data.size();) {
    const std::size_t end = std::min(data.find('\n', at), data.size());
    ++line_no;
    std::string_view line(data.data() + at, end - at);
    at = end + 1;
    const auto is_space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    std::size_t i = 0;
    while (i < line.size() && is_space(line[i])) ++i;
    if (i >= line.size() || line[i] != 'f' || (i + 1 < line.size() && !is_space(line[i + 1])))
      continue;
    int corners = 0;  // whitespace-separated tokens after `f`, up to a comment
    for (++i; i < line.size() && line[i] != '#' && corners < 3;) {
      while (i < line.size() && is_space(line[i])) ++i;
      if (i >= line.size() || line[i] == '#') break;
      ++corners;
      while (i < line.size() && !is_space(line[i])) ++i;
    }
    if (corners < 3)
      throw Error(name, fmt::format("line {}: face has {} vertices (at least 3 needed)", line_no,
                                    corners));
  }
}

MeshFile read_mesh(const fs::path& path) {
  const std::string name = path.string();
  std::string data = read_file(path);
  if (data.find_first_not_of(" \t\r\n") == std::string::npos) throw Error(name, "empty file");
  const std::string format = detect_format(path, data);

  std::vector<CgalPoint> points;
  std::vector<std::vector<std::size_t>> polygons;
  std::vector<std::array<std::uint8_t, 3>> colours;  // PLY vertex colours, when present
  bool ok = false;
  {
    std::istringstream in(data, std::ios::in | std::ios::binary);
    if (format == "ply") {
      read_ply(data, name, points, polygons, colours);
      ok = true;
    } else if (format == "off") {
      read_off(data, name, points, polygons);
      ok = true;
    } else if (format == "stl") {
      // ASCII or binary (CGAL tells them apart, and tries the other when one fails); corners
      // at exactly the same position are one vertex.
      std::vector<std::array<std::size_t, 3>> triangles;
      ok = CGAL::IO::read_STL(in, points, triangles);
      for (const auto& t : triangles) polygons.push_back({t[0], t[1], t[2]});
    } else {
      check_obj_faces(data, name);
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
  if (colours.size() == nv) out.vertex_colors = std::move(colours);
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
  for (int v : supports) {
    if (v < 0 || v >= mesh.num_vertices())
      throw Error(path.string(), fmt::format("internal: support vertex {} of {} vertices", v,
                                             mesh.num_vertices()));
    is_support[v] = 1;
  }
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

}  // namespace gridshell::io
