#pragma once
/// \file transfer.h
/// A field computed on one mesh of a surface (e.g. the coarsened analysis surface,
/// mesh/coarsen.h) carried over to another mesh of the same surface (the input): each face of
/// the target takes the values of the source face closest to its centroid, its direction u
/// projected onto the target face's plane. Cost: O(F_source log F_source) for the tree, then
/// O(log F_source) per target face.

#include "gridshell/fem/principal_stress.h"
#include "gridshell/field/field.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell {

/// Per face of `to`: the index of the face of `from` closest to its centroid (CGAL AABB tree;
/// ties broken by the tree, deterministically). `from` must have a non-degenerate triangle.
std::vector<int> nearest_faces(const TriMesh& from, const TriMesh& to);

/// `field` (per face of `from`) per face of `to` (see the file comment). Every array of `field`
/// that is filled is carried over; u and u_raw are projected and normalised (kept as they are
/// where the projection vanishes).
Field transfer_field(const TriMesh& from, const Field& field, const TriMesh& to);
/// The same along `nearest = nearest_faces(from, to)`, for several fields carried between the
/// same two meshes (the tree and the queries once): O(F_to).
Field transfer_field(const Field& field, const std::vector<int>& nearest, const TriMesh& to);

/// `stress` (per face of `from`) per face of `to`, the same way: each face of `to` takes the
/// principal stresses of the face of `from` closest to its centroid, the directions projected
/// onto its plane (d2 made perpendicular to d1 there).
StressField transfer_stress(const TriMesh& from, const StressField& stress, const TriMesh& to);
/// The same along `nearest = nearest_faces(from, to)`.
StressField transfer_stress(const StressField& stress, const std::vector<int>& nearest,
                            const TriMesh& to);

}  // namespace gridshell
