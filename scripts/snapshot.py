#!/usr/bin/env python3
"""Behaviour snapshot for refactoring: runs a fixed set of seeded commands and records, per run,
the bytes of every mesh file and report.json without its timings. Compare two binaries (or one
binary before and after a change):

  python3 scripts/snapshot.py save BEFORE_DIR [--exe build/gridshell]
  python3 scripts/snapshot.py compare BEFORE_DIR [--exe build/gridshell]

`compare` re-runs the set with --exe and lists every file and report value that differs
(exit 1 when anything does). Takes about a minute on 2 cores.
"""
import argparse, hashlib, json, os, shutil, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RUNS = {
    "funicular_stress": "design builtin:funicular:res=20 --cells 120 -D 2 -A 2 --seed 3 --analyze buckling",
    "dome_uniform": "design builtin:dome --cells 80 --field uniform --seed 3 --analyze linear",
    "paraboloid_xy": "design builtin:paraboloid:res=20 --cells 100 --symmetry xy -D 2 -A 2 --seed 2 --analyze linear",
    "court_length": "design builtin:court --length 300 -D 2 -A 3 --seed 4 --analyze buckling",
    "barrel_planarize": "design builtin:barrel --cells 90 -D 2 -A 2 --planarize --seed 5 --analyze none",
    "funicular_objective": "design builtin:funicular:res=16 --cells 50 --objective balanced --seed 2 --analyze buckling",
    "dome_quad": "baseline builtin:dome --kind quad --length 200 --analyze buckling",
    "dome_tri": "baseline builtin:dome --kind tri --length 200 --seed 3 --analyze linear",
    "dome_iso": "baseline builtin:dome --kind voronoi-iso --length 200 --seed 3 --analyze linear",
    "analyze_obj": "analyze @dome_uniform/gridshell.obj --analyze nonlinear",
    "dome_quad_aniso": "baseline builtin:dome --kind quad-aniso --length 200 --seed 3 --analyze linear",
    "dome_sized": "design builtin:dome --cells 60 --size --seed 3",
    "barrel_eurocode": "design builtin:barrel --cells 70 --loads eurocode --seed 2 --analyze nonlinear",
    "funicular_flat": "design builtin:funicular:res=16 --cells 60 -D 2 -A 2 --panels flat --seed 2 --analyze linear",
    "analyze_frame": "analyze @dome_sized/frame.json --analyze buckling",
}
SHELL = os.path.join(ROOT, "..", "shared", "data", "surfaces", "Shell.ply")
if os.path.exists(SHELL):  # the length control's second pass (planarization lengthens the beams)
    RUNS["shell_length_retry"] = (f"design {SHELL} -D 3 -A 3 --length 415 --planarize --seed 1 "
                                  "--analyze none")
MESH_FILES = ("gridshell.obj", "gridshell_raw.obj", "gridshell.ply", "cells.csv", "nodes.csv",
              "beams.csv", "path.csv", "frame.json", "panels.csv", "joints.csv", "modes.csv")


def strip(value):
    """report.json without timings (they differ run to run) and the checkout's own path."""
    if isinstance(value, dict):
        return {k: strip(v) for k, v in value.items()
                if k not in ("timings_s", "seconds") and not k.endswith("_seconds")}
    if isinstance(value, list):
        return [strip(v) for v in value]
    if isinstance(value, str):  # input paths name the checkout: compare them from its root
        return value.replace(ROOT, "<checkout>")
    return value


def run_all(exe, out):
    os.makedirs(out, exist_ok=True)
    record = {}
    for name, cmd in RUNS.items():
        folder = os.path.join(out, name)
        args = [a.replace("@", out + "/") if a.startswith("@") else a for a in cmd.split()]
        p = subprocess.run([exe] + args + ["--quiet", "-o", folder], capture_output=True, text=True)
        entry = {"status": p.returncode}
        for f in MESH_FILES:
            path = os.path.join(folder, f)
            if os.path.exists(path):
                entry[f] = hashlib.sha256(open(path, "rb").read()).hexdigest()
        rep = os.path.join(folder, "report.json")
        if os.path.exists(rep):
            entry["report"] = strip(json.load(open(rep)))
        record[name] = entry
    return record


def diff(a, b, path=""):
    out = []
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            out += diff(a.get(k), b.get(k), f"{path}.{k}" if path else k)
    elif isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b)):
            out += diff(x, y, f"{path}[{i}]")
    elif a != b:
        out.append(f"{path}: {a!r} -> {b!r}")
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mode", choices=["save", "compare"])
    ap.add_argument("dir")
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "gridshell"))
    a = ap.parse_args()
    if a.mode == "save":
        rec = run_all(a.exe, os.path.join(a.dir, "runs"))
        json.dump(rec, open(os.path.join(a.dir, "snapshot.json"), "w"), indent=1)
        print(f"saved {len(rec)} runs to {a.dir}")
        return 0
    before = json.load(open(os.path.join(a.dir, "snapshot.json")))
    with tempfile.TemporaryDirectory() as tmp:
        after = run_all(a.exe, tmp)
    d = diff(before, after)
    for line in d:
        print(line[:300])
    print(f"{len(d)} differences in {len(after)} runs")
    return 1 if d else 0


if __name__ == "__main__":
    sys.exit(main())
