#!/usr/bin/env python3
"""Measures every speed goal of docs/performance.md and prints its table.

    python3 scripts/performance.py [--build build] [--only NAME,...] [--repeats N] [--long]
                                   [--work /tmp/gridshell_performance]

Each goal is a whole command (`gridshell ...`, wall time and peak memory of the process from
/usr/bin/time) or one case of a Google Benchmark program in bench/ (its own real-time figure).
Whole commands run --repeats times (default 3; goals marked long run once) and report the
median; the machine is noisy (docs/performance.md), so compare binaries by alternating runs in one
sitting, not across days. Goals marked long (sweeps, docs/results.md) run only with --long.
Needs ../shared/data for the shared surfaces; goals that need it are skipped without it.
"""

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT.parent / "shared" / "data"
SURF = DATA / "surfaces"


def goals(work):
    """(name, what, goal seconds, goal MiB or None, anchor text, anchor seconds or None, kind,
    spec, long). kind "cmd": spec is a list of argument lists (setup commands first, the last one
    timed). kind "stage": the same, but the time is one stage of the timed command's
    report.json (in its -o folder): spec[-1] is the dotted key of that time, spec[-2] the
    command.
    kind "bench": spec is (program, benchmark name)."""
    aq = str(SURF / "aquadom_Vouga.ply")
    aq22 = str(work / "aquadom_22")
    return [
        ("default-design", "`gridshell design` on the built-in default surface (objective search "
         "+ non-linear analysis)", 10, None, "paper: 1–10 min per design", 60, "cmd",
         [["design", "-o", str(work / "default"), "--quiet"]], False),
        ("aquadom-design", "Aquadom design, D = A = 3, --length 3898, no analysis", 6, None,
         "paper: 1–10 min per design", 60, "cmd",
         [["design", aq, "-D", "3", "-A", "3", "--length", "3898", "--analyze", "none",
           "--figures", "none", "-o", str(work / "aquadom_33"), "--quiet"]], False),
        ("aquadom-lba", "Aquadom triangulation as a frame (11 748 bars), linear + LBA, 5 modes",
         1.0, None, "CalculiX *BUCKLE, same frame", 42, "cmd",
         [["analyze", aq, "--analyze", "buckling", "-o",
           str(work / "aquadom_lba"), "--quiet"]], False),
        ("aquadom-nonlinear", "non-linear path of the Aquadom design D = A = 2, --length 6000 "
         "(8188 beams), perfect structure", 30, None,
         "paper: over a day per non-linear analysis", 86400, "cmd",
         [["design", aq, "-D", "2", "-A", "2", "--length", "6000", "--analyze", "none",
           "--figures", "none", "-o", aq22, "--quiet"],
          ["analyze", aq22 + "/gridshell.obj", "--analyze", "nonlinear", "--single-path",
           "--figures", "none", "-o", str(work / "aquadom_22_nl"), "--quiet"]], False),
        ("aquadom-stability", "the stability block (report.json structure.timings_s.nonlinear: "
         "perfect path and every imperfect one, both signs) of the Aquadom design -D 2 -A 2 "
         "--length 6000 --analyze nonlinear", 15, None, "paper: over a day per non-linear "
         "analysis", 86400, "stage",
         [["design", aq, "-D", "2", "-A", "2", "--length", "6000", "--analyze", "nonlinear",
           "--figures", "none", "-o", str(work / "aquadom_stability"), "--quiet"],
          "structure.timings_s.nonlinear"], False),
        ("fine-input", "design of a 250 K-triangle input (builtin:paraboloid:res=354), 1000 "
         "cells, linear analysis (the default objective search)", 6, 600, None, None, "cmd",
         [["design", "builtin:paraboloid:res=354", "--cells", "1000", "--analyze", "linear",
           "-o", str(work / "fine"), "--quiet"]], False),
        ("fine-input-one", "the same input, one design (-D 3 -A 3) instead of the default "
         "objective search", 6, 600, None, None, "cmd",
         [["design", "builtin:paraboloid:res=354", "--cells", "1000", "-D", "3", "-A", "3",
           "--analyze", "linear", "--figures", "none", "-o", str(work / "fine_one"),
           "--quiet"]], False),
        ("fine-input-2m", "a 2 M-triangle input (builtin:paraboloid:res=1000), 1000 cells, "
         "linear analysis (the default objective search)", 30, 2048, None, None, "cmd",
         [["design", "builtin:paraboloid:res=1000", "--cells", "1000", "--analyze", "linear",
           "-o", str(work / "fine_2m"), "--quiet"]], False),
        ("fine-input-2m-default", "the same input, the default design (objective search, "
         "300 cells), linear analysis", 20, 2048, None, None, "cmd",
         [["design", "builtin:paraboloid:res=1000", "--analyze", "linear",
           "-o", str(work / "fine_2m_default"), "--quiet"]], False),
        ("real-size-court", "a roof at real size: BritishQuadTang --scale 16 --length 10000 "
         "(96 x 77 m, about 4000 cells; objective search, then both non-linear paths)", 60,
         None, None, None, "cmd",
         [["design", str(SURF / "BritishQuadTang.ply"), "--scale", "16", "--length", "10000",
           "-o", str(work / "real_size_court"), "--quiet"]], False),
        ("sized-default", "`gridshell design --size` on the built-in default surface "
         "(objective search, sizing iteration, non-linear probes and verification)", 15, None,
         None, None, "cmd",
         [["design", "--size", "-o", str(work / "sized_default"), "--quiet"]], False),
        ("studio-300", "studio /api/design, 300 cells, linear + LBA (median of 7)", 1, None,
         None, None, "bench", ("studio_bench", "BM_StudioDesign/300"), False),
        ("studio-1000", "studio /api/design, 1000 cells, linear + LBA (median of 7)", 0.8, None,
         None, None, "bench", ("studio_bench", "BM_StudioDesign/1000"), False),
        ("shell-50k", "shell stress FEM, 50 K triangles (split factorisation)", 2, None,
         None, None, "bench", ("shell_bench", "BM_Shell50K/160/1"), False),
        ("tessellation-aquadom", "Aquadom tessellation, 1200 cells, all threads", 3, None, None,
         None, "bench", ("voronoi_bench", "BM_TessellateAquadom/0"), False),
        ("frame-linear", "Aquadom triangulation as a frame, linear (3 runs)", 1, None,
         "CalculiX, same frame, linear", 18, "bench", ("frame_bench", "BM_AquadomLinear"),
         False),
        ("lilium-nonlinear", "non-linear path of the Lilium triangulation (7547 bars)", 60, None,
         None, None, "bench", ("frame_bench", "BM_LiliumNonlinear"), False),
        ("objective-botanic", "objective search on Botanic (16 designs, linear + LBA)", 60,
         None, None, None, "bench", ("objective_bench", "BM_ObjectiveBotanic"), False),
        ("kit-botanic-1200", "gridshell kit of a 1200-cell Botanic design (D = A = 3; about "
         "2400 printed joints, print plates, rods, panels) at 1:20, 3 mm rods", 30, None, None,
         None, "bench", ("kit_bench", "BM_KitBotanic1200"), False),
        ("sweep-shell", "sweep Shell, D, A in 1..4, 3 repeats, --length 415, non-linear "
         "(48 designs)", 180, None, "paper: 1–10 min per design, over a day per non-linear "
         "analysis", None, "cmd",
         [["sweep", str(SURF / "Shell.ply"), "--D", "1:4", "--A", "1:4", "--repeats", "3",
           "--length", "415", "--analyze", "nonlinear", "-o", str(work / "sweep_shell"),
           "--quiet"]], True),
        ("sweep-botanic", "the same sweep on Botanic, --length 2018", 240, None, None, None,
         "cmd",
         [["sweep", str(SURF / "Botanic.ply"), "--D", "1:4", "--A", "1:4", "--repeats", "3",
           "--length", "2018", "--analyze", "nonlinear", "-o", str(work / "sweep_botanic"),
           "--quiet"]], True),
        ("results-md", "docs/results.md regenerated from scratch (scripts/results.py, 2 jobs; "
         "written to the work folder, not docs/)", 900, None, "≈ 45 min", 2700,
         "script",
         [[sys.executable, str(ROOT / "scripts" / "results.py"), "--exe", "{exe}", "--work",
           str(work / "results_work"), "--out", str(work / "results.md"), "--jobs", "2"]],
         True),
    ]


