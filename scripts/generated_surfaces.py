#!/usr/bin/env python3
"""Eight roof surfaces outside the shared data and the built-ins, for checking a method on
surfaces it was not tuned on (docs/quad_aniso.md, session 12).

    python3 scripts/generated_surfaces.py OUT_DIR

Writes OUT_DIR/NAME.obj (triangles; every boundary vertex becomes a support by default):
  saddle     hyperbolic paraboloid over a 30 x 30 m square, 12 m between high and low corners
  hill       Gaussian bump (7 m) over a disk of radius 18 m
  lplan      vault over an L-shaped 40 x 40 m plan (one quarter removed), with a side wave
  trapezoid  barrel over a trapezoid plan, span 20 m narrowing to 12 m over 36 m
  ring       annular roof (radii 10-24 m, ellipse 1.3:1), height varying around the ring
  blob       three-lobed plan (radius 16 m +/- 25 %), a dome with a superposed wave
  canopy     long wavy canopy, 50 x 14 m
  wave       elliptic plan 40 x 26 m, a dome with a superposed wave
and prints the area of each (the acceptance runs used lengths of about area and area / 2 m).
"""

import math
import sys
from pathlib import Path


def disk_map(u, v):
    """The unit square [0, 1]^2 onto the unit disk (the elliptical grid mapping)."""
    x, y = 2 * u - 1, 2 * v - 1
    return x * math.sqrt(1 - y * y / 2), y * math.sqrt(1 - x * x / 2)


def grid(n, m, point, keep=lambda i, j: True, wrap=False):
    """Vertices point(i / n, j / m) of the kept cells of an n x m grid, two triangles per cell
    (diagonals alternating); with wrap, column n is column 0."""
    index, vertices, faces = {}, [], []

    def vid(i, j):
        if wrap:
            i %= n
        if (i, j) not in index:
            index[(i, j)] = len(vertices)
            vertices.append(point(i / n, j / m))
        return index[(i, j)]

    for i in range(n):
        for j in range(m):
            if not keep(i, j):
                continue
            a, b, c, d = vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)
            faces += [(a, b, c), (a, c, d)] if (i + j) % 2 else [(a, b, d), (b, c, d)]
    return vertices, faces


def area(vertices, faces):
    total = 0.0
    for a, b, c in faces:
        p, q, r = vertices[a], vertices[b], vertices[c]
        u = [q[k] - p[k] for k in range(3)]
        w = [r[k] - p[k] for k in range(3)]
        x = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
        total += 0.5 * math.sqrt(sum(t * t for t in x))
    return total


def hill(u, v):
    x, y = disk_map(u, v)
    return 18 * x, 18 * y, 7 * math.exp(-(18 * 18 * (x * x + y * y)) / 120)


def trapezoid(u, v):
    w = 20 - 8 * u
    return 36 * u, (v - 0.5) * w, 0.45 * w * math.cos(math.pi * (v - 0.5))


def ring(u, v):
    t, r = 2 * math.pi * u, 10 + 14 * v
    return 1.3 * r * math.cos(t), r * math.sin(t), 5 * math.sin(math.pi * v) * (1 + 0.3 * math.cos(2 * t))


def blob(u, v):
    x, y = disk_map(u, v)
    t, r = math.atan2(y, x), math.hypot(x, y)
    radius = 16 * (1 + 0.25 * math.cos(3 * t))
    px, py = radius * r * math.cos(t), radius * r * math.sin(t)
    return px, py, 6 * (1 - r * r) + 1.5 * math.sin(px / 5) * math.cos(py / 7)


def wave(u, v):
    x, y = disk_map(u, v)
    return 20 * x, 13 * y, 5 * (1 - x * x - y * y) + 1.2 * math.sin(3 * x) * math.cos(2 * y)


SURFACES = {
    "saddle": lambda: grid(60, 60, lambda u, v: (30 * u - 15, 30 * v - 15,
                                                 4 + 6 * ((2 * u - 1) ** 2 - (2 * v - 1) ** 2))),
    "hill": lambda: grid(64, 64, hill),
    "lplan": lambda: grid(64, 64, lambda u, v: (40 * u, 40 * v,
                                                6 * math.sin(math.pi * u) * math.sin(math.pi * v)
                                                + 2 * math.sin(2 * math.pi * u)),
                          keep=lambda i, j: not (i >= 32 and j >= 32)),
    "trapezoid": lambda: grid(72, 40, trapezoid),
    "ring": lambda: grid(120, 24, ring, wrap=True),
    "blob": lambda: grid(64, 64, blob),
    "canopy": lambda: grid(100, 28, lambda u, v: (50 * u, 14 * v,
                                                  3 * math.sin(math.pi * v) + 1.5
                                                  * math.sin(3 * math.pi * u) * math.sin(math.pi * v))),
    "wave": lambda: grid(64, 64, wave),
}


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    for name, make in SURFACES.items():
        vertices, faces = make()
        with open(out / f"{name}.obj", "w") as f:
            f.writelines(f"v {x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in vertices)
            f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces)
        print(f"{name}: {len(vertices)} vertices, {len(faces)} triangles, area {area(vertices, faces):.0f} m²")


if __name__ == "__main__":
    main()
