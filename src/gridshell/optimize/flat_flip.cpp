// Beam flips of flat panels (flat_panels_internal.h, flip_collapsed_beams): where the planes
// have shrunk a beam to (below) the post-check's shortest, the panels' planes meet the other way
// round; the beam is turned over (a T1 flip) so that the joints follow the planes' arrangement.
#include <algorithm>
#include <cmath>

#include <spdlog/spdlog.h>

#include "gridshell/optimize/flat_panels_internal.h"

namespace gridshell::flat_detail {

namespace {

/// Position of joint j in face f's cycle, or −1.
int slot_of(const std::vector<int>& face, int j) {
  const auto it = std::find(face.begin(), face.end(), j);
  return it == face.end() ? -1 : static_cast<int>(it - face.begin());
}

bool contains(const std::vector<int>& v, int x) { return std::find(v.begin(), v.end(), x) != v.end(); }

/// Inserts joint `add` next to `at` in `face`, on the side of its neighbour that lies in `side`
/// (a face's joint list): [… p, at, q …] → [… p, add, at, q …] when p is in `side`, else after.
void insert_beside(std::vector<int>& face, int at, int add, const std::vector<int>& side) {
  const int n = static_cast<int>(face.size()), k = slot_of(face, at);
  const int prev = face[(k + n - 1) % n];
  face.insert(face.begin() + (contains(side, prev) ? k : k + 1), add);
}

/// The two faces of joint j's planes other than f and g (−1 when not exactly one).
int third_plane(const Joint& J, int f, int g) {
  int other = -1, count = 0;
  for (int s : J.plane)
    if (s != f && s != g) other = s, ++count;
  return count == 1 ? other : -1;
}

void remove_neighbour(std::vector<int>& nb, int f) {
  nb.erase(std::remove(nb.begin(), nb.end(), f), nb.end());
}

/// Flips beam (a, b) between faces A and B, if it is an interior beam of two unsplit valence-3
/// joints, the faces stay polygons and C, D are not neighbours already. Returns true when done.
bool flip(Layout& L, Problem& P, const Planes& pl, int a, int b) {
  Joint &Ja = L.joints[a], &Jb = L.joints[b];
  if (Ja.support || Jb.support) return false;
  for (int s = 0; s < 3; ++s)
    if (Ja.plane[s] < 0 || Jb.plane[s] < 0) return false;
  std::vector<int> shared;
  for (int s : Ja.plane)
    if (contains({Jb.plane[0], Jb.plane[1], Jb.plane[2]}, s)) shared.push_back(s);
  if (shared.size() != 2) return false;
  const int A = shared[0], B = shared[1];
  const int C = third_plane(Ja, A, B), D = third_plane(Jb, A, B);
  if (C < 0 || D < 0 || C == D || contains(P.face_neighbours[C], D)) return false;
  if (L.faces[A].size() < 4 || L.faces[B].size() < 4) return false;
  if (slot_of(L.faces[A], a) < 0 || slot_of(L.faces[A], b) < 0 || slot_of(L.faces[B], a) < 0 ||
      slot_of(L.faces[B], b) < 0 || slot_of(L.faces[C], a) < 0 || slot_of(L.faces[D], b) < 0 ||
      slot_of(L.faces[C], b) >= 0 || slot_of(L.faces[D], a) >= 0)
    return false;
  // The new beam runs along C ∩ D; a becomes A ∩ C ∩ D (on A's side), b becomes B ∩ C ∩ D.
  Vec3 w = pl.n[C].cross(pl.n[D]);
  if (!(w.norm() > 1e-9)) return false;
  w.normalize();
  Vec3 ca = Vec3::Zero(), cb = Vec3::Zero();
  for (int j : L.faces[A]) ca += P.x0[j];
  for (int j : L.faces[B]) cb += P.x0[j];
  ca /= static_cast<double>(L.faces[A].size());
  cb /= static_cast<double>(L.faces[B].size());
  if (w.dot(ca - cb) < 0) w = -w;
  const std::vector<int> face_a = L.faces[A], face_b = L.faces[B];
  L.faces[A].erase(L.faces[A].begin() + slot_of(L.faces[A], b));
  L.faces[B].erase(L.faces[B].begin() + slot_of(L.faces[B], a));
  insert_beside(L.faces[C], a, b, face_b);  // b next to a's neighbour in B
  insert_beside(L.faces[D], b, a, face_a);  // a next to b's neighbour in A
  Ja.plane[0] = A, Ja.plane[1] = C, Ja.plane[2] = D;
  Jb.plane[0] = B, Jb.plane[1] = C, Jb.plane[2] = D;
  // Targets: the old beam's midpoint, half a design beam each way along the new beam.
  const Vec3 mid = 0.5 * (P.x0[a] + P.x0[b]);
  const double half = 0.5 * (P.x0[a] - P.x0[b]).norm();
  P.x0[a] = mid + half * w;
  P.x0[b] = mid - half * w;
  remove_neighbour(P.face_neighbours[A], B);
  remove_neighbour(P.face_neighbours[B], A);
  P.face_neighbours[C].push_back(D);
  P.face_neighbours[D].push_back(C);
  return true;
}

/// Flips boundary beam (b, i) between faces A and C: b = Bnd ∩ A ∩ C a boundary joint of two
/// panels, i = A ∩ C ∩ D an interior joint. The third panel D reaches the boundary: b becomes
/// Bnd ∩ A ∩ D, i becomes Bnd ∩ C ∩ D, joined by a new boundary side of D along Bnd (A and C
/// lose a corner each, D gains two). Returns true when done.
bool flip_boundary(Layout& L, Problem& P, const Planes& pl, int b, int i) {
  Joint &Jb = L.joints[b], &Ji = L.joints[i];
  if (Jb.support || Ji.support || Jb.along != 0) return false;
  int fixed = 0, bnd = 0;
  for (int s : Jb.plane)
    if (s < 0) ++fixed, bnd = s;
  for (int s : Ji.plane)
    if (s < 0) return false;
  if (fixed != 1) return false;
  std::vector<int> shared;
  for (int s : Jb.plane)
    if (s >= 0 && contains({Ji.plane[0], Ji.plane[1], Ji.plane[2]}, s)) shared.push_back(s);
  if (shared.size() != 2) return false;
  const int D = third_plane(Ji, shared[0], shared[1]);
  if (D < 0 || slot_of(L.faces[D], b) >= 0 || slot_of(L.faces[D], i) < 0) return false;
  // A and C: b's two panels, either way round (b's new target goes to A's side, i's to C's).
  const int A = shared[0], C = shared[1];
  for (int f : {A, C})
    if (L.faces[f].size() < 4 || slot_of(L.faces[f], b) < 0 || slot_of(L.faces[f], i) < 0)
      return false;
  const Vec3 m = L.fixed_normal[-1 - bnd];
  Vec3 w = m.cross(pl.n[D]);
  if (!(w.norm() > 1e-9)) return false;
  w.normalize();
  // b's neighbour in A other than i (pA): the new b sits on A's side of the old b.
  auto other_neighbour = [&](int f) {
    const auto& face = L.faces[f];
    const int n = static_cast<int>(face.size()), k = slot_of(face, b);
    const int prev = face[(k + n - 1) % n], next = face[(k + 1) % n];
    return prev == i ? next : prev;
  };
  const int pA = other_neighbour(A);
  if (w.dot(P.x0[pA] - P.x0[b]) < 0) w = -w;
  const std::vector<int> face_a = L.faces[A];
  L.faces[A].erase(L.faces[A].begin() + slot_of(L.faces[A], i));
  L.faces[C].erase(L.faces[C].begin() + slot_of(L.faces[C], b));
  insert_beside(L.faces[D], i, b, face_a);  // b next to i's neighbour in A
  Jb.plane[0] = bnd, Jb.plane[1] = A, Jb.plane[2] = D;
  Ji.plane[0] = bnd, Ji.plane[1] = C, Ji.plane[2] = D;
  const double half = 0.5 * (P.x0[b] - P.x0[i]).norm();
  const Vec3 at = P.x0[b];
  P.x0[b] = at + half * w;
  P.x0[i] = at - half * w;
  P.anchor[i] = P.anchor[b];
  remove_neighbour(P.face_neighbours[A], C);
  remove_neighbour(P.face_neighbours[C], A);
  return true;
}

}  // namespace

int flip_collapsed_beams(Layout& L, Problem& P, const Planes& pl, const std::vector<Vec3>& x,
                         int max_flips) {
  std::vector<std::pair<double, int>> candidates;  // (signed length, beam), shortest first
  for (std::size_t e = 0; e < P.beams.size(); ++e) {
    const Beam& B = P.beams[e];
    const double s = B.u.dot(x[B.b] - x[B.a]);
    if (s < P.shortest_allowed) candidates.emplace_back(s, static_cast<int>(e));
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<char> touched(L.joints.size(), 0);
  int flips = 0;
  for (const auto& c : candidates) {
    if (flips >= max_flips) break;
    const Beam B = P.beams[c.second];
    if (touched[B.a] || touched[B.b]) continue;  // one flip per joint per round
    if (flip(L, P, pl, B.a, B.b) || (P.o.boundary_flips && (flip_boundary(L, P, pl, B.a, B.b) ||
                                                            flip_boundary(L, P, pl, B.b, B.a)))) {
      touched[B.a] = touched[B.b] = 1;
      ++flips;
    }
  }
  spdlog::debug("[flat panels] {} of {} short beams flipped", flips, candidates.size());
  return flips;
}

}  // namespace gridshell::flat_detail
