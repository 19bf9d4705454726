#!/usr/bin/env python3
"""The acceptance table of `baseline --kind quad-aniso` (docs/quad_aniso.md).

    python3 scripts/quad_aniso_stats.py [--exe build/gridshell] [--work quad_aniso_work]
                                        [--jobs 2] [--only NAME,...] [--settings 3x3,1x1,2x4]
                                        [--fresh] [--surface NAME=PATH:L1,L2 ...]

Runs `gridshell baseline SURFACE --kind quad-aniso -D D -A A --length L --analyze none` for the
six shared surfaces (../shared/data, skipped when absent) and the built-in surfaces, at each
(D, A) setting and each surface's lengths (plus any --surface given: a mesh file of your own at
the lengths listed; with --surface and no --only, only those), and prints a Markdown table of the figures of
report.json's `quad_aniso` block against its targets:

  valence 4 >= 85 % and quads >= 85 % of the interior, every face simple, shortest beam >= 10 %
  of the median, length within 5 %; where a >= 2, >= 70 % of beams within 15 deg of u or u-perp;
  median aspect >= 1.5 where a >= 2.5 (A > 1); median aspect of all quads <= 1.2 at (1, 1).
Two more checks count as misses though the issue does not name them: no sliver panel (< 2 % of
the median area) and no overlap (beams that cross, a joint inside a panel: mesh/overlaps.h).
The column "spacing ×" is the 10th–90th percentile of the lattice's spacing factor on M′
(QuadAnisoOptions::integrable_scale: how far the cells depart from the sizes d asks for).

A run whose report.json exists under --work is not repeated (--fresh deletes --work first).
The last line counts the rows that meet every target. Exit 0 unless a run fails.
"""

import argparse
import concurrent.futures
import json
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SURF = ROOT.parent / "shared" / "data" / "surfaces"

# name, input arguments, lengths (m). The shared surfaces at the paper's lengths (British Quad at
# real scale, Lilium at its Voronoi row's length) and at about half; the built-ins at two sizes.
SHARED = [
    ("Shell", ["Shell.ply"], [415, 200]),
    ("Neumunster", ["Neumunster.ply"], [975, 500]),
    ("Botanic", ["Botanic.ply"], [2018, 1000]),
    ("Aquadom", ["aquadom_Vouga.ply"], [3898, 2000]),
    ("Lilium", ["liliumVouga.ply"], [1165, 600]),
    ("British Quad", ["BritishQuadTang.ply", "--scale", "16"], [5260, 2600]),
]
BUILTIN = [
    ("dome", ["builtin:dome"], [1200, 600]),
    ("funicular", ["builtin:funicular"], [1200, 600]),
    ("paraboloid", ["builtin:paraboloid"], [1200, 600]),
    ("barrel", ["builtin:barrel"], [1200, 600]),
    ("court", ["builtin:court"], [1200, 600]),
]


def run(exe, work, name, args):
    out = work / name
    report = out / "report.json"
    if not report.exists():
        if out.exists():
            shutil.rmtree(out)
        cmd = [str(exe), "baseline"] + args + ["--analyze", "none", "--figures", "none",
                                               "--quiet", "--threads", "1", "-o", str(out)]
        t = time.time()
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode != 0:
            print(f"FAILED {name}: {' '.join(cmd)}\n{p.stderr.strip()}", file=sys.stderr)
            return None, 0
        (out / "seconds.txt").write_text(f"{time.time() - t:.2f}\n")
    seconds = float((out / "seconds.txt").read_text()) if (out / "seconds.txt").exists() else 0
    return json.loads(report.read_text()), seconds


