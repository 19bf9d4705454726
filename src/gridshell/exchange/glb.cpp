#include "gridshell/exchange/glb.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <sstream>

#include <tiny_gltf.h>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"

namespace gridshell::exchange {

namespace {

/// One mesh's vertex streams and triangles, glTF's axes (y up).
struct Geometry {
  std::vector<float> position, normal, id;
  std::vector<std::uint32_t> index;

  std::uint32_t add(const Vec3& p, const Vec3& n, int part) {
    const auto v = static_cast<std::uint32_t>(id.size());
    y_up(position, p);
    y_up(normal, n);
    id.push_back(static_cast<float>(part));
    return v;
  }
  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    index.insert(index.end(), {a, b, c});
  }

 private:
  /// (x, y, z), z up → glTF's (x, z, −y), y up.
  static void y_up(std::vector<float>& out, const Vec3& x) {
    out.insert(out.end(), {static_cast<float>(x.x()), static_cast<float>(x.z()),
                           static_cast<float>(-x.y())});
  }
};

/// A unit vector ⟂ d, as close to `up` as possible (any ⟂ one when up ∥ d).
Vec3 across(const Vec3& d, const Vec3& up) {
  Vec3 u = up - up.dot(d) * d;
  if (u.norm() < 1e-9 * std::max(1.0, up.norm())) {
    u = std::abs(d.z()) < 0.9 ? Vec3::UnitZ() : Vec3::UnitX();
    u -= u.dot(d) * d;
  }
  return u.normalized();
}

/// A prism of profile `p` (points in the (u, v) plane, counter-clockwise from u towards v)
/// between the beam's ends; smooth normals (round) or one per side (flat).
void add_prism(Geometry& g, const GlbBeam& beam, const std::vector<Eigen::Vector2d>& p, bool smooth,
               int part) {
  const double length = (beam.b - beam.a).norm();
  if (!(length > 0)) return;
  const Vec3 d = (beam.b - beam.a) / length;
  const Vec3 u = across(d, beam.up), v = d.cross(u);
  const auto at = [&](const Eigen::Vector2d& q) { return Vec3(q.x() * u + q.y() * v); };
  const std::size_t n = p.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 o0 = at(p[k]), o1 = at(p[(k + 1) % n]);
    const Vec3 side = (o1 - o0).cross(d).normalized();
    const Vec3 n0 = smooth ? o0.normalized() : side, n1 = smooth ? o1.normalized() : side;
    const std::uint32_t a0 = g.add(beam.a + o0, n0, part), a1 = g.add(beam.a + o1, n1, part),
                        b1 = g.add(beam.b + o1, n1, part), b0 = g.add(beam.b + o0, n0, part);
    g.triangle(a0, a1, b1);
    g.triangle(a0, b1, b0);
  }
}

Geometry beam_geometry(const std::vector<GlbBeam>& beams) {
  Geometry g;
  constexpr int kSides = 12;
  for (std::size_t i = 0; i < beams.size(); ++i) {
    const GlbBeam& b = beams[i];
    std::vector<Eigen::Vector2d> profile;
    if (b.round) {
      for (int k = 0; k < kSides; ++k) {
        const double t = 2 * std::numbers::pi * k / kSides;
        profile.emplace_back(0.5 * b.height * std::cos(t), 0.5 * b.height * std::sin(t));
      }
    } else {
      const double h = 0.5 * b.height, w = 0.5 * b.width;
      profile = {{h, w}, {-h, w}, {-h, -w}, {h, -w}};
    }
    add_prism(g, b, profile, b.round, static_cast<int>(i));
  }
  return g;
}

Geometry panel_geometry(const std::vector<std::vector<Vec3>>& panels) {
  Geometry g;
  for (std::size_t i = 0; i < panels.size(); ++i) {
    const auto& corners = panels[i];
    if (corners.size() < 3) continue;
    PolyMesh one;
    one.V.resize(static_cast<Eigen::Index>(corners.size()), 3);
    std::vector<int> face;
    for (std::size_t k = 0; k < corners.size(); ++k) {
      one.V.row(static_cast<Eigen::Index>(k)) = corners[k].transpose();
      face.push_back(static_cast<int>(k));
    }
    one.faces.push_back(face);
    const Vec3 normal = [&] {
      Vec3 a = Vec3::Zero();
      for (std::size_t k = 0; k < corners.size(); ++k)
        a += corners[k].cross(corners[(k + 1) % corners.size()]);
      return a.norm() > 0 ? Vec3(a.normalized()) : Vec3(Vec3::UnitZ());
    }();
    const TriMesh tri = triangulate(one);
    const auto base = static_cast<std::uint32_t>(g.id.size());
    for (const Vec3& c : corners) g.add(c, normal, static_cast<int>(i));
    for (int t = 0; t < tri.F.rows(); ++t)
      g.triangle(base + static_cast<std::uint32_t>(tri.F(t, 0)),
                 base + static_cast<std::uint32_t>(tri.F(t, 1)),
                 base + static_cast<std::uint32_t>(tri.F(t, 2)));
  }
  return g;
}

