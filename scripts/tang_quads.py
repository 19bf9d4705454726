#!/usr/bin/env python3
"""Recover Tang's quad grid-shell from ../shared/data/surfaces/BritishQuadTang.ply.

The shared file stores each quad of Tang's mesh as four triangles around an extra centre vertex.
Deleting every interior vertex of valence 4 whose four triangles close a fan, and replacing the
fan by the quad of its outer edges, gives back the quad mesh (728 quads) that the paper compares
against. Supports (pure red vertices) are kept; the output is an ASCII PLY with red supports, so
`gridshell analyze OUT.ply` picks them up. The surface is normalised (6.0 x 4.8 m); `--scale 16`
brings it to about the real roof's 97 m x 77 m.

usage: scripts/tang_quads.py [IN.ply] OUT.ply [--scale S]
"""
import sys
from collections import defaultdict


def read_ascii_ply(path):
    with open(path) as f:
        lines = f.read().split("\n")
    if not lines or lines[0].strip() != "ply":
        sys.exit(f"{path}: not a PLY file")
    header, i = [], 1
    while lines[i].strip() != "end_header":
        header.append(lines[i].split())
        i += 1
    i += 1
    if ["format", "ascii", "1.0"] not in header:
        sys.exit(f"{path}: only ascii PLY is handled by this script")
    elements, current = [], None
    for h in header:
        if h[0] == "element":
            current = [h[1], int(h[2]), []]
            elements.append(current)
        elif h[0] == "property":
            current[2].append(h[-1])
    verts, faces = [], []
    for name, count, props in elements:
        rows = [lines[i + k].split() for k in range(count)]
        i += count
        if name == "vertex":
            ix, iy, iz = props.index("x"), props.index("y"), props.index("z")
            has_rgb = "red" in props
            for r in rows:
                red = has_rgb and (int(r[props.index("red")]), int(r[props.index("green")]),
                                   int(r[props.index("blue")])) == (255, 0, 0)
                verts.append(([float(r[ix]), float(r[iy]), float(r[iz])], red))
        elif name == "face":
            for r in rows:
                n = int(r[0])
                faces.append([int(x) for x in r[1:1 + n]])
    return verts, faces


def main(argv):
    args = [a for a in argv if not a.startswith("--")]
    scale = 1.0
    if "--scale" in argv:
        scale = float(argv[argv.index("--scale") + 1])
        args.remove(argv[argv.index("--scale") + 1])
    if len(args) == 1:
        args = ["../shared/data/surfaces/BritishQuadTang.ply"] + args
    if len(args) != 2:
        sys.exit(__doc__)
    verts, faces = read_ascii_ply(args[0])
    edge_faces = defaultdict(int)
    vert_faces = defaultdict(list)
    for fi, f in enumerate(faces):
        for k in range(len(f)):
            a, b = f[k], f[(k + 1) % len(f)]
            edge_faces[(min(a, b), max(a, b))] += 1
            vert_faces[f[k]].append(fi)
    boundary = set()
    for (a, b), n in edge_faces.items():
        if n == 1:
            boundary.update((a, b))
    removed_faces, quads, centres = set(), [], set()
    for v, fs in vert_faces.items():
        if v in boundary or len(fs) != 4 or any(len(faces[f]) != 3 for f in fs):
            continue
        # The outer edge of each triangle, oriented as in the triangle: (next, next-next) of v.
        nxt = {}
        for f in fs:
            t = faces[f]
            k = t.index(v)
            nxt[t[(k + 1) % 3]] = t[(k + 2) % 3]
        if len(nxt) != 4:
            continue
        start = next(iter(nxt))
        loop = [start]
        while nxt[loop[-1]] != start and len(loop) < 5:
            loop.append(nxt[loop[-1]])
        if len(loop) != 4 or any(u in centres for u in loop):
            continue
        centres.add(v)
        removed_faces.update(fs)
        quads.append(loop)
    keep = [f for i, f in enumerate(faces) if i not in removed_faces] + quads
    used = sorted({v for f in keep for v in f})
    new_id = {v: i for i, v in enumerate(used)}
    with open(args[1], "w") as out:
        out.write("ply\nformat ascii 1.0\ncomment Tang's quad mesh recovered by tang_quads.py\n")
        out.write(f"element vertex {len(used)}\nproperty double x\nproperty double y\n"
                  "property double z\nproperty uchar red\nproperty uchar green\n"
                  f"property uchar blue\nelement face {len(keep)}\n"
                  "property list uchar int vertex_indices\nend_header\n")
        for v in used:
            p, red = verts[v]
            rgb = "255 0 0" if red else "192 192 192"
            out.write(f"{p[0] * scale!r} {p[1] * scale!r} {p[2] * scale!r} {rgb}\n")
        for f in keep:
            out.write(f"{len(f)} " + " ".join(str(new_id[v]) for v in f) + "\n")
    n_quads = sum(1 for f in keep if len(f) == 4)
    print(f"{args[1]}: {len(used)} vertices, {len(keep)} faces ({n_quads} quads, "
          f"{len(keep) - n_quads} others), {len(centres)} centre vertices removed")


if __name__ == "__main__":
    main(sys.argv[1:])
