#include "gridshell/field/transfer.h"

#include "gridshell/core/error.h"
#include "gridshell/mesh/nearest_triangles.h"

namespace gridshell {

namespace {
/// u projected onto the plane of face f of `to`, normalised (unchanged if it vanishes).
Vec3 onto_face(const Vec3& u, const TriMesh& to, int f) {
  const Vec3 a = to.vertex(to.F(f, 0)), b = to.vertex(to.F(f, 1)), c = to.vertex(to.F(f, 2));
  const Vec3 n = (b - a).cross(c - a);
  if (n.norm() == 0) return u;
  const Vec3 t = u - u.dot(n) / n.squaredNorm() * n;
  return t.norm() > 1e-12 * u.norm() ? Vec3(t.normalized()) : u;
}
}  // namespace

std::vector<int> nearest_faces(const TriMesh& from, const TriMesh& to) {
  const NearestTriangles tree(from);
  if (tree.empty()) throw Error("field transfer", "the source mesh has no triangle");
  return tree.nearest_faces(to);
}

Field transfer_field(const TriMesh& from, const Field& field, const TriMesh& to) {
  if (field.size() != from.num_faces())
    throw Error("field transfer", "the field does not match the source mesh");
  return transfer_field(field, nearest_faces(from, to), to);
}

Field transfer_field(const Field& field, const std::vector<int>& source, const TriMesh& to) {
  if (static_cast<int>(source.size()) != to.num_faces())
    throw Error("field transfer", "the face map does not match the target mesh");
  for (int s : source)
    if (s < 0 || s >= field.size())
      throw Error("field transfer", "the face map does not match the field");
  Field out;
  auto carry = [&](const auto& in, auto& dst) {
    if (in.empty()) return;
    dst.reserve(source.size());
    for (int s : source) dst.push_back(in[s]);
  };
  carry(field.u, out.u);
  carry(field.d, out.d);
  carry(field.a, out.a);
  carry(field.u_raw, out.u_raw);
  carry(field.d_raw, out.d_raw);
  carry(field.a_raw, out.a_raw);
  carry(field.coherence, out.coherence);
  for (int f = 0; f < to.num_faces(); ++f) {
    out.u[f] = onto_face(out.u[f], to, f);
    if (!out.u_raw.empty()) out.u_raw[f] = onto_face(out.u_raw[f], to, f);
  }
  return out;
}

StressField transfer_stress(const TriMesh& from, const StressField& stress, const TriMesh& to) {
  if (static_cast<int>(stress.size()) != from.num_faces())
    throw Error("field transfer", "the stress does not match the source mesh");
  return transfer_stress(stress, nearest_faces(from, to), to);
}

StressField transfer_stress(const StressField& stress, const std::vector<int>& source,
                            const TriMesh& to) {
  if (static_cast<int>(source.size()) != to.num_faces())
    throw Error("field transfer", "the face map does not match the target mesh");
  for (int s : source)
    if (s < 0 || s >= static_cast<int>(stress.size()))
      throw Error("field transfer", "the face map does not match the stress");
  StressField out(source.size());
  for (int f = 0; f < to.num_faces(); ++f) {
    out[f] = stress[source[f]];
    out[f].d1 = onto_face(out[f].d1, to, f);
    const Vec3 a = to.vertex(to.F(f, 0)), b = to.vertex(to.F(f, 1)), c = to.vertex(to.F(f, 2));
    const Vec3 n = (b - a).cross(c - a);
    if (n.norm() > 0) out[f].d2 = n.normalized().cross(out[f].d1);
  }
  return out;
}

}  // namespace gridshell
