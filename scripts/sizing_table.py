#!/usr/bin/env python3
"""Sized steel and buildability by pattern (docs/results.md, section 8).

For each surface, five designs, every one sized with `--size` (which implies `--loads
eurocode`: glass 0.4 kN/m², snow s_k 1.0 kN/m² with its drifted arrangements; hot-finished CHS
of EN 10210-2; non-linear level; λ ≥ 1; δ ≤ span/300), `--figures none --quiet`, 300 cells:

1. the stress-driven Voronoi: `design SURFACE --size` — its objective search (`--objective
   balanced`, the default) picks the field settings (D, A, conventions) before the sizing;
   `--stress-args "-D 2 -A 2"` replaces the search by fixed settings;
2. at that design's total beam length L (`--length L`): the isotropic Voronoi
   (`design -D 1 -A 1 --length L --size`);
3. the comparison grids `baseline --kind quad | quad-aniso | tri --length L --size`.

Each run writes its folder WORK/SURFACE/PATTERN (report.json and the rest, plus run.json: the
command, wall and CPU seconds — user+sys of the child, the figure comparable under load). A run
whose report.json and run.json exist is not repeated, so the script can be resumed. A surface
whose runs together take longer than --budget seconds of wall time is stopped there and listed
as not measured. Then it writes docs/results.md's section 8 (to stdout, or spliced into a file
with --splice): how it was made, the masses, the buildability, what was not measured, the
consistency check of every `sized: true` report (utilisation ≤ 1, λ ≥ λ_min, δ ≤ limit; a
report that breaks one is also named on stderr) and, per surface and overall, which pattern is
lightest and by how much.

    nice -n 19 python3 scripts/sizing_table.py                 # run what is missing, print
    python3 scripts/sizing_table.py --no-run --splice docs/results.md
    python3 scripts/sizing_table.py --surfaces builtin:dome "FILE.ply --scale 16" --work DIR
"""
import argparse
import json
import resource
import shlex
import subprocess
import sys
import statistics
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXE = ROOT / "build" / "gridshell"
SHARED = str(ROOT.parent / "shared" / "data" / "surfaces") + "/{}.ply"  # ../shared beside the project
SURFACES = (["builtin:funicular"]
            + [SHARED.format(n) for n in ("Shell", "Neumunster", "Botanic", "aquadom_Vouga",
                                          "liliumVouga")]
            + [SHARED.format("BritishQuadTang") + " --scale 16"]
            + ["builtin:dome", "builtin:barrel", "builtin:paraboloid", "builtin:court"])
nan = float("nan")
PATTERNS = ["stress", "iso", "quad", "quad-aniso", "tri"]
LABEL = {"stress": "stress-driven Voronoi", "iso": "isotropic Voronoi", "quad": "quad",
         "quad-aniso": "quad-aniso", "tri": "triangle"}


NAMES = {"aquadom_Vouga": "Aquadom", "liliumVouga": "Lilium", "BritishQuadTang": "British Quad"}


def surface_name(surface):
    """Surface spec ("FILE [options]" or "builtin:NAME") → the folder name."""
    return shlex.split(surface)[0].split(":")[-1].split("/")[-1].split(".")[0]


def display_name(surface):
    name = surface_name(surface)
    return NAMES.get(name, name if "builtin:" not in surface else f"{name} (built-in)")