def pct(x):
    return f"{100 * x:.1f} %"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--exe", default=str(ROOT / "build" / "gridshell"))
    ap.add_argument("--work", default=str(ROOT / "quad_aniso_work"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", help="comma-separated surface names")
    ap.add_argument("--settings", default="3x3,1x1,2x4", help="(D, A) pairs as DxA, comma-separated")
    ap.add_argument("--lengths", type=int, default=2, help="how many of each surface's lengths")
    ap.add_argument("--fresh", action="store_true")
    ap.add_argument("--surface", action="append", default=[],
                    help="NAME=PATH:L1[,L2]: a surface file of your own at these lengths (m)")
    a = ap.parse_args()
    exe, work = Path(a.exe), Path(a.work)
    if a.fresh and work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True, exist_ok=True)
    surfaces = (SHARED if SURF.is_dir() else []) + BUILTIN
    if not SURF.is_dir():
        print(f"{SURF} is absent: built-in surfaces only", file=sys.stderr)
    extra = []
    for spec in a.surface:
        name, _, rest = spec.partition("=")
        path, _, lengths = rest.rpartition(":")
        if not name or not path or not lengths:
            sys.exit(f"--surface {spec}: expected NAME=PATH:L1[,L2]")
        extra.append((name, [str(Path(path).resolve())], [int(x) for x in lengths.split(",")]))
    if extra:
        surfaces = extra if not a.only else surfaces + extra
    if a.only:
        keep = set(a.only.split(","))
        surfaces = [s for s in surfaces if s[0] in keep]
    settings = [tuple(int(x) for x in s.split("x")) for s in a.settings.split(",")]
    jobs = []
    for name, args, lengths in surfaces:
        if not args[0].startswith("builtin:") and not Path(args[0]).is_absolute():
            args = [str(SURF / args[0])] + args[1:]
        for L in lengths[:a.lengths]:
            for D, A in settings:
                key = f"{name.lower().replace(' ', '_')}_{D}x{A}_{L}"
                jobs.append((key, (name, D, A, L), args + ["--kind", "quad-aniso", "-D", str(D),
                                                           "-A", str(A), "--length", str(L)]))
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        futures = [(key, meta, pool.submit(run, exe, work, key, args))
                   for key, meta, args in jobs]
        results = [(key, meta, f.result()) for key, meta, f in futures]

    print("| Surface | (D, A) | L (m) | joints | faces | valence 4 | quads | non-simple / overlaps | "
          "min/median | length | aligned (beams) | aspect (quads) | aspect (all) | spacing × | "
          "covered | time (s) | misses |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    met = failed = 0
    for key, (name, D, A, L), (rep, seconds) in results:
        if rep is None:
            failed += 1
            print(f"| {name} | ({D}, {A}) | {L} | failed | | | | | | | | | | | | | |")
            continue
        q, m = rep["quad_aniso"], rep["mesh"]
        length = m["total_length_m"] / L - 1
        miss = []
        if q["valence4_share"] < 0.85:
            miss.append("valence")
        if q["quad_share"] < 0.85:
            miss.append("quads")
        if q["non_simple_faces"] > 0:
            miss.append("simple")
        if q.get("overlaps", 0) > 0:  # not a target of the issue: beams crossing, panels stacked
            miss.append("overlap")
        if q["min_edge_ratio"] < 0.10:
            miss.append("short beam")
        if q.get("min_area_ratio", 1) < 0.02:  # not a target of the issue: a sliver panel
            miss.append("sliver")
        if abs(length) > 0.05:
            miss.append("length")
        if q["strong_beams"] > 0 and q["aligned_share"] < 0.70:
            miss.append("aligned")
        if A >= 2.5 and q["aspect_quads"] > 0 and q["median_aspect"] < 1.5:
            miss.append("aspect")
        if D == 1 and A == 1 and q["median_aspect_all"] > 1.2:
            miss.append("aspect (1, 1)")
        met += not miss
        aligned = (f"{pct(q['aligned_share'])} ({q['strong_beams']})"
                   if q["strong_beams"] else "–")
        aspect = (f"{q['median_aspect']:.2f} ({q['aspect_quads']})" if q["aspect_quads"] else "–")
        spacing = (f"{q['spacing_factor_p10']:.2f}–{q['spacing_factor_p90']:.2f}"
                   if "spacing_factor_p10" in q else "–")
        covered = pct(q["coverage"]) if "coverage" in q else "–"
        print(f"| {name} | ({D}, {A}) | {L} | {m['vertices']} | {m['faces']} | "
              f"{pct(q['valence4_share'])} | {pct(q['quad_share'])} | {q['non_simple_faces']} / "
              f"{q.get('overlaps', '–')} | "
              f"{q['min_edge_ratio']:.2f} | {100 * length:+.1f} % | {aligned} | {aspect} | "
              f"{q['median_aspect_all']:.2f} | {spacing} | {covered} | {seconds:.1f} | "
              f"{', '.join(miss) or '–'} |")
    print(f"\n{met} of {len(results)} runs meet every target"
          + (f"; {failed} failed" if failed else "") + ".")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
