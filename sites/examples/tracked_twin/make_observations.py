#!/usr/bin/env python3
"""Writes the tracked twin campaign on the Tschamut terrain: site.json,
observations.json, runs.csv, tracks.csv and impacts.csv (README.md).

Eight runs of the Tschamut 2014 campaign give the releases and the blocks
(../tschamut/data, EnviDat doi:10.16904/envidat.34, ODbL 1.0: see
README.md). rockcal simulates one rock per run at the hidden values (meadow:
hardness 0.4, roughness 0.8 m, friction 0.5) with seed 11 and samples each
path at 25 Hz; the script then writes what a tracked campaign would hand
over, with measurement noise added (random.seed(7)):
  tracks.csv   each path's centre, 0.05 m of noise (one sigma) per axis;
  runs.csv     each run's stop point, 0.05 m of noise per axis;
  impacts.csv  the impacts `rockcal validate --write-impacts` finds in the
               noise-free paths (the flight detector at error.track
               2 mm: flights of 0.08 s and longer; at 5 cm only the
               impacts before long flights, the high rebounds, are found),
               at most three a run, those of the largest incoming speeds of
               at least 3 m/s, with the spin before the impact (wx, wy, wz,
               an in-rock gyroscope's reading); 0.1 m/s of noise (one
               sigma) per velocity component. An impact the noise turns
               back into the ground is dropped.
The site file starts elsewhere (hardness 0.25, roughness 0.4 m, friction
0.7). Deterministic for a given build of rockcal.

  sites/examples/tracked_twin/make_observations.py BUILD_DIR
"""
import csv
import json
import math
import os
import random
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
TSCHAMUT = os.path.join(HERE, "..", "tschamut", "data")
RUNS = ["v004", "v005", "v020", "v039", "v051", "v068", "v092", "v099"]
HIDDEN = {"hardness": 0.4, "roughness": 0.8, "friction": 0.5}
START = {"hardness": 0.25, "roughness": 0.4, "friction": 0.7}
BOUNDS = {"hardness": [0.05, 0.9], "roughness": [0.1, 2.5], "friction": [0.15, 0.9]}
SAMPLE_SECONDS = 0.04       # 25 Hz
POSITION_NOISE_M = 0.05     # per axis, tracks and stop points
VELOCITY_NOISE_MPS = 0.1    # per component, impacts
MIN_IMPACT_SPEED_MPS = 3.0  # incoming
IMPACTS_PER_RUN = 3
DETECTOR_SIGMA_M = 0.002  # the impacts' detector: flights of 0.08 s and longer
ROCKS_PER_RUN = 4           # per evaluation


def site_json():
    runs = {r["run"]: r for r in csv.DictReader(open(os.path.join(TSCHAMUT, "runs.csv")))}
    groups = []
    for run in RUNS:
        r = runs[run]
        groups.append({
            "id": run,
            "count": ROCKS_PER_RUN,
            "inventory": "../tschamut/data/block_%s.csv" % r["block_id"],
            "release": {
                "point": [round(float(r["release_x_m"]), 3), round(float(r["release_y_m"]), 3)],
                "height": 0.0,
                "position_spread": 0.5,
                "velocity": [round(float(r["release_v%s_mps" % c]), 4) for c in "xyz"],
                "velocity_spread": [0.3] * 3,
            },
        })
    return {
        "name": "Tracked twin (Tschamut terrain)",
        "description": "A twin campaign of eight tracked runs on the Tschamut 2014 terrain proxy: "
                       "tracks, stop points and impacts written by rockcal at hidden values with "
                       "measurement noise (make_observations.py). Terrain and blocks: EnviDat "
                       "doi:10.16904/envidat.34 (WSL SLF), ODbL 1.0. See README.md.",
        "units": "si",
        "surface": {"grid_file": "../tschamut/data/terrain.asc", "resolution": 5.0,
                    "sphere_spacing": 5.0},
        "materials": [dict(id="meadow", **START, calibrate=BOUNDS)],
        "rocks": groups,
        "simulation": {"seed": 1, "max_time": 120},
    }