def run(args, out, timeout):
    """One sized gridshell run into `out`; returns its report (None when it timed out)."""
    report, meta = out / "report.json", out / "run.json"
    if report.exists() and meta.exists():
        return json.loads(report.read_text()) | {"_run": json.loads(meta.read_text())}
    cmd = [str(EXE), *args, "--size", "--quiet", "--figures", "none", "-o", str(out)]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.time()
    try:
        subprocess.run(cmd, check=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    info = {"command": shlex.join(["gridshell", *cmd[1:]]), "wall_s": time.time() - t0,
            "cpu_s": cpu}
    meta.write_text(json.dumps(info, indent=1))
    return json.loads(report.read_text()) | {"_run": info}


def measure(surface, work, stress_args, budget):
    """The five runs of one surface; returns {pattern: report} and a note when cut short."""
    work.mkdir(parents=True, exist_ok=True)
    results, spent = {}, 0.0
    surface, *extra = shlex.split(surface)

    def step(pattern, args):
        nonlocal spent
        left = budget - spent
        if left <= 0:
            return False
        r = run(args, work / pattern, left)
        if r is None:
            return False
        spent += r["_run"]["wall_s"]
        results[pattern] = r
        return True

    if not step("stress", ["design", surface, *extra, *stress_args]):
        return results, f"stress-driven design over the {budget:.0f} s budget"
    length = f"{results['stress']['mesh']['total_length_m']:.3f}"
    if not step("iso", ["design", surface, *extra, "-D", "1", "-A", "1", "--length", length]):
        return results, f"runs over the {budget:.0f} s budget"
    for kind in ("quad", "quad-aniso", "tri"):
        if not step(kind, ["baseline", surface, *extra, "--kind", kind, "--length", length]):
            return results, f"runs over the {budget:.0f} s budget"
    return results, ""


def label(pattern, r):
    if pattern != "stress":
        return LABEL[pattern]
    f = r["design"]["field"]
    extra = "".join(f", {f[k]}" for k in ("stress_measure", "stretch", "density")
                    if f.get(k) not in (None, "magnitude", "along", "rising"))
    return f"{LABEL[pattern]} (D {f['D']:g}, A {f['A']:g}{extra})"


def verdict(s):
    if s.get("sized"):
        return "yes"
    return "**no**: " + str(s.get("failure") or s.get("failing_check") or "?")


def mass_row(name, pattern, r, iso):
    s, st, m = r["sizing"], r["structure"], r["mesh"]
    g = st["governing"]
    both = s.get("sized") and iso is not None and iso["sizing"].get("sized")
    vs = f"{100 * (s['mass_kg'] / iso['sizing']['mass_kg'] - 1):+.1f} %" if both else "–"
    util, lam, _ = worst(r)
    return (f"| {name} | {label(pattern, r)} | {verdict(s)} | {m['total_length_m']:.0f} "
            f"| {kg(s['mass_kg'])} | {s['mass_kg_per_m2']:.1f} | {vs} "
            f"| {s['distinct_sections']} | {util if util is not None else nan:.2f} "
            f"| {lam if lam is not None else nan:.2f} "
            f"| {1e3 * g['delta_m']:.0f} / {1e3 * st['delta_limit_m']:.0f} | {s['iterations']} "
            f"| {r['_run']['wall_s']:.0f} | {r['_run']['cpu_s']:.0f} |")


def build_row(name, pattern, r):
    b = r["buildability"]
    valence = ", ".join(f"{k}: {v}" for k, v in sorted(b["joint_clusters_by_valence"].items()))
    return (f"| {name} | {label(pattern, r)} | {b['face_planarity']:.3f} | {b['joints']} "
            f"| {b['joint_clusters']} ({valence}) | {b['beam_length_similarity']:.3f} "
            f"| {b['distinct_sections']} |")


def kg(x):
    return f"{x:,.0f}".replace(",", " ")


def surface_statement(name, results):
    """One plain line: which pattern is lightest and by how much; the buildability leaders."""
    sized = {k: r for k, r in results.items() if r["sizing"].get("sized")}
    failed = [f"the {LABEL[k]} not sized ({verdict(r['sizing'])[8:]})"
              for k, r in results.items() if k not in sized]
    if not sized:
        return f"- **{name}**: no pattern sized; " + "; ".join(failed) + "."
    mass = {k: r["sizing"]["mass_kg"] for k, r in sized.items()}
    order = sorted(mass, key=mass.get)
    best, ref = order[0], mass.get("iso")
    line = f"- **{name}**: lightest: {LABEL[best]}, {kg(mass[best])} kg"
    if len(order) > 1:
        line += f", {100 * (1 - mass[best] / mass[order[1]]):.1f} % below the next " \
                f"({LABEL[order[1]]}, {kg(mass[order[1]])} kg)"
    if ref and best != "iso" and (len(order) < 2 or order[1] != "iso"):
        line += f" and {100 * (1 - mass[best] / ref):.1f} % below the isotropic Voronoi"
    if ref and "stress" in mass:
        line += f"; the stress-driven Voronoi {100 * (mass['stress'] / ref - 1):+.1f} % " \
                "against the isotropic one"
    b = {k: r["buildability"] for k, r in results.items()}
    clusters = min(b, key=lambda k: b[k]["joint_clusters"])
    similar = min(b, key=lambda k: b[k]["beam_length_similarity"])
    line += (f". Fewest joint types: {LABEL[clusters]} ({b[clusters]['joint_clusters']}); "
             f"most even beam lengths: {LABEL[similar]} "
             f"({b[similar]['beam_length_similarity']:.3f})")
    slack = [f"the {LABEL[k]} is bound by no check (utilisation {u:.2f}, λ {lam:.2f}, δ "
             f"{d:.2f} of its limit): the sizing's ratchet kept steel it no longer needed, so "
             "its mass is an upper bound"
             for k, r in sized.items() for u, lam, d in [worst(r)]
             if u < 0.8 and lam is not None and lam > 1.5 * r["sizing"]["lambda_min"] and d < 0.8]
    return line + "".join("; " + x for x in failed + slack) + "."


def overall_statement(all_results):
    """Counts of wins, and each pattern's mass against the isotropic Voronoi on the surfaces
    where both sized; the buildability leaders."""
    wins, ratios, complete = {}, {k: [] for k in PATTERNS}, 0
    for results in all_results.values():
        sized = {k: r["sizing"]["mass_kg"] for k, r in results.items()
                 if r["sizing"].get("sized")}
        for k in sized:
            if "iso" in sized:
                ratios[k].append(100 * (sized[k] / sized["iso"] - 1))
        if len(sized) == len(PATTERNS):
            complete += 1
            best = min(sized, key=sized.get)
            wins[best] = wins.get(best, 0) + 1
    lines = [f"- **Lightest** on the {complete} surfaces where all five patterns sized: "
             + ", ".join(f"{LABEL[k]} on {n}" for k, n in sorted(wins.items(),
                                                                  key=lambda x: -x[1])) + "."]
    lines.append("- **Against the isotropic Voronoi** (median and range over the surfaces where "
                 "both sized): " + "; ".join(
                     f"{LABEL[k]} {statistics.median(v):+.1f} % ({min(v):+.1f} … "
                     f"{max(v):+.1f} %, {len(v)} surfaces)"
                     for k, v in ratios.items() if k != "iso" and v) + ".")
    stress = ratios["stress"]
    lines.append(f"- **The stress-driven Voronoi** is lighter than the isotropic one on "
                 f"{sum(1 for v in stress if v < 0)} of {len(stress)} surfaces.")
    full = len([r for r in all_results.values() if len(r) == len(PATTERNS)])
    lines.append(f"- **Buildability**, on the {full} surfaces with all five measured (ties "
                 "count for each): " + "; ".join(
                     f"{what}: {leaders(all_results, key)}" for what, key in (
                         ("fewest joint clusters", "joint_clusters"),
                         ("most even beam lengths", "beam_length_similarity"),
                         ("flattest panels", "face_planarity"),
                         ("fewest sections", "distinct_sections"), ("fewest joints", "joints")))
                 + ".")
    return lines


def leaders(all_results, key):
    """Which pattern has the lowest buildability figure `key`, on how many surfaces."""
    count = {}
    for results in all_results.values():
        if len(results) < len(PATTERNS):
            continue
        low = min(round(r["buildability"][key], 3) for r in results.values())
        for k, r in results.items():
            if round(r["buildability"][key], 3) <= low:
                count[k] = count.get(k, 0) + 1
    return ", ".join(f"{LABEL[k]} on {n}" for k, n in sorted(count.items(), key=lambda x: -x[1]))


def combination_lambda(c):
    """A ULS combination's λ as the sizing checks it (analysis/combination_runs.h): the smaller
    of λ_imperfect and λ_perfect, else λ_nonlinear, else λ_LBA."""
    paths = [c[k] for k in ("lambda_imperfect", "lambda_perfect") if c.get(k) is not None]
    if paths:
        return min(paths)
    return c.get("lambda_nonlinear") if c.get("lambda_nonlinear") is not None else c.get(
        "lambda_lba")


def worst(r):
    """Over the combinations: the largest member utilisation (§6.2 and §6.3 checks), the
    smallest ULS λ, the largest SLS δ / limit."""
    combos = r["structure"]["combinations"].values()
    uls = [c for c in combos if c["uls"]]
    util = max(max(c["utilisation_max"], c.get("buckling_utilisation_max") or 0) for c in uls)
    lams = [x for x in map(combination_lambda, uls) if x is not None]
    delta = max(c["delta_max_m"] / c["delta_limit_m"] for c in combos if not c["uls"])
    return util, (min(lams) if lams else None), delta


def consistency(name, pattern, r):
    """Problems of a report that says sized: true but breaks a check (empty when none)."""
    s, g = r["sizing"], r["structure"]["governing"]
    if not s.get("sized"):
        return []
    util, lam, delta = worst(r)
    bad = []
    if util > 1 + 1e-9:
        bad.append(f"utilisation {util:.4f} > 1")
    if r["structure"].get("lambda_lba") is not None and (lam is None
                                                         or lam < s["lambda_min"] - 1e-9):
        bad.append(f"λ {lam} < {s['lambda_min']}")
    if delta > 1 + 1e-9:
        bad.append(f"δ {delta:.3f} × its limit")
    if not all(g.get(k) for k in ("pass", "utilisation_pass", "lambda_pass", "delta_pass")):
        bad.append("a governing verdict says it fails")
    return [f"- {name} / {label(pattern, r)}: " + "; ".join(bad)] if bad else []


def load(work):
    """The runs made so far in a surface's folder: {pattern: report with its run.json}."""
    return {k: json.loads((work / k / "report.json").read_text())
            | {"_run": json.loads((work / k / "run.json").read_text())}
            for k in PATTERNS if (work / k / "run.json").exists()}


HEADING = "## 8. Sized steel and buildability by pattern"


def how_made(a, commit):
    return [
        HEADING, "",
        f"Made by `nice -n 19 python3 scripts/sizing_table.py --work {a.work}` (gridshell "
        f"{commit}); every run's folder (report.json, beams.csv with each member's section and "
        f"governing check, frame.json) stays under `{a.work}/SURFACE/PATTERN/` with run.json: "
        "the command and its seconds. Per surface, 300 cells: the stress-driven Voronoi is "
        "`gridshell design SURFACE --size`"
        + (f" {a.stress_args}" if a.stress_args else
           ", whose objective search (`--objective balanced`) picks the field's D, A and "
           "conventions before the sizing (the chosen ones are in the pattern column)")
        + "; at its total beam length L the isotropic Voronoi (`design -D 1 -A 1 --length L "
        "--size`) and the comparison grids (`baseline --kind quad | quad-aniso | tri --length L "
        "--size`; quad-aniso with its own default field, D 3, A 3). British Quad is scaled ×16 "
        "to its real size (section 1); each surface rests on its own supports (section 5).", "",
        "Sizing (docs/sizing.md): eurocode loads (self-weight; glass and cladding 0.4 kN/m²; "
        "snow s_k 1.0 kN/m² of plan times the roof's shape factor, undrifted and drifted, "
        "EN 1991-1-3; ULS 1.35 G + 1.5 Q and SLS G + Q, EN 1990); S355; each member the "
        "lightest of the 75 hot-finished CHS of EN 10210-2 that passes; non-linear level: "
        "every member check of EN 1993-1-1 ≤ 1, the non-linear λ of every ULS combination with "
        "the unfavourable imperfection ≥ 1 (the comparison grids' too), the SLS δ ≤ span / "
        "300. In the table, utilisation is the largest member check (§6.2 cross-section, §6.3 "
        "member buckling) over the ULS combinations, λ the smallest ULS combination's (the "
        "smaller of the perfect and the imperfect path's), δ the largest SLS one's against "
        "its limit. Mass is the steel of the "
        "members (joints not included); kg/m² per m² of plan. Seconds: wall time under other "
        "work on the shared 2-core machine (this script runs at nice 19), and CPU time "
        "(user + sys of the run), the comparable figure.", ""]


def section(a, all_results, notes, problems, commit):
    """The markdown section: how it was made, the two tables, the plain statements."""
    mass = ["| surface | pattern | sized | length m | mass kg | kg/m² plan | vs isotropic "
            "| sections | utilisation | λ | δ / limit mm | iterations | s wall | s CPU |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    build = ["| surface | pattern | face planarity | joints | joint clusters (by valence) "
             "| beam-length similarity | sections |", "|---|---|---|---|---|---|---|"]
    for name, results in all_results.items():
        for pattern in PATTERNS:
            if pattern in results:
                mass.append(mass_row(name, pattern, results[pattern], results.get("iso")))
                build.append(build_row(name, pattern, results[pattern]))
    runs = [r["_run"] for results in all_results.values() for r in results.values()]
    out = how_made(a, commit) + mass + [""]
    out += [f"The {len(runs)} runs took {sum(x['cpu_s'] for x in runs) / 60:.0f} min of CPU "
            f"({sum(x['wall_s'] for x in runs) / 60:.0f} min wall at nice 19 beside other "
            "work).", ""]
    out += ["Buildability (FreeGrid figures, docs/buildability.md; lower is easier to build: "
            "1 = flat panels or beams of one length) of the same sized designs:", ""]
    out += build + [""]
    out += ["Not measured:", ""] + notes + [""] if notes else [
        f"Every surface measured (none over the {a.budget:.0f} s budget per surface).", ""]
    out += ["Every `sized: true` row passes its checks in its report.json, read back over every "
            "combination: member checks ≤ 1, ULS λ ≥ λ_min, SLS δ ≤ its limit, the governing "
            "verdicts pass." if not problems else
            "**Rows reported sized that break a check:**", ""] + problems + ([""] if problems
                                                                             else [])
    out += ["What it says, per surface (sized rows compared):", ""]
    out += [surface_statement(n, r) for n, r in all_results.items() if r] + [""]
    out += ["Overall:", ""] + overall_statement(all_results) + [""]
    out += ["How to read it: every pattern here has the stress-driven design's beam length, not "
            "its own best cell size (with sizing, a pattern is better compared at that; "
            "`design --objective mass` searches it for the Voronoi); the mass is the members' "
            "only, and a triangulated grid's joints of valence 5–7 cost more to make than the "
            "Voronoi's of valence 3 (the joint clusters above count the kinds, not their cost). "
            "A triangulated grid carries the load by membrane action in its members; the "
            "Voronoi's valence-3 joints make the cells carry it by bending, which the sizing "
            "pays for in steel.", ""]
    return out


def splice(path, lines):
    """Replaces the section under HEADING in the markdown file (or appends it)."""
    text = path.read_text()
    new = "\n".join(lines).rstrip("\n") + "\n"
    if HEADING in text:
        start = text.index(HEADING)
        end = text.find("\n## ", start + 1)
        text = text[:start] + new + ("\n" + text[end + 1:] if end >= 0 else "")
    else:
        text = text.rstrip("\n") + "\n\n" + new
    path.write_text(text)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--surfaces", nargs="+", default=SURFACES)
    p.add_argument("--work", default="results_work_sizing")
    p.add_argument("--stress-args", default="", help='e.g. "-D 2 -A 2" instead of the search')
    p.add_argument("--budget", type=float, default=480, help="wall seconds per surface")
    p.add_argument("--no-run", action="store_true", help="only tabulate the runs already made")
    p.add_argument("--splice", metavar="MD", help="write the section into this file "
                   "(e.g. docs/results.md) instead of stdout")
    a = p.parse_args()
    work_root = Path(a.work)
    work_root.mkdir(parents=True, exist_ok=True)
    commit_file = work_root / "commit.txt"
    if not commit_file.exists():
        commit_file.write_text(subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short",
                                               "HEAD"], capture_output=True,
                                              text=True).stdout.strip() + "\n")
    notes, problems, all_results = [], [], {}
    for surface in a.surfaces:
        work = work_root / surface_name(surface)
        if not a.no_run:
            _, note = measure(surface, work, shlex.split(a.stress_args), a.budget)
            if note:
                (work / "note.txt").write_text(note + "\n")
    for surface in a.surfaces:
        name, work = display_name(surface), work_root / surface_name(surface)
        results = load(work)
        all_results[name] = results
        if len(results) < len(PATTERNS):
            why = (work / "note.txt").read_text().strip() if (work / "note.txt").exists() \
                else "not run"
            missing = [LABEL[k] for k in PATTERNS if k not in results]
            notes.append(f"- {name}: {', '.join(missing)} — {why}.")
        for pattern, r in results.items():
            problems += consistency(name, pattern, r)
    lines = section(a, all_results, notes, problems, commit_file.read_text().strip())
    if a.splice:
        splice(Path(a.splice), lines)
    else:
        print("\n".join(lines))
    if problems:
        print("\n".join(["Sized but breaking a check:"] + problems), file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
