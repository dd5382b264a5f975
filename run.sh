#!/usr/bin/env bash
# rockcal's one entry point on a fresh Debian machine:
#   ./run.sh demo   install what is missing, build, calibrate the Authume example
#   ./run.sh test   install what is missing, build with sanitizers, run the tests
#   ./run.sh build  install what is missing and build (Release) into build/
#   ./run.sh bench  build and run the benchmarks in bench/
set -euo pipefail
cd "$(dirname "$0")"

# libopenmpi-dev: the MPI engine (mpirun -np N rockcal ...); rockcal also
# builds without it (then single-process only).
PACKAGES=(build-essential cmake libeigen3-dev libnlopt-cxx-dev libceres-dev
          nlohmann-json3-dev libgtest-dev libgmock-dev libgdal-dev libqhull-dev
          libopenmpi-dev)
JOBS=$(nproc 2>/dev/null || echo 2)

install_missing() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "run.sh: installing ${missing[*]}" >&2
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get update -qq
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
}

# A compiler cache, where the machine has one (Debian's ccache; not
# installed by this script): a second build of the same sources, in this
# checkout or in another clone, compiles only what changed. Paths are taken
# relative to the checkout and the build folder is left out of the hash, so
# that two clones share their objects.
launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER= -DCMAKE_C_COMPILER_LAUNCHER=)
if command -v ccache >/dev/null 2>&1; then
  export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi

build() {  # build DIR TYPE [extra cmake args]
  local dir=$1 type=$2
  shift 2
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE="$type" "${launcher[@]}" "$@" >/dev/null
  cmake --build "$dir" -j "$JOBS"
}

case "${1:-}" in
  build)
    install_missing
    build build Release
    ;;
  demo)
    install_missing
    build build Release -DROCKCAL_BUILD_TESTS=OFF -DROCKCAL_UNITY_BUILD=ON
    out=${2:-out/authume}
    mkdir -p "$(dirname "$out")"
    ./build/cli/rockcal calibrate sites/examples/authume/site.json \
      --observations sites/examples/authume/observations.json \
      --method nlopt:bobyqa --max-evals 63 --estimate smoothed --out "$out" --force
    echo "run.sh: results in $out/ (parameters.md, trace.csv, calibration.json, summary.json, ...)"
    ;;
  test)
    install_missing
    # Everything under the address + undefined-behaviour sanitizers, at -O1
    # (the sanitizers' own advice: a third less compile time than -O2 for
    # tests that run a little slower) with line tables only (-g1: findings
    # keep their file and line) ...
    # Each library, rockcal and each test executable compiled in batches of
    # sources (ROCKCAL_UNITY_BUILD, CMakeLists.txt, tests/CMakeLists.txt):
    # about half the compile time, here and in the heavy tests' optimised
    # build below (parallel/ is compiled file by file: cmake/warnings.cmake).
    build build-asan RelWithDebInfo -DROCKCAL_SANITIZE=ON -DROCKCAL_BUILD_BENCH=OFF -DROCKCAL_UNITY_BUILD=ON \
      -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG"
    ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
      ctest --test-dir build-asan --output-on-failure -j "$JOBS" -LE heavy
    # ... but the numerical experiments labelled "heavy" (calibration twin
    # experiments) in an optimised build: under the sanitizers they take hours.
    # They include tests/cli/mpi_heavy_test.cc: rockcal under mpirun -np 2
    # against the single process, bit for bit (Open MPI's own allocations
    # defeat the sanitized build's leak check). Without link-time
    # optimisation: its links cost more than it saves here.
    cmake -S . -B build-heavy -DCMAKE_BUILD_TYPE=Release -DROCKCAL_LTO=OFF -DROCKCAL_UNITY_BUILD=ON \
      "${launcher[@]}" >/dev/null
    heavy=$(cd tests && ls */*_heavy_test.cc | cut -d/ -f1 | sort -u | sed 's/$/_heavy_tests/')
    for target in $heavy; do cmake --build build-heavy -j "$JOBS" --target "$target"; done
    ctest --test-dir build-heavy --output-on-failure -j "$JOBS" -L heavy
    ;;
  bench)
    install_missing
    build build Release
    for b in build/bench/*_bench; do "$b"; done
    ;;
  *)
    echo "usage: ./run.sh demo|test|build|bench" >&2
    exit 2
    ;;
esac