def run_timed(exe, args):
    """Wall seconds, peak RSS in MiB and CPU seconds (user + system, all threads) of one process
    (exe None: args is the whole command); raises on failure."""
    with tempfile.NamedTemporaryFile("r", suffix=".time") as t:
        cmd = ["/usr/bin/time", "-f", "%e %M %U %S", "-o", t.name] + \
            ([str(exe)] if exe is not None else []) + args
        t0 = time.monotonic()
        p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        wall = time.monotonic() - t0
        if p.returncode != 0:
            raise RuntimeError(f"{' '.join(args)} failed: {p.stderr.strip()[-300:]}")
        fields = Path(t.name).read_text().split()
        return wall, int(fields[-3]) / 1024, float(fields[-2]) + float(fields[-1])


def mib_text(mib, goal_mib):
    """Memory as people read it: MiB below 1 GiB, else GiB; ✗ above the goal."""
    text = f"{mib:.0f} MiB" if mib < 1024 else f"{mib / 1024:.2f} GiB"
    return text + (" ✗" if goal_mib and mib > goal_mib else "")


def report_time(args, key):
    """Seconds under the dotted `key` of report.json in the command's -o folder."""
    value = json.loads((Path(args[args.index("-o") + 1]) / "report.json").read_text())
    for part in key.split("."):
        value = value[part]
    return float(value)


