"""Point supports for docs/results.md (imported by scripts/results.py).

The paper's Shell and Paraboloid "rest on a small number of points" (its tuning section), while
the shared Shell.ply marks all 80 boundary vertices red and the built-in paraboloid is supported
on its whole boundary. This module writes the `--supports FILE.json` files that put them on a
few points instead, and lists the runs of section 1c (Table 1 rows under both support choices).

- Shell: the four lowest points of its boundary (z = -1.53 m at the middles of the four sides
  of its 10 × 10 m plan; the corners rise to +1.53 m), each with its two neighbours along the
  boundary (0.5 m either side): 12 surface vertices, so a few joints of any grid lie on them.
- Paraboloid: the built-in `z = rise (1 - (x² + y²) / (2 h²))` over a square touches z = 0 only
  at its four corners, which are where such a shell stands; each corner with its two boundary
  neighbours (span / res either side): 12 surface vertices.
"""

import json
from pathlib import Path

# The paper's Paraboloid (Table 1): Voronoi (4, 2), 1424 vertices, 745 faces, 2064 edges,
# 2156 m, lambda 6.59, delta 27.22 mm. Its dimensions are not given; the built-in's proportions
# (rise = span / 5) at a span of 40 m give about the paper's 745 cells at the paper's 2156 m.
PARABOLOID_SPAN, PARABOLOID_RISE, PARABOLOID_RES = 40, 8, 32
PARABOLOID = (f"builtin:paraboloid:span={PARABOLOID_SPAN},rise={PARABOLOID_RISE},"
              f"res={PARABOLOID_RES}")
PARABOLOID_LENGTH = 2156.0
PARABOLOID_DA = (4, 2)


def read_ascii_ply(path):
    """Vertex positions and faces of an ASCII PLY file (Shell.ply)."""
    lines = Path(path).read_text().splitlines()
    nv = nf = 0
    i = 0
    while lines[i].strip() != "end_header":
        p = lines[i].split()
        if p[:2] == ["element", "vertex"]:
            nv = int(p[2])
        elif p[:2] == ["element", "face"]:
            nf = int(p[2])
        i += 1
    i += 1
    V = [tuple(float(x) for x in lines[i + k].split()[:3]) for k in range(nv)]
    F = []
    for line in lines[i + nv:i + nv + nf]:
        q = line.split()
        F.append([int(x) for x in q[1:1 + int(q[0])]])
    return V, F


def boundary_loops(F):
    """The boundary loops of a polygon mesh, each as an ordered list of vertex ids."""
    count = {}
    for f in F:
        for a, b in zip(f, f[1:] + f[:1]):
            e = (min(a, b), max(a, b))
            count[e] = count.get(e, 0) + 1
    adj = {}
    for (a, b), c in count.items():
        if c == 1:
            adj.setdefault(a, []).append(b)
            adj.setdefault(b, []).append(a)
    seen, loops = set(), []
    for s in sorted(adj):
        if s in seen:
            continue
        loop, prev, cur = [s], None, s
        seen.add(s)
        while True:
            nxt = [x for x in adj[cur] if x != prev and x not in seen]
            if not nxt:
                break
            prev, cur = cur, nxt[0]
            loop.append(cur)
            seen.add(cur)
        loops.append(loop)
    return loops


def shell_point_supports(ply):
    """The lowest boundary points of Shell.ply (local minima of z along its boundary loop, within
    1 mm of the lowest), each with its two boundary neighbours."""
    V, F = read_ascii_ply(ply)
    (loop,) = boundary_loops(F)
    n = len(loop)
    zmin = min(V[v][2] for v in loop)
    ids = set()
    for k, v in enumerate(loop):
        z = V[v][2]
        if z <= zmin + 1e-3 and z <= V[loop[k - 1]][2] and z <= V[loop[(k + 1) % n]][2]:
            ids.update((loop[k - 1], v, loop[(k + 1) % n]))
    return sorted(ids)


def paraboloid_corner_supports(res=PARABOLOID_RES):
    """The built-in paraboloid's four corners and their boundary neighbours (its vertex (i, j) is
    j (res + 1) + i, surfaces/builtin.cpp)."""
    ids = set()
    for ci in (0, res):
        for cj in (0, res):
            di, dj = (1 if ci == 0 else -1), (1 if cj == 0 else -1)
            for i, j in ((ci, cj), (ci + di, cj), (ci, cj + dj)):
                ids.add(j * (res + 1) + i)
    return sorted(ids)


