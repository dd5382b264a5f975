#!/bin/sh
# Golden check of the command line: runs the bundled examples at a fixed seed
# and writes a digest of every output file with its wall-time fields
# stripped, so that a refactor can be shown to change no output.
#
#   tests/golden/golden.sh BUILD_DIR OUT_DIR
#
# writes OUT_DIR/digest.txt (one "sha256  run/file" line per output file) and
# OUT_DIR/normalised/ (the stripped files, to diff two runs). Compare two
# digests with `diff A/digest.txt B/digest.txt`.
set -eu
if [ $# -ne 2 ]; then
  echo "usage: $0 BUILD_DIR OUT_DIR" >&2
  exit 2
fi
build=$1
out=$2
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../.." && pwd)
exe=$build/cli/rockcal
[ -x "$exe" ] || { echo "$0: no rockcal executable at $exe" >&2; exit 2; }
ex=$src/sites/examples
rm -rf "$out"
mkdir -p "$out/runs"
runs=$out/runs

"$exe" calibrate "$ex/tutorial/site.json" --observations "$ex/tutorial/observations.json" \
  --max-evals 12 --rocks 40 --seed 1 --quiet --out "$runs/calibrate-tutorial" >/dev/null
"$exe" calibrate "$ex/authume/site.json" --observations "$ex/authume/observations.json" \
  --max-evals 8 --rocks 40 --seed 1 --quiet --out "$runs/calibrate-authume" >/dev/null
for site in tutorial profile2d authume; do
  "$exe" simulate "$ex/$site/site.json" --rocks 40 --seed 1 --quiet --out "$runs/simulate-$site" >/dev/null
done
"$exe" study stability "$ex/profile2d/site.json" --seed 1 --quiet --out "$runs/stability-profile2d" >/dev/null

python3 "$here/normalise.py" "$runs" "$out/normalised" > "$out/digest.txt"
echo "wrote $out/digest.txt ($(wc -l < "$out/digest.txt") files)"
