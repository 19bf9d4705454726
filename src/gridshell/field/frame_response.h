#pragma once
/// \file frame_response.h
/// Beyond the paper: a field from the grid-shell's own structural response instead of the
/// stresses of a continuous shell (`design --field frame-energy|frame-mode`).
///
/// A continuous shell carries its load in membrane action; a Voronoi grid-shell (valence-3
/// joints, no triangles) carries much of it in bending, so the shell's stresses are an indirect
/// guide to where its beams work. The frame itself says it directly: the strain energy of a
/// member under the load is the sensitivity of the compliance to that member's stiffness, and
/// its energy in the first buckling mode the sensitivity of λ_LBA (λ = φᵀKφ / −φᵀK_Gφ). Putting
/// more beam length where those energies are high is one step of an optimality-criteria
/// update, taken through the tessellation's density and stretch.
///
/// From per-member values w_e (energies), each joint v gets the tensor
///     T_v = (1 / A_v) Σ_{members e at v} ½ w_e t_e t_eᵀ
/// (t_e the member's unit direction, A_v the joint's tributary area): its size is the energy per
/// unit area around the joint, its principal direction the direction of the members that work
/// most. Every vertex of the surface mesh takes the mean tensor of its three nearest joints, and
/// each triangle the principal values and directions of its vertices' mean, projected onto its
/// plane — a StressField with s1 ≥ s2 ≥ 0 that make_field turns into (u, d, a) like any other.

#include <vector>

#include "gridshell/fem/principal_stress.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell {

/// The response field on `surface` of a grid-shell whose members are the edges of `gridshell`
/// in mesh/topology.h order (the order of analysis/gridshell_frame.h), with one non-negative
/// value per member. Throws Error("frame response", ...) for mismatched sizes or negative or
/// non-finite values.
StressField frame_response_field(const TriMesh& surface, const PolyMesh& gridshell,
                                 const std::vector<double>& member_value);

/// The same field at the listed triangles of `surface` only: entry k is, bit for bit, entry
/// `faces[k]` of the whole field (a triangle's value depends on its own three vertices alone).
/// What a design on a coarsened copy of a fine input reads of it (pipeline/design.h,
/// GivenStress): on a 2 M-triangle input, about 8 000 triangles instead of every one. Throws
/// also for a face id out of range.
StressField frame_response_field(const TriMesh& surface, const std::vector<int>& faces,
                                 const PolyMesh& gridshell,
                                 const std::vector<double>& member_value);

}  // namespace gridshell
