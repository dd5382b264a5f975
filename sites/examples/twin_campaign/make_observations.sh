#!/usr/bin/env bash
# Writes the observations of the twin campaign: each site simulated at the
# true values (class "ground": hardness 0.45, roughness 0.3 m) with 600 rocks
# and seed 11, then
#   fan/observations.json    the stop points of the rocks that stopped, and
#                            the share that stopped;
#   gully/observations.json  the bounce heights at partitions P1 and P2.
# Measurement errors 0.1 m (heights) and 1 m (runout).
#   sites/examples/twin_campaign/make_observations.sh BUILD_DIR
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
exe=$1/cli/rockcal
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$exe" simulate "$here/fan/site.json" --rocks 600 --seed 11 --quiet \
  --set material.talus.hardness=0.45 --set material.talus.roughness=0.3 --out "$tmp/fan"
"$exe" simulate "$here/gully/site.json" --rocks 600 --seed 11 --quiet \
  --set material.scree.hardness=0.45 --set material.scree.roughness=0.3 --out "$tmp/gully"
python3 - "$tmp" "$here" <<'PY'
import csv, json, sys
tmp, here = sys.argv[1], sys.argv[2]

def rows(name):
    with open(f"{tmp}/{name}/rocks.csv") as f:
        return list(csv.DictReader(f))

error = {"height": 0.1, "runout": 1.0}
fan_rows = rows("fan")
stops = [[round(float(r["stop_x"]), 4), round(float(r["stop_y"]), 4)]
         for r in fan_rows if r["outcome"] == "stopped"]
# The share that stopped: the field would see the others go.
fan = {"units": "si",
       "runout": {"stop_points": stops, "from": [2.5, 10.0], "direction": [1, 0],
                  "observed_rocks": len(fan_rows),
                  "stopped_fraction": round(len(stops) / len(fan_rows), 6)},
       "error": error}
gully_rows = rows("gully")
scars = [{"partition": p, "heights": [round(float(r[f"{p}.height_m"]), 4)
                                      for r in gully_rows if r[f"{p}.height_m"]]}
         for p in ("P1", "P2")]
gully = {"units": "si", "tree_scars": scars, "error": error}
for name, doc in (("fan", fan), ("gully", gully)):
    with open(f"{here}/{name}/observations.json", "w") as f:
        json.dump(doc, f, separators=(", ", ": "))
        f.write("\n")
PY
echo "wrote $here/fan/observations.json, $here/gully/observations.json"