/// Appends `bytes` to the buffer (4-byte aligned) with a view and returns the view's index.
int add_view(tinygltf::Model& m, const void* bytes, std::size_t size, int target) {
  auto& data = m.buffers[0].data;
  while (data.size() % 4) data.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = data.size();
  view.byteLength = size;
  view.target = target;
  const auto* p = static_cast<const unsigned char*>(bytes);
  data.insert(data.end(), p, p + size);
  m.bufferViews.push_back(view);
  return static_cast<int>(m.bufferViews.size()) - 1;
}

int add_accessor(tinygltf::Model& m, const std::vector<float>& values, int type, bool bounds) {
  tinygltf::Accessor a;
  a.bufferView =
      add_view(m, values.data(), values.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
  a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  a.type = type;
  const int width = type == TINYGLTF_TYPE_VEC3 ? 3 : 1;
  a.count = values.size() / width;
  if (bounds) {  // glTF requires min and max of positions
    a.minValues.assign(width, 1e300);
    a.maxValues.assign(width, -1e300);
    for (std::size_t k = 0; k < values.size(); ++k) {
      a.minValues[k % width] = std::min(a.minValues[k % width], static_cast<double>(values[k]));
      a.maxValues[k % width] = std::max(a.maxValues[k % width], static_cast<double>(values[k]));
    }
  }
  m.accessors.push_back(a);
  return static_cast<int>(m.accessors.size()) - 1;
}

int add_material(tinygltf::Model& m, const std::string& name, std::vector<double> colour,
                 double metallic, double roughness, bool glass) {
  tinygltf::Material mat;
  mat.name = name;
  mat.pbrMetallicRoughness.baseColorFactor = std::move(colour);
  mat.pbrMetallicRoughness.metallicFactor = metallic;
  mat.pbrMetallicRoughness.roughnessFactor = roughness;
  if (glass) {
    mat.alphaMode = "BLEND";
    mat.doubleSided = true;
  }
  m.materials.push_back(mat);
  return static_cast<int>(m.materials.size()) - 1;
}

void add_mesh(tinygltf::Model& m, const std::string& kind, const Geometry& g, int count,
              int material) {
  tinygltf::Primitive p;
  p.mode = TINYGLTF_MODE_TRIANGLES;
  p.material = material;
  p.attributes["POSITION"] = add_accessor(m, g.position, TINYGLTF_TYPE_VEC3, true);
  p.attributes["NORMAL"] = add_accessor(m, g.normal, TINYGLTF_TYPE_VEC3, false);
  p.attributes["_ID"] = add_accessor(m, g.id, TINYGLTF_TYPE_SCALAR, false);
  tinygltf::Accessor idx;
  idx.bufferView = add_view(m, g.index.data(), g.index.size() * sizeof(std::uint32_t),
                            TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  idx.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  idx.type = TINYGLTF_TYPE_SCALAR;
  idx.count = g.index.size();
  m.accessors.push_back(idx);
  p.indices = static_cast<int>(m.accessors.size()) - 1;
  tinygltf::Mesh mesh;
  mesh.name = kind;
  mesh.primitives.push_back(p);
  tinygltf::Value::Object extras;
  extras["kind"] = tinygltf::Value(kind);
  extras["count"] = tinygltf::Value(count);
  mesh.extras = tinygltf::Value(extras);
  m.meshes.push_back(mesh);
  tinygltf::Node node;
  node.name = kind;
  node.mesh = static_cast<int>(m.meshes.size()) - 1;
  m.nodes.push_back(node);
  m.scenes[0].nodes.push_back(static_cast<int>(m.nodes.size()) - 1);
}

void check_finite(const GlbModel& model) {
  for (const GlbBeam& b : model.beams)
    if (!b.a.allFinite() || !b.b.allFinite() || !b.up.allFinite() || !std::isfinite(b.height) ||
        !std::isfinite(b.width))
      throw Error("gridshell.glb", "internal: refusing to write a non-finite number");
  for (const auto& p : model.panels)
    for (const Vec3& c : p)
      if (!c.allFinite()) throw Error("gridshell.glb", "internal: refusing to write a non-finite number");
}

}  // namespace

std::string glb_bytes(const GlbModel& model) {
  check_finite(model);
  tinygltf::Model m;
  m.asset.version = "2.0";
  m.asset.generator = "gridshell";
  m.buffers.emplace_back();
  m.scenes.emplace_back();
  m.defaultScene = 0;
  // A mesh must have a primitive: a part with no triangles (no beams, no panels) is left out.
  const Geometry beams = beam_geometry(model.beams), panels = panel_geometry(model.panels);
  if (!beams.index.empty())
    add_mesh(m, "beams", beams, static_cast<int>(model.beams.size()),
             add_material(m, "steel", {0.56, 0.57, 0.58, 1.0}, 0.8, 0.45, false));
  if (!panels.index.empty())
    add_mesh(m, "panels", panels, static_cast<int>(model.panels.size()),
             add_material(m, "glass", {0.62, 0.80, 0.92, 0.35}, 0.0, 0.1, true));
  m.buffers[0].name = "gridshell";
  std::ostringstream out;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&m, out, false, true))
    throw Error("gridshell.glb", "the glTF writer failed");
  return out.str();
}

void write_glb(const std::filesystem::path& path, const GlbModel& model) {
  io::write_file_atomic(path, glb_bytes(model));
}

}  // namespace gridshell::exchange
