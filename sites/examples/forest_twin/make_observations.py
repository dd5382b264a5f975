#!/usr/bin/env python3
"""Writes the forest twin on the tutorial's terrain: site.json and
observations.json (README.md).

The tutorial's slope (../tutorial/points.csv, synthetic, US units) with a
stand on its runout. rockcal simulates the site's rocks at the hidden values
of the soil (hardness 0.25, roughness 1.5 ft) with seed 11 through the
stand; the script then writes what a field survey would hand over:
  tree_scars   the scars on the SCARRED_STEMS stems struck most often:
               every strike's height above the ground (tree_impacts.csv)
               with 0.1 ft of noise (one sigma), at the stem's position
               and radius (trees.csv);
  runout       the stop points of the rocks that stopped, 1 ft of noise
               per axis.
The site file starts elsewhere (soil hardness 0.4, roughness 0.5 ft).
Deterministic for a given build of rockcal (random.seed(7)).

  sites/examples/forest_twin/make_observations.py BUILD_DIR
"""
import csv
import json
import os
import random
import subprocess
import sys
import tempfile
from collections import defaultdict

HERE = os.path.dirname(os.path.abspath(__file__))
HIDDEN = {"hardness": 0.25, "roughness": 1.5}
START = {"hardness": 0.4, "roughness": 0.5}
BOUNDS = {"hardness": [0.05, 0.5], "roughness": [0.15, 4.0]}
HIDDEN_ROCKS = 200          # the hidden run's rocks
SCARRED_STEMS = 12          # stems whose scars are observed
HEIGHT_NOISE_FT = 0.1       # per scar height
STOP_NOISE_FT = 1.0         # per axis of a stop point
FT_PER_M = 1 / 0.3048


def site_json():
    return {
        "name": "Forest twin (tutorial terrain)",
        "description": "The tutorial's synthetic slope with a stand of 400 stems/ha on its "
                       "runout: scars and stop points written by rockcal at hidden soil values "
                       "(make_observations.py). See README.md.",
        "units": "us",
        "surface": {"resolution": 12, "points_file": "../tutorial/points.csv"},
        "materials": [
            {"id": "bedrock", "hardness": 0.7, "roughness": 0.5},
            {"id": "talus", "hardness": 0.4, "roughness": 2.0,
             "zone": [[90, -10], [250, -10], [250, 210], [90, 210]]},
            dict(id="soil", **START, zone=[[250, -10], [610, -10], [610, 210], [250, 210]],
                 calibrate=BOUNDS),
        ],
        "rocks": [
            {"count": 50, "shape": "sphere", "size": [1.0, 4.0], "unit_weight": 165,
             "release": {"zone": [[10, 70], [40, 70], [40, 130], [10, 130]], "height": 0}},
            {"count": 50, "shape": "cube", "size": [1.0, 4.0], "unit_weight": 165,
             "release": {"zone": [[10, 70], [40, 70], [40, 130], [10, 130]], "height": 0}},
        ],
        "forest": {"stands": [{"zone": [[300, 30], [590, 30], [590, 170], [300, 170]],
                               "stems_per_ha": 400, "dbh_mean_cm": 30, "dbh_sd_cm": 8,
                               "conifer_percent": 60}]},
        "simulation": {"seed": 1, "max_time": 60},
    }


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    exe = os.path.join(sys.argv[1], "cli", "rockcal")
    with open(os.path.join(HERE, "site.json"), "w") as f:
        json.dump(site_json(), f, indent=1)
        f.write("\n")
    random.seed(7)
    with tempfile.TemporaryDirectory() as tmp:
        hidden = os.path.join(tmp, "hidden")
        sets = []
        for k, v in HIDDEN.items():
            sets += ["--set", "material.soil.%s=%g" % (k, v)]
        subprocess.run([exe, "simulate", os.path.join(HERE, "site.json"), "--rocks",
                        str(HIDDEN_ROCKS), "--seed", "11", *sets, "--quiet", "--out", hidden],
                       check=True, capture_output=True)
        stems = list(csv.DictReader(open(os.path.join(hidden, "trees.csv"))))
        strikes = defaultdict(list)
        for s in csv.DictReader(open(os.path.join(hidden, "tree_impacts.csv"))):
            strikes[int(s["tree"])].append(float(s["height"]))
        rocks = list(csv.DictReader(open(os.path.join(hidden, "rocks.csv"))))
    # The most struck stems, ties to the lower index.
    scarred = sorted(strikes, key=lambda t: (-len(strikes[t]), t))[:SCARRED_STEMS]
    trees = []
    for t in sorted(scarred):
        stem = stems[t]
        trees.append({
            "x": float(stem["x"]), "y": float(stem["y"]),
            "radius": round(float(stem["dbh_cm"]) / 200 * FT_PER_M, 3),
            "heights": [round(max(0.0, h + random.gauss(0, HEIGHT_NOISE_FT)), 2)
                        for h in strikes[t]],
        })
    stops = [[round(float(r["stop_x"]) * FT_PER_M + random.gauss(0, STOP_NOISE_FT), 1),
              round(float(r["stop_y"]) * FT_PER_M + random.gauss(0, STOP_NOISE_FT), 1)]
             for r in rocks if r["outcome"] == "stopped"]
    obs = {
        "units": "us",
        "tree_scars": [{"trees": trees}],
        "runout": {"stop_points": stops, "stopped_fraction": round(len(stops) / len(rocks), 4),
                   "observed_rocks": len(rocks)},
        "error": {"height": HEIGHT_NOISE_FT, "runout": STOP_NOISE_FT},
    }
    with open(os.path.join(HERE, "observations.json"), "w") as f:
        json.dump(obs, f, indent=1)
        f.write("\n")
    print("%d stems scarred (%d scars), %d of %d rocks stopped" %
          (len(trees), sum(len(t["heights"]) for t in trees), len(stops), len(rocks)))


if __name__ == "__main__":
    main()
