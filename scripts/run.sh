#!/usr/bin/env bash
# One entry point for a fresh Debian 12 machine: installs what is missing, builds, then runs
#   demo  - gridshell design on the built-in default surface, results in ./demo/
#   test  - the size limits of src/ (scripts/function_sizes.py --check), the whole test suite
#           (Release build, then again under AddressSanitizer + UBSan), then a short run of the
#           input readers' fuzzers (scripts/fuzz.sh)
#   build - only set up and build
set -euo pipefail
cd "$(dirname "$0")/.."

# Dense kernels for CHOLMOD's supernodal factorisation (the shell and frame solvers), installed as
# Debian's libblas.so.3 / liblapack.so.3 alternatives (auto mode picks them over the reference
# libraries): libblis4-serial = BLIS BLAS (fast level 3, reentrant by design), libatlas3-base =
# ATLAS's LAPACK (its dpotrf is ~2x cheaper than reference LAPACK's on CHOLMOD's many small
# supernodes). Both single-threaded, so results are the same bits run to run and with concurrent
# factorisations from TBB threads (tests: ShellSolver.ConcurrentSolvesAreIdenticalToASerialOne).
# 50 K-triangle shell: factorisation 4-5x faster than reference BLAS (docs/shell.md).
# Not OpenBLAS: Debian's serial OpenBLAS is not thread-safe (concurrent CHOLMOD factorisations in
# a parallel sweep gave false zero pivots), and the threaded one makes results depend on thread
# count.
PACKAGES=(build-essential cmake ninja-build pkg-config libeigen3-dev libsuitesparse-dev
  libspectra-dev liblbfgspp-dev libcli11-dev nlohmann-json3-dev libspdlog-dev libfmt-dev libtbb-dev
  libgtest-dev libgmock-dev libbenchmark-dev libcgal-dev calculix-ccx
  libblis4-serial libatlas3-base)

# jemalloc: the executables' allocator, backed by transparent huge pages (src/interpose/allocator.cpp;
# page faults were a fifth of the Aquadom LBA on the 2-core VM, where one costs several µs;
# docs/performance.md). Optional: without it CMake falls back to glibc's malloc.
PACKAGES+=(libjemalloc-dev)

# Boost's headers (also pulled in by CGAL): Boost.Math's TOMS 748 root finder locates λ_y and λ_δ
# on the non-linear path (fem/frame_arclength.cpp).
PACKAGES+=(libboost-dev)

# DXF and glTF: panels.dxf, beams.dxf and gridshell.glb in every design folder
# (src/gridshell/exchange/); ezdxf is the tests' independent DXF reader.
PACKAGES+=(libdxflib-dev libtinygltf-dev python3-ezdxf)

# Open MPI: the optional distributed sweep (`mpirun -n K gridshell sweep ...`) and its test.
PACKAGES+=(libopenmpi-dev openmpi-bin)

# Cairo: the figures/*.png every design, baseline, analyze and sweep draws (src/gridshell/figures/).
PACKAGES+=(libcairo2-dev)

# report.html (docs/report.md): Node.js and npm bundle the viewer (three.js, esbuild from
# web/package-lock.json) at build time; headless Chromium and libpng are the tests' browser and
# screenshot reader.
# (A machine with its own Node.js, e.g. NodeSource's, which bundles npm, keeps it.)
PACKAGES+=(chromium libpng-dev)
command -v npm >/dev/null || PACKAGES+=(nodejs npm)

# `gridshell studio` (docs/studio.md): cpp-httplib serves the page and its JSON API; unzip checks
# the exported archive in the tests.
PACKAGES+=(libcpp-httplib-dev unzip)

# Clang with libFuzzer and the sanitizer runtimes: the fuzz smoke run of `test` (scripts/fuzz.sh).
PACKAGES+=(clang libclang-rt-14-dev)

install_packages() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "installing: ${missing[*]}" >&2
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "need root or sudo to install: ${missing[*]}" >&2; exit 1; }
    sudo="sudo"
  fi
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get update -qq
  # calculix-ccx is only the tests' independent oracle: carry on without it if it cannot be had.
  if ! $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null; then
    local core=()
    for p in "${missing[@]}"; do [ "$p" = calculix-ccx ] || core+=("$p"); done
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${core[@]}" >/dev/null
  fi
}

# The viewer's npm packages, exactly as pinned in web/package-lock.json (again only when the lock
# file changed since the last install).
install_web() {
  if [ -x web/node_modules/.bin/esbuild ] && [ web/node_modules/.package-lock.json -nt web/package-lock.json ]; then
    return 0
  fi
  npm ci --prefix web --no-audit --no-fund
}

build() {  # build DIR [extra cmake args]
  local dir=$1; shift
  local launcher=()
  if command -v ccache >/dev/null; then
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
    export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$(cd .. && pwd)}
  fi
  cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" "$@" >/dev/null
  cmake --build "$dir" --parallel "$(nproc)"
}

cmd=${1:-demo}
install_packages
install_web
case "$cmd" in
  build) build build ;;
  demo)
    build build -DGRIDSHELL_BUILD_TESTS=OFF
    ./build/gridshell design -o demo
    echo "results in $(pwd)/demo (open report.html first; gridshell.obj in MeshLab or gridshell.vtp / field.vtp in ParaView; report.json has δ and λ)"
    ;;
  test)
    # Warnings are errors in the Release test build (CI); the demo and the -O1 sanitizer builds
    # only warn (the sanitizer build has not been made warning-free under -Werror yet).
    # Size limits first (seconds, before the build): no function over 120 lines and no file over
    # 800 in src/ (docs/DEVELOPING.md); the offenders are listed and the run fails.
    python3 scripts/function_sizes.py --check
    build build -DGRIDSHELL_BUILD_TESTS=ON -DGRIDSHELL_WERROR=ON
    ctest --test-dir build --output-on-failure -j "$(nproc)"
    # The sanitizer pass: -O1 (faster to build), without the heavy programs.
    build build-sanitize -DGRIDSHELL_SANITIZE=ON -DGRIDSHELL_BUILD_BENCH=OFF \
      -DGRIDSHELL_HEAVY_TESTS=OFF -DGRIDSHELL_MPI=OFF "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -DNDEBUG"
    ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
      LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0" \
      ctest --test-dir build-sanitize --output-on-failure -j "$(nproc)" -LE heavy
    # The fuzz smoke run: the input readers' libFuzzer harnesses (Clang, build-fuzz/), 25 s each
    # over their seed corpus fuzz/corpus/; a crash, sanitizer report or hang fails the run.
    JOBS=$(nproc) bash scripts/fuzz.sh 25
    ;;
  *) echo "usage: scripts/run.sh demo|test|build" >&2; exit 2 ;;
esac