def write_supports(path, ids):
    path = Path(path)
    if not path.exists():
        path.write_text(json.dumps({"supports": ids}) + "\n")
    return path


def support_variants(work, shell_ply):
    """(name, label, surface args, (D, A), length, paper (lambda, delta) or None) of section 1c
    and of the point-supported sweeps."""
    shell_pts = write_supports(work / "supports_shell_points.json",
                               shell_point_supports(shell_ply))
    para_pts = write_supports(work / "supports_paraboloid_corners.json",
                              paraboloid_corner_supports())
    return [
        ("shell_points", "Shell, 4 low points", [str(shell_ply), "--supports", str(shell_pts)],
         (3, 3), 415.0, (3.05, 46.65)),
        ("paraboloid_points", "Paraboloid, 4 corners", [PARABOLOID, "--supports", str(para_pts)],
         PARABOLOID_DA, PARABOLOID_LENGTH, (6.59, 27.22)),
        ("paraboloid_boundary", "Paraboloid, whole boundary",
         [PARABOLOID, "--supports", "boundary"], PARABOLOID_DA, PARABOLOID_LENGTH, (6.59, 27.22)),
    ]


BFIELD_LABEL = {"shell": "Shell, 4 low points, field of the boundary-pinned shell",
                "paraboloid": "Paraboloid, 4 corners, field of the boundary-pinned shell"}


def variant_jobs(variants, analyze, bfield=None):
    """Section 1c's runs: the Voronoi design at the paper's (D, A) and the comparison grids, all at
    the paper's length, for each support variant; on points, also the design whose field comes
    from the shell pinned on its whole boundary (bfield: surface → BLK file)."""
    jobs = []
    for name, _, args, (D, A), length, _ in variants:
        size = ["--length", f"{length:.0f}", "--analyze", analyze]
        jobs.append((f"{name}_voronoi", ["design"] + args + ["-D", str(D), "-A", str(A)] + size))
        field = (bfield or {}).get(name.split("_")[0])
        if field and name.endswith("_points"):
            jobs.append((f"{name}_voronoi_bfield", ["design"] + args +
                         ["-D", str(D), "-A", str(A), "--field", str(field)] + size))
        for kind in ("voronoi-iso", "quad", "tri"):
            jobs.append((f"{name}_{kind}", ["baseline"] + args + ["--kind", kind] + size))
    return jobs


# The paper's Table 1 rows of the point-supported surfaces: vertices, faces, edges, length (m).
PAPER_COUNTS = {"shell": (988, 477, 1441, 415), "paraboloid": (1424, 745, 2064, 2156)}


def supports_section(rows, variants, fmt):
    """Section 1c: markdown lines and, per variant, (label, {structure: row}) for the claims."""
    md = ["## 1c. Point supports: the paper's Shell and Paraboloid", "",
          "The paper's tuning section says Shell and Paraboloid \"rest on a small number of "
          "points\"; its Table 1 has one row for each (Voronoi only, no comparison grid). Here "
          "both are designed and analysed on a few points and, for the paraboloid, also on its "
          "whole boundary (Shell on its whole boundary is section 1). Point supports are "
          "`--supports FILE.json` files written by `scripts/results_supports.py`: Shell.ply's "
          "four lowest boundary vertices (z = −1.53 m, the middles of the sides of its 10 × 10 m "
          "plan) and the built-in paraboloid's four corners (z = 0), each with its two "
          "neighbours along the boundary — 12 surface vertices; a grid's joints on the boundary "
          "between two of them are pinned (the `supports` column). The supports are those of "
          "the shell analysis that gives the stress field too; the paper pinned the whole "
          "boundary for that analysis, which the row \"field of the boundary-pinned shell\" "
          "does (`gridshell stress --supports boundary`, its stresses as a `--field` file). Paraboloid: `" + PARABOLOID + "` (the paper gives no "
          "dimensions; at 40 m span the paper's 2156 m gives about its 745 cells), (D, A) = "
          f"{PARABOLOID_DA}, all rows at the paper's length. Same frame as section 1; λ = "
          "non-linear (λ_LBA in brackets).", "",
          "| Surface, supports | Structure | Vertices | Faces | Edges | Length (m) | vs target | "
          "λ (λ_LBA) | δ (mm) | supports | paper: λ, δ (mm) |",
          "|---|---|---|---|---|---|---|---|---|---|---|"]
    groups = []
    for name, label, _, (D, A), length, paper in variants:
        group = {}
        counts = PAPER_COUNTS[name.split("_")[0]]
        md.append(f"| {label} | *paper: Voronoi ({D}, {A})* | {counts[0]} | {counts[1]} | "
                  f"{counts[2]} | {counts[3]} | | {paper[0]:g} | {paper[1]:g} | | |")
        for key, structure in (("voronoi", f"voronoi ({D}, {A})"),
                               ("voronoi_bfield", f"voronoi ({D}, {A}), field of the "
                                "boundary-pinned shell"), ("voronoi-iso", "voronoi-iso"),
                               ("quad", "quad (isotropic)"), ("tri", "tri")):
            r = rows.get(f"{name}_{key}")
            if r is None and key == "voronoi_bfield":
                continue
            if r is None:
                md.append(f"| {label} | {structure} | failed | | | | | | | | |")
                continue
            group[key] = r
            dev = (r["length"] / length - 1) * 100
            md.append(f"| {label} | {structure} | {fmt(r['vertices'])} | {fmt(r['faces'])} | "
                      f"{fmt(r['edges'])} | {fmt(r['length'])} | {dev:+.1f} % | "
                      f"{fmt(r['lambda'])} ({fmt(r['lambda_lba'])}) | {fmt(r['delta_mm'])} | "
                      f"{fmt(r.get('supports'))} | |")
        groups.append((label, group))
    md.append("")
    return md, groups