def run_bench(build, program, name):
    # The JSON goes to a file: some programs log to stdout.
    with tempfile.NamedTemporaryFile("r", suffix=".json") as out:
        p = subprocess.run([str(build / program), f"--benchmark_filter=^{name}",
                            f"--benchmark_out={out.name}", "--benchmark_out_format=json"],
                           capture_output=True, text=True)
        if p.returncode != 0:
            raise RuntimeError(f"{program} failed: {p.stderr.strip()[-300:]}")
        rows = json.loads(Path(out.name).read_text())["benchmarks"]
    median = [r for r in rows if r.get("aggregate_name") == "median"]
    rows = median or [r for r in rows if r.get("run_type") == "iteration"]
    r = rows[0]
    scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[r["time_unit"]]
    return r["real_time"] * scale


def needs_data(spec):
    return any(str(DATA) in a or "results.py" in a for args in spec for a in args) \
        if isinstance(spec, list) else \
        spec[0] in ("objective_bench", "voronoi_bench", "frame_bench", "kit_bench")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build"))
    ap.add_argument("--only", default="")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--long", action="store_true",
                    help="also the sweeps and docs/results.md (about 15 minutes)")
    ap.add_argument("--work", default=os.path.join(tempfile.gettempdir(),
                                                   "gridshell_performance"))
    a = ap.parse_args()
    build, work = Path(a.build), Path(a.work)
    work.mkdir(parents=True, exist_ok=True)
    exe = build / "gridshell"
    only = {s for s in a.only.split(",") if s}
    print(f"load average before: {os.getloadavg()[0]:.2f}", file=sys.stderr)
    print("| goal | what | ours: wall (median; runs) | CPU | peak | goal | anchor | anchor / ours |")
    print("|---|---|---|---|---|---|---|---|")
    for (name, what, goal_s, goal_mib, anchor, anchor_s, kind, spec, long) in goals(work):
        if only and name not in only:
            continue
        if long and not a.long and name not in only:
            continue
        if needs_data(spec) and not DATA.is_dir():
            print(f"| {name} | {what} | skipped: no ../shared/data | | | | | |")
            continue
        peak = cpu = ""
        try:
            if kind == "script":  # a whole script from scratch: its work folder emptied first
                args = [x.replace("{exe}", str(exe)) for x in spec[-1]]
                shutil.rmtree(args[args.index("--work") + 1], ignore_errors=True)
                runs = [run_timed(None, args)]
                ours, cpu = runs[0][0], f"{runs[0][2]:.2f} s"
                peak, detail = mib_text(runs[0][1], None), "1 run"
            elif kind in ("cmd", "stage"):
                cmds = spec[:-1] if kind == "stage" else spec
                for setup in cmds[:-1]:
                    run_timed(exe, setup)
                runs = []
                for _ in range(1 if long else a.repeats):
                    wall, mib, cpu_s = run_timed(exe, cmds[-1])
                    if kind == "stage":
                        wall = report_time(cmds[-1], spec[-1])
                    runs.append((wall, mib, cpu_s))
                ours = statistics.median(w for w, _, _ in runs)
                cpu = f"{statistics.median(c for _, _, c in runs):.2f} s" + \
                    (" (process)" if kind == "stage" else "")
                peak = mib_text(max(m for _, m, _ in runs), goal_mib)
                detail = " / ".join(f"{w:.2f}" for w, _, _ in runs)
            else:
                ours = run_bench(build, *spec)
                detail = "bench"
        except RuntimeError as e:
            print(f"| {name} | {what} | failed: {e} | | | | | |")
            continue
        mark = "" if ours <= goal_s else " ✗"
        goal = f"≤ {goal_s:g} s" + (f", ≤ {mib_text(goal_mib, None)}" if goal_mib else "")
        ratio = (f"{anchor_s / ours:.0f}×" if anchor_s / ours >= 10 else
                 f"{anchor_s / ours:.1f}×") if anchor_s else ""
        print(f"| {name} | {what} | {ours:.2f} s{mark} ({detail}) | {cpu} | {peak} | {goal} | "
              f"{anchor or ''} | {ratio} |", flush=True)
    print(f"load average after: {os.getloadavg()[0]:.2f}", file=sys.stderr)


if __name__ == "__main__":
    main()
