#!/usr/bin/env python3
"""A twin of measured impacts (issue #53): are hardness, roughness and
friction recovered from 20 rebounds on rough ground?

The tutorial's slope, one rock group "s1" of 2 ft spheres, 20 impacts on the
talus (roughness 2 ft) at grid nodes 2.5 ft above the surface points,
arriving at 8-25 ft/s across and 25-40 ft/s down (random.seed(3)). The
"field" rebounds are the replays' medians per component at hidden values
(`rockcal score`, seed 5, impacts.csv's vx_sim, vy_sim, vz_sim); impacts
whose replays mostly do not leave the ground are dropped. With --single
each "field" rebound is one replay instead (`impact_draws` 1, at seed
--field-seed, 11 by default), as a measured rebound is: one draw of what
the ground does, at other random numbers than the calibration's. `rockcal
calibrate` then starts from hardness 0.3, roughness 1 ft, friction 0.8
(bounds [0.1, 0.8], [0.5, 4] ft, [0.3, 0.9]) at the same seed.

  bench/impacts_twin.py BUILD_DIR OUT_DIR [--friction 0.6] [--evals 150] [--reach 0]
                       [--posterior [--log-sigma]] [--single [--field-seed 11]]

Prints the recovered values and their errors as shares of their ranges
(with --posterior, also each value's 90 % interval and whether it holds the
hidden value; --log-sigma: the posterior's likelihood with the sigmas' log
term, rockcal's --posterior-log-sigma).
"""
import argparse
import csv
import json
import os
import random
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
TUTORIAL = os.path.join(HERE, "..", "sites", "examples", "tutorial")
HIDDEN = {"hardness": 0.45, "roughness": 2.0}
BOUNDS = {"hardness": [0.1, 0.8], "roughness": [0.5, 4.0], "friction": [0.3, 0.9]}


def run(exe, *args):
    subprocess.run([exe, *args, "--force", "--quiet"], check=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("out")
    ap.add_argument("--friction", type=float, default=0.6)
    ap.add_argument("--evals", type=int, default=150)
    ap.add_argument("--reach", type=int, default=0, help="points of the global stage (0: none)")
    ap.add_argument("--posterior", action="store_true",
                    help="sample the posterior: do its 90 %% intervals hold the hidden values?")
    ap.add_argument("--log-sigma", action="store_true",
                    help="the posterior with the sigmas' log term (--posterior-log-sigma)")
    ap.add_argument("--single", action="store_true",
                    help="each field rebound one replay (at --field-seed), not the replays' median")
    ap.add_argument("--field-seed", type=int, default=11, help="the single rebounds' seed")
    a = ap.parse_args()
    exe = os.path.join(a.build, "cli", "rockcal")
    os.makedirs(a.out, exist_ok=True)
    points = os.path.abspath(os.path.join(TUTORIAL, "points.csv"))
    z = {}
    for r in csv.DictReader(open(points)):
        z[(int(float(r["x"])), int(float(r["y"])))] = float(r["z"])
    site = json.load(open(os.path.join(TUTORIAL, "site.json")))
    site["surface"]["points_file"] = points
    site["rocks"] = [{"id": "s1", "count": 4, "shape": "sphere", "size": [2.0, 2.0],
                      "unit_weight": 165,
                      "release": {"zone": [[10, 70], [40, 70], [40, 130], [10, 130]],
                                  "height": 0}}]
    site["partitions"] = []
    site.pop("report", None)
    hidden = dict(HIDDEN, friction=a.friction)
    site["materials"][1] = {"id": "talus", "zone": [[90, -10], [250, -10], [250, 210], [90, 210]],
                            "calibrate": BOUNDS, **hidden}

    def write_site(name, values):
        s = json.loads(json.dumps(site))
        s["materials"][1].update(values)
        path = os.path.join(a.out, name)
        json.dump(s, open(path, "w"), indent=1)
        return path

    random.seed(3)
    rows = []
    for x in range(110, 240, 10):
        for y in (40, 100, 160):
            if len(rows) < 20:
                rows.append([f"i{len(rows)}", "s1", x, y, round(z[(x, y)] + 2.5, 2),
                             round(random.uniform(8, 25), 2), round(random.uniform(-4, 4), 2),
                             round(-random.uniform(25, 40), 2)])
    header = "id,group,x,y,z,vx_in,vy_in,vz_in,vx_out,vy_out,vz_out\n"
    first = os.path.join(a.out, "impacts_in.csv")
    with open(first, "w") as f:
        f.write(header + "".join(",".join(map(str, r)) + ",5,0,5\n" for r in rows))
    obs = os.path.join(a.out, "obs_in.json")
    first_obs = {"units": "us", "impacts_file": first}
    if a.single:
        first_obs["impact_draws"] = 1
    json.dump(first_obs, open(obs, "w"))
    run(exe, "score", write_site("hidden.json", hidden), "--observations", obs, "--rocks", "4",
        "--seed", str(a.field_seed) if a.single else "5", "--out", os.path.join(a.out, "hidden"))
    sim = {r["id"]: r for r in csv.DictReader(open(os.path.join(a.out, "hidden", "impacts.csv")))}
    field = os.path.join(a.out, "impacts.csv")
    kept = 0
    with open(field, "w") as f:
        f.write(header)
        for r in rows:
            s = sim[r[0]]
            if int(s["left"]) < int(s["draws"]) // 2 or float(s["normal_ratio_sim"]) <= 0.05:
                continue
            f.write(",".join(map(str, r + [s["vx_sim"], s["vy_sim"], s["vz_sim"]])) + "\n")
            kept += 1
    obs = os.path.join(a.out, "obs.json")
    json.dump({"units": "us", "impacts_file": field, "error": {"rebound": 0.05}}, open(obs, "w"))
    start = write_site("start.json", {"hardness": 0.3, "roughness": 1.0, "friction": 0.8})
    out = os.path.join(a.out, "calibration")
    extra = ["--posterior", "--predictive", "0"] if a.posterior else []
    if a.posterior and a.log_sigma:
        extra.append("--posterior-log-sigma")
    run(exe, "calibrate", start, "--observations", obs, "--rocks", "4", "--reach", str(a.reach),
        "--seed", "5", "--max-evals", str(a.evals), *extra, "--out", out)
    params = json.load(open(os.path.join(out, "parameters.json")))["parameters"]
    print(f"{kept} impacts; misfit {json.load(open(os.path.join(out, 'calibration.json')))['misfit_after']:.4g}")
    for p in params:
        if p["material"] != "talus":
            continue
        lo, hi = BOUNDS[p["name"]]
        truth = hidden[p["name"]]
        value = p["value"] / 0.3048 if p["name"] == "roughness" else p["value"]
        line = (f"{p['name']:10s} hidden {truth:.3g}  recovered {value:.3g}  "
                f"error {100 * abs(value - truth) / (hi - lo):.1f} % of the range")
        if p.get("posterior"):
            scale = 1 / 0.3048 if p["name"] == "roughness" else 1.0
            q05, q95 = p["posterior"]["p05"] * scale, p["posterior"]["p95"] * scale
            line += (f"  90 % interval [{q05:.3g}, {q95:.3g}] "
                     f"{'holds' if q05 <= truth <= q95 else 'MISSES'} it")
        print(line)


if __name__ == "__main__":
    sys.exit(main())
