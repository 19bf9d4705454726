#!/usr/bin/env bash
# Builds the libFuzzer harnesses (build-fuzz/, Clang, ASan + UBSan) and runs each one after the
# other for SECONDS (default 60) over its seed corpus fuzz/corpus/NAME/:
#   scripts/fuzz.sh [SECONDS] [NAME ...]      NAME: mesh field model (default: all three)
# New interesting inputs go to build-fuzz/corpus/NAME/ (kept between runs, not in the repo); a
# finding (crash, sanitizer report, uncaught exception, timeout, huge allocation, broken promise)
# is written to build-fuzz/findings/NAME/ and makes the script exit non-zero after the remaining
# harnesses have run. Reproduce one with: build-fuzz/fuzz/fuzz_NAME FILE
# JOBS=N limits the build's parallelism (default: all cores). docs/DEVELOPING.md "Fuzzing".
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-60}
shift || true
names=("$@")
[ ${#names[@]} -eq 0 ] && names=(mesh field model)
case "$seconds" in ''|*[!0-9]*) echo "usage: scripts/fuzz.sh [SECONDS] [mesh|field|model ...]" >&2; exit 2 ;; esac

command -v clang++ >/dev/null || { echo "fuzz.sh: needs clang (Debian: clang libclang-rt-14-dev)" >&2; exit 2; }
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$(cd .. && pwd)}
fi
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DGRIDSHELL_FUZZ=ON -DGRIDSHELL_BUILD_TESTS=OFF -DGRIDSHELL_BUILD_BENCH=OFF -DGRIDSHELL_MPI=OFF \
  "${launcher[@]}" >/dev/null
cmake --build build-fuzz --target fuzzers --parallel "${JOBS:-$(nproc)}"

failed=()
for name in "${names[@]}"; do
  exe=build-fuzz/fuzz/fuzz_$name
  [ -x "$exe" ] || { echo "fuzz.sh: no harness '$name' (mesh, field, model)" >&2; exit 2; }
  mkdir -p "build-fuzz/corpus/$name" "build-fuzz/findings/$name"
  echo "== fuzz_$name: ${seconds} s over fuzz/corpus/$name" >&2
  # -timeout: one input may take at most 10 s; -rss_limit_mb: also caps single allocations.
  if ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$exe" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
      -dict="fuzz/dict/$name.dict" -artifact_prefix="build-fuzz/findings/$name/" \
      -print_final_stats=1 "build-fuzz/corpus/$name" "fuzz/corpus/$name" \
      >"build-fuzz/findings/$name.log" 2>&1; then
    grep -E "^stat::number_of_executed_units|^Done" "build-fuzz/findings/$name.log" >&2 || true
  else
    echo "fuzz_$name: FINDING (log: build-fuzz/findings/$name.log)" >&2
    grep -E "ERROR|SUMMARY|broken promise|terminate|Test unit written" \
      "build-fuzz/findings/$name.log" | head -n 20 >&2 || true
    failed+=("$name")
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz.sh: findings in: ${failed[*]}" >&2
  exit 1
fi
echo "fuzz.sh: no findings" >&2
