#pragma once
/// \file shell_model_json.h
/// Reading a shell model from MODEL.json (CONTRACT.md): `nodes`, `triangles` (or polygon
/// `faces`, fan-triangulated), `thickness` (m, default 0.1), `materials` (the one named by
/// `"material"`, else the only one; E, nu, density), `supports` (per node, `fix` a list of
/// ux uy uz rx ry rz, or the words "pinned" / "clamped"), `loads`:
///   {"node": i, "force": [fx, fy, fz], "moment": [mx, my, mz]}
///   {"type": "surface",   "q": [qx, qy, qz]}   per unit surface area
///   {"type": "projected", "q": [qx, qy, qz]}   per unit plan area
///   {"type": "pressure",  "p": p}               against the facet normal (extension)
///   {"type": "self_weight", "g": 9.81}
/// Every problem is reported as Error(path, what) naming the offending entry.

#include <filesystem>

#include "gridshell/fem/shell_solver.h"

namespace gridshell::io {

/// True when the file looks like a MODEL.json (extension .json).
bool is_model_json(const std::filesystem::path& path);

/// Reads and validates a shell model.
fem::ShellModel read_shell_model(const std::filesystem::path& path);

}  // namespace gridshell::io
