#!/usr/bin/env python3
"""Sized steel by pattern (docs/sizing.md, "Sized steel by pattern").

For each surface: the stress-driven Voronoi design (-D 2 -A 2), then at its total beam length
the isotropic Voronoi (-D 1 -A 1) and the quad and triangle baselines, every one sized with
`--size` (eurocode loads, hot-finished CHS, non-linear level); prints the markdown table.

    python3 scripts/sizing_table.py [--surfaces builtin:funicular builtin:dome ...] [--work DIR]
"""
import argparse
import json
import subprocess
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXE = ROOT / "build" / "gridshell"


def run(args, out):
    t0 = time.time()
    subprocess.run([str(EXE), *args, "--size", "--quiet", "--figures", "none", "-o", str(out)],
                   check=True)
    report = json.loads((out / "report.json").read_text())
    report["_seconds"] = time.time() - t0
    return report


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--surfaces", nargs="+",
                   default=["builtin:funicular", "builtin:dome", "builtin:barrel"])
    p.add_argument("--work", default="sizing_work")
    a = p.parse_args()
    rows = ["| surface | pattern | mass kg | kg/m² | vs isotropic | sections | λ | δ mm "
            "| iterations | s |",
            "|---|---|---|---|---|---|---|---|---|---|"]
    for surface in a.surfaces:
        name = surface.split(":")[-1].split("/")[-1].split(".")[0]
        work = Path(a.work) / name
        work.mkdir(parents=True, exist_ok=True)
        stress = run(["design", surface, "-D", "2", "-A", "2"], work / "stress")
        length = str(stress["mesh"]["total_length_m"])
        results = {
            "Voronoi, isotropic": run(["design", surface, "-D", "1", "-A", "1", "--length", length],
                                      work / "iso"),
            "Voronoi, stress-driven D=A=2": stress,
        }
        for kind in ("quad", "tri"):
            results[kind] = run(["baseline", surface, "--kind", kind, "--length", length],
                                work / kind)
        iso = results["Voronoi, isotropic"]["sizing"]["mass_kg"]
        for pattern, r in results.items():
            s, g = r["sizing"], r["structure"]["governing"]
            rows.append(
                f"| {name} | {pattern} | {s['mass_kg']:.0f}{'' if s['sized'] else ' (not sized)'} "
                f"| {s['mass_kg_per_m2']:.1f} | {100 * (s['mass_kg'] / iso - 1):+.1f} % "
                f"| {s['distinct_sections']} | {g.get('lambda_value') or 0:.2f} "
                f"| {1e3 * g['delta_m']:.0f} | {s['iterations']} | {r['_seconds']:.0f} |")
    print("\n".join(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
