#!/usr/bin/env bash
# The frame analyses users wait for, timed as whole processes, A/B between two builds:
#   * the Aquadom design at -D 2 -A 2 --length 6000 (8 188 beams) analysed non-linearly (the
#     perfect and the imperfect path, as `design` and `analyze` do by default);
#   * the triangulated Aquadom as a frame (11 748 bars): linear + LBA, 5 modes.
# The design is made once (with BUILD_A) into OUT/aq22, so that only the analyses are timed. The
# two binaries run alternately, REPEATS times each; the script prints wall and CPU seconds per
# run, λ, λ_LBA and the stage timings of report.json, and the median ratio B/A per case.
#
# Usage: [CASES="lba nonlinear"] bench/frame_speed.sh BUILD_A [BUILD_B] [REPEATS] [OUT_DIR]
# (from the repository root)
# e.g.   bench/frame_speed.sh /tmp/old_build build 3
set -euo pipefail
a=${1:?give a build directory}
b=${2:-$a}
repeats=${3:-3}
out=${4:-/tmp/frame_speed}
data=${GRIDSHELL_SHARED:-$(dirname "$0")/../../shared}/data/surfaces
mkdir -p "$out"
if [ ! -f "$out/aq22/gridshell.obj" ]; then
  "$a/gridshell" design "$data/aquadom_Vouga.ply" -D 2 -A 2 --length 6000 --analyze none \
    --figures none --quiet -o "$out/aq22" >/dev/null
fi
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"

run() {  # label build case
  local dir="$out/$1-$3-$4"
  case $3 in
    nonlinear) set -- "$@" "$out/aq22/gridshell.obj" --analyze nonlinear ;;
    lba) set -- "$@" "$data/aquadom_Vouga.ply" --analyze buckling ;;
  esac
  /usr/bin/time -f "%e %U %S" -o "$dir.time" "$2/gridshell" analyze "${@:5}" --figures none \
    --quiet -o "$dir" >/dev/null
  python3 - "$1" "$3" "$dir" <<'PY'
import json, sys
label, case, d = sys.argv[1:]
wall, user, sys_ = (float(x) for x in open(d + ".time").read().split()[-3:])
s = json.load(open(d + "/report.json"))
st, t = s["structure"], s["timings_s"]
print(f"{case:9s} {label}: wall {wall:7.2f} s, cpu {user + sys_:7.2f} s, "
      f"lambda {st.get('lambda_nonlinear')}, lambda_imperfect {st.get('lambda_imperfect')}, "
      f"lambda_LBA {st.get('lambda_lba')}, stages "
      + ", ".join(f"{k} {v:.2f}" for k, v in t.items()))
PY
}

for case in ${CASES:-lba nonlinear}; do
  for r in $(seq 1 "$repeats"); do
    run A "$a" "$case" "$r"
    [ "$b" != "$a" ] && run B "$b" "$case" "$r"
  done
done | tee "$out/runs.txt"
python3 - "$out/runs.txt" <<'PY'
import re, statistics, sys
rows = {}
for line in open(sys.argv[1]):
    m = re.match(r"(\S+)\s+(A|B): wall\s+([\d.]+) s, cpu\s+([\d.]+)", line)
    if m:
        rows.setdefault((m[1], m[2]), []).append((float(m[3]), float(m[4])))
for case in ("lba", "nonlinear"):
    if (case, "A") not in rows:
        continue
    med = {k: (statistics.median(w for w, _ in rows[(case, k)]),
               statistics.median(c for _, c in rows[(case, k)])) for k in "AB" if (case, k) in rows}
    line = f"{case}: A median wall {med['A'][0]:.2f} s cpu {med['A'][1]:.2f} s"
    if "B" in med:
        line += (f"; B median wall {med['B'][0]:.2f} s cpu {med['B'][1]:.2f} s; "
                 f"B/A wall {med['B'][0] / med['A'][0]:.3f}, cpu {med['B'][1] / med['A'][1]:.3f}")
    print(line)
PY
