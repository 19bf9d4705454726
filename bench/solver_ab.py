#!/usr/bin/env python3
"""The sparse solver's A/B table (docs/performance.md, "The sparse solver"): the frame, shell and
metric benchmarks and the Aquadom LBA process, for several builds and GRIDSHELL_CHOLESKY
settings, run in rounds (every variant once per round, in turn) so that the machine's load
drift falls on all of them alike. Prints the median wall seconds per case and variant, the
median ratio to the first variant, and the load average before and after.

  python3 bench/solver_ab.py --variant today=/work/main/build \\
      --variant component=build --variant plain=build-noip \\
      --variant plain-simplicial=build-noip:simplicial --rounds 3

A variant is LABEL=BUILD_DIR[:GRIDSHELL_CHOLESKY value] (core/sparse_cholesky.h). --cases picks
some of: frame-linear frame-lba lilium-nonlinear shell-50k shell-5k metric-refined
metric-aquadom aquadom-lba aquadom-nonlinear.
"""
import argparse, json, os, statistics, subprocess, sys, tempfile, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "..", "shared", "data", "surfaces")
BENCH = {  # case: (program, benchmark name)
    "frame-linear": ("frame_bench", "BM_AquadomLinear"),
    "frame-lba": ("frame_bench", "BM_AquadomBuckling"),
    "lilium-nonlinear": ("frame_bench", "BM_LiliumNonlinear"),
    "shell-50k": ("shell_bench", "BM_Shell50K/160/1"),
    "shell-5k": ("shell_bench", "BM_Shell5K/50/1"),
    "metric-refined": ("metric_bench", "BM_DeformRefined/300"),
    "metric-aquadom": ("metric_bench", "BM_AquadomSynthetic/5"),
}
PROCESS = {  # case: gridshell arguments (OUT is replaced by a scratch folder)
    "aquadom-lba": ["analyze", os.path.join(DATA, "aquadom_Vouga.ply"), "--analyze", "buckling"],
    "aquadom-nonlinear": ["analyze", "AQ22/gridshell.obj", "--analyze", "nonlinear",
                          "--single-path"],
}


def load():
    return open("/proc/loadavg").read().split()[0]


def run_bench(build, env, program, name, scratch):
    out = os.path.join(scratch, "bench.json")
    subprocess.run([os.path.join(build, program), f"--benchmark_filter=^{name}(/|$)",
                    f"--benchmark_out={out}", "--benchmark_out_format=json"], env=env,
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    runs = json.load(open(out))["benchmarks"]
    scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}
    return statistics.median(r["real_time"] * scale[r["time_unit"]] for r in runs
                             if r.get("run_type", "iteration") == "iteration")


def run_process(build, env, args, scratch, aq22):
    args = [a.replace("AQ22", aq22) for a in args]
    t0 = time.perf_counter()
    subprocess.run([os.path.join(build, "gridshell"), *args, "--figures", "none", "--quiet",
                    "-o", scratch], env=env, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--variant", action="append", required=True)
    ap.add_argument("--cases", default="frame-linear,frame-lba,shell-50k,metric-refined,"
                    "metric-aquadom,aquadom-lba")
    ap.add_argument("--rounds", type=int, default=3)
    a = ap.parse_args()
    variants = []
    for v in a.variant:
        label, spec = v.split("=", 1)
        build, _, mode = spec.partition(":")
        env = dict(os.environ)
        env.pop("GRIDSHELL_CHOLESKY", None)
        if mode:
            env["GRIDSHELL_CHOLESKY"] = mode
        variants.append((label, os.path.abspath(build), env))
    cases = a.cases.split(",")
    scratch = tempfile.mkdtemp(prefix="solver_ab_")
    aq22 = os.path.join(scratch, "aq22")
    if "aquadom-nonlinear" in cases:
        subprocess.run([os.path.join(variants[0][1], "gridshell"), "design",
                        os.path.join(DATA, "aquadom_Vouga.ply"), "-D", "2", "-A", "2",
                        "--length", "6000", "--analyze", "none", "--figures", "none", "--quiet",
                        "-o", aq22], check=True, stdout=subprocess.DEVNULL)
    times = {(c, v[0]): [] for c in cases for v in variants}
    print(f"load average before: {load()}", flush=True)
    for r in range(a.rounds):
        for case in cases:
            for label, build, env in variants:
                if case in BENCH:
                    t = run_bench(build, env, *BENCH[case], scratch)
                else:
                    t = run_process(build, env, PROCESS[case], os.path.join(scratch, "out"), aq22)
                times[(case, label)].append(t)
                print(f"round {r + 1} {case:17s} {label:22s} {t:8.3f} s  (load {load()})",
                      flush=True)
    print(f"load average after: {load()}")
    labels = [v[0] for v in variants]
    print("\n| case | " + " | ".join(labels) + " |")
    print("|---|" + "---|" * len(labels))
    for case in cases:
        base = times[(case, labels[0])]
        cells = []
        for label in labels:
            t = times[(case, label)]
            ratio = statistics.median(x / y for x, y in zip(t, base))
            cells.append(f"{statistics.median(t):.3f} s" +
                         ("" if label == labels[0] else f" (×{ratio:.2f})"))
        print(f"| {case} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    sys.exit(main())