def run(args, check=True):
    return subprocess.run(args, capture_output=True, text=True, check=check)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    exe = os.path.join(sys.argv[1], "cli", "rockcal")
    site = site_json()
    with open(os.path.join(HERE, "site.json"), "w") as f:
        json.dump(site, f, indent=1)
        f.write("\n")
    random.seed(7)
    with tempfile.TemporaryDirectory() as tmp:
        hidden = os.path.join(tmp, "hidden")
        sets = []
        for k, v in HIDDEN.items():
            sets += ["--set", "material.meadow.%s=%g" % (k, v)]
        run([exe, "simulate", os.path.join(HERE, "site.json"), "--rocks", str(len(RUNS)),
             "--seed", "11", *sets, "--trajectories", str(len(RUNS)), "--sample-seconds",
             str(SAMPLE_SECONDS), "--quiet", "--out", hidden])
        rocks = list(csv.DictReader(open(os.path.join(hidden, "rocks.csv"))))
        run_of = {r["rock"]: RUNS[int(r["group"])] for r in rocks}
        stopped = [r for r in rocks if r["outcome"] == "stopped"]
        paths = {}
        for s in csv.DictReader(open(os.path.join(hidden, "trajectories.csv"))):
            paths.setdefault(run_of[s["rock"]], []).append(
                tuple(float(s[c]) for c in ("t", "x", "y", "z", "vx", "vy", "vz", "wx", "wy",
                                            "wz")))

        def write_tracks(path, noise):
            with open(path, "w") as f:
                f.write("run,t,x,y,z\n")
                for r in stopped:
                    name = run_of[r["rock"]]
                    for t, x, y, z, *_ in paths[name]:
                        p = [c + (random.gauss(0, noise) if noise else 0) for c in (x, y, z)]
                        f.write("%s,%.2f,%.3f,%.3f,%.3f\n" % (name, t, *p))

        with open(os.path.join(HERE, "runs.csv"), "w") as f:
            f.write("run,stop_x,stop_y\n")
            for r in stopped:
                f.write("%s,%.3f,%.3f\n" % (run_of[r["rock"]],
                                            float(r["stop_x"]) + random.gauss(0, POSITION_NOISE_M),
                                            float(r["stop_y"]) + random.gauss(0, POSITION_NOISE_M)))
        write_tracks(os.path.join(HERE, "tracks.csv"), POSITION_NOISE_M)
        # The impacts of the noise-free paths, as the detector finds them.
        write_tracks(os.path.join(tmp, "clean.csv"), 0.0)
        obs = {"units": "si", "runs_file": os.path.join(HERE, "runs.csv"),
               "tracks_file": os.path.join(tmp, "clean.csv"),
               "error": {"runout": 1.0, "track": DETECTOR_SIGMA_M, "impact_speed": 0.3}}
        json.dump(obs, open(os.path.join(tmp, "clean.json"), "w"))
        found = os.path.join(tmp, "found.csv")
        run([exe, "validate", os.path.join(HERE, "site.json"), "--observations",
             os.path.join(tmp, "clean.json"), "--write-impacts", found])
        header, *rows = open(found).read().splitlines()
        per_run = {}
        for line in rows:
            row = dict(zip(header.split(","), line.split(",")))
            speed = math.sqrt(sum(float(row[c]) ** 2 for c in ("vx_in", "vy_in", "vz_in")))
            if speed >= MIN_IMPACT_SPEED_MPS:
                per_run.setdefault(row["group"], []).append((speed, line))
        kept = []
        for name in RUNS:
            best = sorted(per_run.get(name, []), reverse=True)[:IMPACTS_PER_RUN]
            kept += [line for _, line in sorted(best, key=lambda b: rows.index(b[1]))]
        cols = header.split(",")

        def spin_before(line):
            # The spin of the path's sample nearest the impact among those
            # still on the incoming flight (velocity nearer v_in than v_out):
            # an in-rock gyroscope's reading; constant in flight.
            f = dict(zip(cols, map(str.strip, line.split(","))))
            c = [float(f[k]) for k in ("x", "y", "z")]
            v_in = [float(f[k]) for k in ("vx_in", "vy_in", "vz_in")]
            v_out = [float(f[k]) for k in ("vx_out", "vy_out", "vz_out")]

            def d2(a, b):
                return sum((p - q) ** 2 for p, q in zip(a, b))

            incoming = [s for s in paths[f["group"]] if d2(s[4:7], v_in) < d2(s[4:7], v_out)]
            return min(incoming, key=lambda s: d2(s[1:4], c))[7:10]

        header += ",wx,wy,wz"
        cols = header.split(",")
        kept = [line + ",%.3f,%.3f,%.3f" % spin_before(line) for line in kept]
        noisy = []
        for line in kept:
            f = line.split(",")
            for c in ("x", "y", "z"):
                k = cols.index(c)
                f[k] = "%.3f" % float(f[k])
            for c in ("vx_in", "vy_in", "vz_in", "vx_out", "vy_out", "vz_out"):
                k = cols.index(c)
                f[k] = "%.3f" % (float(f[k]) + random.gauss(0, VELOCITY_NOISE_MPS))
            noisy.append(",".join(f))
        obs = {"units": "si", "runs_file": "runs.csv", "tracks_file": "tracks.csv",
               "impacts_file": "impacts.csv",
               "error": {"runout": 1.0, "track": POSITION_NOISE_M, "impact_speed": 0.3,
                         "rebound": 0.05}}
        with open(os.path.join(HERE, "observations.json"), "w") as f:
            json.dump(obs, f, indent=1)
            f.write("\n")
        # An impact the noise turned away from the ground (or off it) is
        # dropped: the reader names its line.
        while True:
            with open(os.path.join(HERE, "impacts.csv"), "w") as f:
                f.write(header + "\n" + "".join(line + "\n" for line in noisy))
            v = run([exe, "validate", os.path.join(HERE, "site.json"), "--observations",
                     os.path.join(HERE, "observations.json")], check=False)
            if v.returncode == 0:
                break
            m = re.search(r"impacts\.csv:(\d+):", v.stderr)
            if not m:
                sys.exit(v.stderr)
            print("dropped:", v.stderr.strip())
            del noisy[int(m.group(1)) - 2]
    print("%d runs stopped of %d; %d impacts of %d found (>= %g m/s, at most %d a run)"
          % (len(stopped), len(rocks), len(noisy), len(rows), MIN_IMPACT_SPEED_MPS,
             IMPACTS_PER_RUN))


if __name__ == "__main__":
    main()
