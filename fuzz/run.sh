#!/usr/bin/env bash
# Builds the fuzz targets with clang and runs each for SECONDS (default 60).
#   fuzz/run.sh [SECONDS]
# Findings (crash-*, leak-*, timeout-*) are left in build-fuzz/findings/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
targets="site_fuzz observations_fuzz point_files_fuzz esri_grid_fuzz stl_fuzz evaluation_log_fuzz"
CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DROCKCAL_FUZZ=ON \
  -DROCKCAL_BUILD_TESTS=OFF -DROCKCAL_BUILD_BENCH=OFF >/dev/null
for t in $targets; do cmake --build build-fuzz -j 2 --target "$t"; done
mkdir -p build-fuzz/findings
status=0
for t in $targets; do
  corpus=build-fuzz/corpus/$t
  mkdir -p "$corpus"
  echo "fuzz/run.sh: $t for $seconds s" >&2
  # Seed inputs: the examples, and a target's own under fuzz/seeds/ if any.
  seeds=(sites/examples)
  [ -d fuzz/seeds/"$t" ] && seeds+=(fuzz/seeds/"$t")
  ./build-fuzz/fuzz/"$t" "$corpus" "${seeds[@]}" -max_total_time="$seconds" -max_len=65536 \
    -timeout=10 -rss_limit_mb=2048 -artifact_prefix=build-fuzz/findings/"$t"- \
    -print_final_stats=1 2>build-fuzz/"$t".log || { status=1; tail -30 build-fuzz/"$t".log >&2; }
done
exit $status
