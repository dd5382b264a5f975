#!/usr/bin/env python3
"""Writes site.json and observations.json of the Tschamut 2014 example from
data/runs.csv and data/blocks.csv (derived from EnviDat doi:10.16904/envidat.34,
ODbL 1.0; see README.md and data/README.md for the attribution).

One rock group per tracked run (its "id" is the run's id): the run's block
as an inventory of one measured box (data/block_<id>.csv: mass and sides),
released at the run's tracked release point, resting on the ground, with
its first tracked velocity, and the release's uncertainty: a position
spread (a disc) and a velocity spread per component. The observations are
the runs' stop points (runs_file: data/runs.csv itself). Deterministic.
"""
import csv
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))
ROCKS_PER_RUN = 2          # per evaluation (2: a run's own spread; the refining stage takes 4 times as many)
POSITION_SPREAD_M = 0.5    # radius of the release disc (LPS and hand placement)
VELOCITY_SPREAD_MPS = 0.3  # one sigma of each component of the first tracked velocity


def main():
    blocks = {}
    with open(os.path.join(HERE, "data", "blocks.csv")) as f:
        for row in csv.DictReader(f):
            blocks[row["block_id"]] = row
    for bid, row in blocks.items():
        with open(os.path.join(HERE, "data", "block_%s.csv" % bid), "w") as out:
            out.write("# Tschamut 2014 block %s (%s): mass (kg) and measured sides L1 >= L2 >= L3 (m),\n"
                      "# from data/blocks.csv (EnviDat doi:10.16904/envidat.34, ODbL 1.0).\n"
                      "mass,L1,L2,L3\n%s,%s,%s,%s\n"
                      % (bid, row["name"], row["mass_kg"], row["L1_m"], row["L2_m"], row["L3_m"]))
    groups = []
    with open(os.path.join(HERE, "data", "runs.csv")) as f:
        for row in csv.DictReader(f):
            groups.append({
                "id": row["run"],
                "count": ROCKS_PER_RUN,
                "inventory": "data/block_%s.csv" % row["block_id"],
                "release": {
                    "point": [round(float(row["release_x_m"]), 3), round(float(row["release_y_m"]), 3)],
                    "height": 0.0,
                    "position_spread": POSITION_SPREAD_M,
                    "velocity": [round(float(row["release_v%s_mps" % c]), 4) for c in "xyz"],
                    "velocity_spread": [VELOCITY_SPREAD_MPS] * 3,
                },
            })
    site = {
        "name": "Tschamut 2014",
        "description": "Tracked rockfall runs on a meadow slope at Tschamut (GR, Switzerland), "
                       "2014: one rock group per run (its block as a measured box, its release "
                       "point and first velocity, with their uncertainty). Terrain: a 5 m proxy "
                       "built from the tracked ground points. Data: EnviDat doi:10.16904/envidat.34 "
                       "(WSL SLF), ODbL 1.0. See README.md.",
        "units": "si",
        "surface": {"grid_file": "data/terrain.asc", "resolution": 5.0, "sphere_spacing": 5.0},
        "materials": [{
            "id": "meadow",
            "hardness": 0.3,
            "roughness": 0.5,
            # A meadow's grass resists rolling: rolling resistance and
            # friction are calibrated too, not taken from the hardness.
            "calibrate": {"hardness": [0.05, 0.9], "roughness": [0.1, 2.5],
                          "friction": [0.15, 0.9], "rolling_resistance": [0.0, 0.3]},
        }],
        "rocks": groups,
        "simulation": {"seed": 1, "max_time": 120},
    }
    with open(os.path.join(HERE, "site.json"), "w") as f:
        json.dump(site, f, indent=2)
        f.write("\n")
    obs = {"units": "si", "runs_file": "data/runs.csv", "error": {"runout": 2.0}}
    with open(os.path.join(HERE, "observations.json"), "w") as f:
        json.dump(obs, f, indent=2)
        f.write("\n")


if __name__ == "__main__":
    main()
