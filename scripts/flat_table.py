#!/usr/bin/env python3
"""The flat-panel table of docs/panels.md: free against flat panels on the shared surfaces and
the built-ins.

Runs `gridshell design SURFACE -D D -A A --panels free|flat --analyze buckling` for every case
(two runs at a time at most, under nice 19, into a temporary folder) and prints one Markdown row
per case from the two runs' report.json: whether the flat stage passed (attempt, flips, panels glazed as triangles) or why it
failed, out of plane free → flat, the flat joints' distance to the surface, non-convex panels and
the smallest panel angle (free → flat), λ_LBA free → flat, the flat/free total beam length and
the flat stage's seconds, then the pass count.

    python3 scripts/flat_table.py                       # the 11 cases of docs/panels.md at -D 2 -A 2
    python3 scripts/flat_table.py -D 3 -A 3 --seed 2
    python3 scripts/flat_table.py builtin:funicular:span=30,rise=6 --args="--cells 500"
    python3 scripts/flat_table.py --json out.json       # also every row's numbers, for comparing

British Quad's file is normalised to a 6 m span; it runs at `--scale 16` (96 × 77 m, its real
size, docs/results.md) so that its λ_LBA is meaningful. Stdlib only.
"""
import argparse
import glob
import json
import os
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
# The shared data beside the project (../shared/data, as scripts/results.py reads it).
SHARED = os.path.join(HERE, "..", "..", "shared", "data", "surfaces")
BUILTINS = ["builtin:dome", "builtin:paraboloid", "builtin:barrel", "builtin:funicular",
            "builtin:court"]
# Per surface file: extra arguments (real size).
EXTRA = {"BritishQuadTang": ["--scale", "16"]}
NAMES = {"BritishQuadTang": "British Quad", "Neumunster": "Neumünster",
         "aquadom_Vouga": "Aquadom", "liliumVouga": "Lilium"}
SHARED_ORDER = ["Shell", "Botanic", "Neumunster", "aquadom_Vouga", "liliumVouga",
                "BritishQuadTang"]


def default_cases():
    files = {os.path.splitext(os.path.basename(p))[0]: p
             for p in glob.glob(os.path.join(SHARED, "*.ply"))}
    order = [s for s in SHARED_ORDER if s in files] + sorted(set(files) - set(SHARED_ORDER))
    return [files[s] for s in order] + BUILTINS


def label(surface):
    if surface.startswith("builtin:"):
        return surface[len("builtin:"):]
    stem = os.path.splitext(os.path.basename(surface))[0]
    return NAMES.get(stem, stem)


def run(binary, surface, mode, args, out):
    stem = os.path.splitext(os.path.basename(surface))[0]
    cmd = ["nice", "-n", "19", binary, "design", surface, "-D", str(args.D), "-A", str(args.A),
           "--panels", mode, "--analyze", "buckling", "--seed", str(args.seed), "--figures",
           "none", "--quiet", "-o", out] + EXTRA.get(stem, []) + args.args.split()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    path = os.path.join(out, "report.json")
    if p.returncode != 0 or not os.path.exists(path):
        return {"error": (p.stderr.strip().splitlines() or ["exit %d" % p.returncode])[-1]}
    with open(path) as f:
        return json.load(f)


def numbers(free, flat):
    """The row's numbers (None where a run has no value)."""
    def get(r, *keys):
        for k in keys:
            if not isinstance(r, dict) or k not in r:
                return None
            r = r[k]
        return r

    fp = get(flat, "design", "flat_panels") or {}
    row = {
        "error": flat.get("error") or free.get("error"),
        "panels": get(flat, "mesh", "panels"),
        "attempts": fp.get("attempts"),
        "flips": fp.get("flipped_beams"),
        "triangulated": fp.get("triangulated_panels", 0),
        "failure": fp.get("failure"),
        "oop_free_max": get(free, "mesh", "out_of_plane_max_m"),
        "oop_free_median": get(free, "mesh", "out_of_plane_median_m"),
        "oop_flat": get(flat, "mesh", "out_of_plane_max_m"),
        "surf_max": get(flat, "mesh", "surface_distance_max_m"),
        "surf_mean": get(flat, "mesh", "surface_distance_mean_m"),
        "span": get(flat, "structure", "span_m"),
        "nonconvex_free": get(free, "mesh", "nonconvex_panels"),
        "nonconvex": get(flat, "mesh", "nonconvex_panels"),
        "angle_free": get(free, "mesh", "panel_angle_min_deg"),
        "angle": get(flat, "mesh", "panel_angle_min_deg"),
        "lambda_free": get(free, "structure", "lambda_lba"),
        "lambda_flat": get(flat, "structure", "lambda_lba"),
        "length_free": get(free, "mesh", "total_length_m"),
        "length_flat": get(flat, "mesh", "total_length_m"),
        "stage_s": get(flat, "timings_s", "flat_panels"),
    }
    row["pass"] = row["panels"] == "flat"
    return row


def g(v, digits=3, scale=1.0):
    return "–" if v is None else "%.*g" % (digits, v * scale)


