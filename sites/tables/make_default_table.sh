#!/bin/sh
# Regenerates rockcal's default table, sites/tables/default.json, from
# scratch: calibrates each bundled real site with its posterior, keeps the
# small files the table is pooled from (parameters.json, posterior.csv) in
# sites/tables/calibrations/<site>/, and pools them with rockcal table
# (about.json: the classes' descriptions and the sites' provenance).
#
#   sh sites/tables/make_default_table.sh [BUILD_DIR]     (from the repository root)
#
# BUILD_DIR defaults to build (a Release build: ./run.sh build). It takes
# long: see sites/tables/README.md for the last run's wall time. The light
# test TableTest.ShippedTableIsTheTableOfTheShippedCalibrations checks that
# rockcal table of the kept calibrations gives default.json exactly; rebuild
# rockcal after a regeneration (default.json is built into it).
set -eu
build=${1:-build}
rockcal=$build/cli/rockcal
[ -x "$rockcal" ] || { echo "no $rockcal: build rockcal first (./run.sh build)" >&2; exit 2; }
[ -f sites/tables/about.json ] || { echo "run from the repository root" >&2; exit 2; }
rockcal=$(cd "$(dirname "$rockcal")" && pwd)/rockcal
work=$(mktemp -d /tmp/rockcal-default-table.XXXXXX)
version=$("$rockcal" --version | sed 's/^rockcal //')
start=$(date +%s)

calibrate() {  # name site-folder extra-options...
  name=$1; dir=$2; shift 2
  t0=$(date +%s)
  "$rockcal" calibrate "$dir/site.json" --observations "$dir/observations.json" "$@" \
    --posterior --threads 2 --quiet --out "$work/$name"
  echo "$name: $(( $(date +%s) - t0 )) s"
  mkdir -p "sites/tables/calibrations/$name"
  cp "$work/$name/parameters.json" "sites/tables/calibrations/$name/"
  # Every 20th posterior sample (the table reads parameters.json only, whose
  # intervals are of every sample): enough for simulate --parameters here.
  awk 'NR == 1 || (NR - 2) % 20 == 0' "$work/$name/posterior.csv" \
    > "sites/tables/calibrations/$name/posterior.csv"
}

# The commands must be the ones about.json names.
calibrate authume sites/examples/authume --method nlopt:bobyqa --max-evals 63 --estimate smoothed
calibrate tschamut sites/examples/tschamut

# The version that calibrated, into about.json's provenance.
sed "s/\"rockcal_version\": \"[^\"]*\"/\"rockcal_version\": \"$version\"/" sites/tables/about.json \
  > "$work/about.json"
cp "$work/about.json" sites/tables/about.json
(cd sites/tables && "$rockcal" table calibrations/authume calibrations/tschamut \
  --about about.json --quiet --out "$work/table")
cp "$work/table/table.json" sites/tables/default.json
cp "$work/table/table.md" sites/tables/default.md
echo "wrote sites/tables/default.json and default.md in $(( $(date +%s) - start )) s (work files: $work)"
