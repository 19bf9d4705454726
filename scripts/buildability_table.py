#!/usr/bin/env python3
"""The buildability figures of docs/buildability.md measured: the default design of each built-in
surface (`gridshell design builtin:NAME --analyze none`) and the baselines on the default surface
at the default design's total length, printed as the Markdown table of that page (without its
column from the benchmark's own script, which is run by hand on the same gridshell.obj files).

  python3 scripts/buildability_table.py [--work DIR]

Runs are resumable: a folder with a report.json is reused.
"""
import argparse, json, os, subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXE = os.path.join(ROOT, "build", "gridshell")
BUILTIN = ["funicular", "paraboloid", "dome", "barrel", "court"]
BASELINES = ["voronoi-iso", "quad", "quad-aniso", "tri"]


def run(work, name, args):
    out = os.path.join(work, name)
    if not os.path.exists(os.path.join(out, "report.json")):
        subprocess.run([EXE] + args + ["--analyze", "none", "--figures", "none", "--quiet",
                                       "-o", out], check=True)
    return json.load(open(os.path.join(out, "report.json")))


def row(label, r):
    b, m = r["buildability"], r["mesh"]
    by = ", ".join(f"{v}: {n}" for v, n in
                   sorted(b["joint_clusters_by_valence"].items(), key=lambda x: int(x[0])))
    return (f"| {label} | {m['faces']} | {m['total_length_m']:.0f} | {b['face_planarity']:.4f} | "
            f"{b['joints']} | {b['joint_clusters']} ({by}) | "
            f"{b['beam_length_similarity']:.3f} | {b['distinct_sections']} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--work", default=os.path.join(ROOT, "results_work", "buildability"))
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    print("| grid-shell | panels | length (m) | face planarity | joints | "
          "joint clusters (by valence) | beam-length similarity | distinct sections |")
    print("|---|---|---|---|---|---|---|---|")
    length = None
    for s in BUILTIN:
        r = run(a.work, f"design_{s}", ["design", f"builtin:{s}"])
        if s == "funicular":
            length = round(r["mesh"]["total_length_m"])
        print(row(f"{s} (default design)" if s == "funicular" else s, r))
    for k in BASELINES:
        r = run(a.work, f"base_{k}",
                ["baseline", "builtin:funicular", "--kind", k, "--length", str(length)])
        print(row(f"funicular: {k}", r))


if __name__ == "__main__":
    main()