def markdown(name, r):
    if r["error"]:
        return "| %s | error: %s |" % (name, r["error"])
    mm = 1e3
    if r["pass"]:
        extra = []
        if r["attempts"] and r["attempts"] > 1:
            extra.append("attempt %d" % r["attempts"])
        if r["flips"]:
            extra.append("%d flips" % r["flips"])
        if r["triangulated"]:
            extra.append("%d as triangles" % r["triangulated"])
        panels = "**flat**" + (" (%s)" % ", ".join(extra) if extra else "")
        oop = "%s / %s → %s" % (g(r["oop_free_max"], 3, mm), g(r["oop_free_median"], 3, mm),
                               g(r["oop_flat"], 2, mm))
        surf = "%s / %s, %s" % (g(r["surf_max"], 3, mm), g(r["surf_mean"], 3, mm),
                                g(r["span"], 3, 10))
        shape = "%s → %s, %s → %s°" % (g(r["nonconvex_free"]), g(r["nonconvex"]),
                                      g(r["angle_free"]), g(r["angle"], 2))
    else:
        panels = "free: %s" % (r["failure"] or "flat stage failed")
        oop = "%s / %s → –" % (g(r["oop_free_max"], 3, mm), g(r["oop_free_median"], 3, mm))
        surf = shape = "–"
    lf, lt = r["lambda_free"], r["lambda_flat"]
    if r["pass"] and lf and lt:
        lam = ("%s → %s (%+.0f %%)" % (g(lf), g(lt), 100 * (lt / lf - 1))).replace("(-", "(−")
    else:
        lam = g(lf)
    length = ("%.3f" % (r["length_flat"] / r["length_free"])
              if r["pass"] and r["length_free"] and r["length_flat"] else "–")
    return "| %s | %s | %s | %s | %s | %s | %s | %s |" % (
        name, panels, oop, surf, shape, lam, length, g(r["stage_s"], 2))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("surfaces", nargs="*", help="surface files or builtin:NAME[:params] "
                    "(default: the 6 shared surfaces and the 5 built-ins)")
    ap.add_argument("-D", type=float, default=2)
    ap.add_argument("-A", type=float, default=2)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--args", default="", help="more arguments for every run, e.g. '--cells 500'")
    ap.add_argument("--binary", default=os.path.join(HERE, "..", "build", "gridshell"))
    ap.add_argument("--jobs", type=int, default=2, choices=[1, 2])
    ap.add_argument("--flat-only", action="store_true",
                    help="run only the flat designs (no λ or length comparison)")
    ap.add_argument("--json", help="write every row's numbers here")
    ap.add_argument("--free-from", help="take the free designs' numbers from an earlier --json "
                    "of the same cases and settings instead of running them again")
    args = ap.parse_args()
    cases = args.surfaces or default_cases()
    binary = os.path.abspath(args.binary)
    earlier = {}
    if args.free_from:
        with open(args.free_from) as f:
            earlier = json.load(f)
    modes = ["flat"] if args.flat_only or earlier else ["free", "flat"]
    with tempfile.TemporaryDirectory(prefix="flat_table_") as tmp:
        jobs = [(c, m, os.path.join(tmp, "%d_%s" % (i, m)))
                for i, c in enumerate(cases) for m in modes]
        with ThreadPoolExecutor(max_workers=args.jobs) as pool:
            reports = list(pool.map(lambda j: run(binary, j[0], j[1], args, j[2]), jobs))
    by = {(c, m): r for (c, m, _), r in zip(jobs, reports)}
    print("`design SURFACE -D %g -A %g --panels free|flat --analyze buckling --seed %d%s`\n"
          % (args.D, args.A, args.seed, (" " + args.args) if args.args else ""))
    print("| surface | panels | out of plane free max / median → flat (mm) | surface max / mean "
          "(mm), limit | non-convex free → flat, min angle free → flat | λ_LBA free → flat | "
          "length flat/free | stage (s) |")
    print("|---|---|---|---|---|---|---|---|")
    rows = {}
    for c in cases:
        r = numbers(by.get((c, "free"), {}), by[(c, "flat")])
        for k, v in earlier.get(label(c), {}).items():
            if k.endswith("_free") or k.startswith("oop_free"):
                r[k] = v
        rows[c] = r
        print(markdown(label(c), r))
    passed = sum(r["pass"] for r in rows.values())
    within = [c for c, r in rows.items() if r["pass"] and r["lambda_free"] and r["lambda_flat"]
              and abs(r["lambda_flat"] / r["lambda_free"] - 1) <= 0.10]
    angles = [r["angle"] for r in rows.values() if r["pass"] and r["angle"] is not None]
    print("\npassing: %d of %d; λ_LBA within 10 %%: %d (%s); smallest angle of a passing design: "
          "%s°" % (passed, len(rows), len(within), ", ".join(label(c) for c in within) or "none",
                   g(min(angles), 2) if angles else "–"))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({label(c): r for c, r in rows.items()}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