# ---------------------------------------------------------------------------------------------
# The paper's combination: the stress field of the shell pinned on its whole boundary, the
# grid-shell standing on a few points (`--field FILE` with `--supports FILE.json`).


def paraboloid_mesh(span=PARABOLOID_SPAN, rise=PARABOLOID_RISE, n=PARABOLOID_RES):
    """The built-in paraboloid's vertices and triangles, in its own order (surfaces/builtin.cpp
    make_grid)."""
    h = span / 2
    V = []
    for j in range(n + 1):
        for i in range(n + 1):
            x, y = -h + span * i / n, -h + span * j / n
            V.append((x, y, rise * (1 - (x * x + y * y) / (2 * h * h))))
    F = []
    for j in range(n):
        for i in range(n):
            a, b = j * (n + 1) + i, j * (n + 1) + i + 1
            c, d = (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i
            if (2 * i + 1 < n) == (2 * j + 1 < n):
                F += [[a, b, c], [a, c, d]]
            else:
                F += [[a, b, d], [b, c, d]]
    return V, F


def stress_to_blk(stress_csv, V, F, out):
    """`gridshell stress`'s per-triangle principal stresses as a BLK field file (one point per
    triangle, at its centroid; field/field_io.h): what `--field FILE` reads."""
    import csv
    lines = ["x y z s1 v1x v1y v1z s2 v2x v2y v2z"]
    with open(stress_csv) as f:
        rows = list(csv.DictReader(f))
    if len(rows) != len(F):
        raise ValueError(f"{stress_csv}: {len(rows)} triangles, the surface has {len(F)}")
    for r, tri in zip(rows, F):
        c = [sum(V[v][k] for v in tri) / 3 for k in range(3)]
        lines.append(" ".join(f"{x:.9g}" for x in c + [float(r["s1"]), float(r["d1x"]),
                                                          float(r["d1y"]), float(r["d1z"]),
                                                          float(r["s2"]), float(r["d2x"]),
                                                          float(r["d2y"]), float(r["d2z"])]))
    Path(out).write_text("\n".join(lines) + "\n")
    return Path(out)


def boundary_fields(runner, shell_ply):
    """BLK fields of Shell and the paraboloid pinned on their whole boundary: name → path."""
    out = {}
    for name, surface, mesh in (("shell", str(shell_ply), lambda: read_ascii_ply(shell_ply)),
                                ("paraboloid", PARABOLOID, paraboloid_mesh)):
        blk = runner.work / f"field_{name}_boundary.blk"
        if not blk.exists():
            rep = runner.run(f"stress_{name}_boundary", ["stress", surface, "--supports",
                                                         "boundary"])
            if rep is None:
                continue
            V, F = mesh()
            stress_to_blk(runner.work / f"stress_{name}_boundary" / "stress.csv", V, F, blk)
        out[name] = blk
    return out
