#!/usr/bin/env python3
"""Twin experiments built like the Tschamut 2014 site (issue #38): the
site's terrain, a few of its tracked runs' release points and first
velocities, each run one point release of a sphere with no spread (a
deterministic group: its rocks are copies of one another), one material.
The "observed" stop point of each run is its simulation at a known truth
(hardness, roughness); each staging choice then calibrates from the site's
start and is judged by how far it lands from the truth (in % of each
range) against its wall time. A 100-point reach design over the same box
is the yardstick of the global stage: the lowest misfit of the search's
stages must be no worse than the design's best.

  bench/tschamut_twin.py BUILD_DIR OUT_DIR [--runs 8] [--truths H,R;H,R]
                         [--choices old,new,...] [--threads 1]
                         [--count 1 --position-spread 0]

With --count N > 1 and --position-spread R > 0 each run's group is N
spheres released within R m of its point (no longer deterministic), and
each run's "observed" stop is one draw at the truth at another seed (1001).

Writes OUT_DIR/results.csv (one row per truth and choice) and prints a
table. Deterministic: a seed fixes everything.
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.join(HERE, "..", "sites", "examples", "tschamut")
BOX = {"hardness": (0.05, 0.9), "roughness": (0.1, 2.5)}

# Staging choices: name -> extra arguments of `rockcal calibrate`.
CHOICES = {
    # The staging before #38: a 4 (n + 1) = 12 point design, bobyqa, race, refine.
    "old": ["--reach", "12"],
    # The default after #38: the design grows with the budget (max_evals / 2).
    "new": [],
    # NLopt's global methods in place of bobyqa (with the default design).
    "direct_l": ["--method", "nlopt:direct_l"],
    "crs2": ["--method", "nlopt:crs2"],
    # The smoothed estimate on top of the new default.
    "new_smoothed": ["--estimate", "smoothed"],
    # The new default within the yardstick's 100 evaluations: a 33-point
    # design, 44 first-stage and 22 refining evaluations (and the race's 4
    # and the noise check's 3).
    "new_99": ["--max-evals", "66"],
}


def run(cmd, log):
    with open(log, "w") as f:
        t0 = time.time()
        r = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT)
        dt = time.time() - t0
    if r.returncode != 0:
        sys.exit("failed (%d): %s; see %s" % (r.returncode, " ".join(cmd), log))
    return dt


def make_twin(out, runs, truth, rockcal, threads, count=1, spread=0.0):
    """The twin site and its observations at `truth`; returns (site, obs)."""
    with open(os.path.join(EXAMPLE, "data", "runs.csv")) as f:
        rows = list(csv.DictReader(f))
    step = max(1, len(rows) // runs)
    chosen = rows[::step][:runs]
    groups = []
    for row in chosen:
        groups.append({
            "id": row["run"], "count": count, "shape": "sphere", "size": 0.35, "unit_weight": 26.0,
            "release": {"point": [float(row["release_x_m"]), float(row["release_y_m"])],
                        "height": 0.0,
                        "velocity": [float(row["release_v%s_mps" % c]) for c in "xyz"]}})
        if spread > 0:
            groups[-1]["release"]["position_spread"] = spread
    site = {
        "name": "Tschamut twin", "units": "si",
        "surface": {"grid_file": os.path.abspath(os.path.join(EXAMPLE, "data", "terrain.asc")),
                    "resolution": 5.0, "sphere_spacing": 5.0},
        "materials": [{"id": "meadow", "hardness": 0.3, "roughness": 0.5,
                       "calibrate": {k: list(v) for k, v in BOX.items()}}],
        "rocks": groups, "simulation": {"seed": 1, "max_time": 120}}
    os.makedirs(out, exist_ok=True)
    site_path = os.path.join(out, "site.json")
    with open(site_path, "w") as f:
        json.dump(site, f, indent=1)
    sim = os.path.join(out, "truth")
    # The observed draw: one rock a run (at another seed when the groups spread).
    truth_site = site_path
    if count > 1:
        one = json.loads(json.dumps(site))
        for g in one["rocks"]:
            g["count"] = 1
        one["simulation"]["seed"] = 1001
        truth_site = os.path.join(out, "site_truth.json")
        with open(truth_site, "w") as f:
            json.dump(one, f, indent=1)
    run([rockcal, "simulate", truth_site, "--out", sim, "--force", "--threads", str(threads),
         "--set", "material.meadow.hardness=%g" % truth[0],
         "--set", "material.meadow.roughness=%g" % truth[1]], os.path.join(out, "truth.log"))
    stops = []
    with open(os.path.join(sim, "rocks.csv")) as f:
        for r in csv.DictReader(f):
            if r["outcome"] == "stopped":
                g = groups[int(r["group"])]
                stops.append({"id": g["id"], "stop": [float(r["stop_x"]), float(r["stop_y"])]})
    obs = {"units": "si", "runs": stops, "error": {"runout": 2.0}}
    obs_path = os.path.join(out, "observations.json")
    with open(obs_path, "w") as f:
        json.dump(obs, f, indent=1)
    return site_path, obs_path


def main():
    p = argparse.ArgumentParser()
    p.add_argument("build")
    p.add_argument("out")
    p.add_argument("--runs", type=int, default=8)
    p.add_argument("--truths", default="0.3,0.8;0.6,1.6;0.15,0.4")
    p.add_argument("--choices", default="old,new")
    p.add_argument("--max-evals", type=int, default=100)
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--reach-yardstick", type=int, default=100)
    p.add_argument("--count", type=int, default=1)
    p.add_argument("--position-spread", type=float, default=0.0)
    a = p.parse_args()
    rockcal = os.path.join(a.build, "cli", "rockcal")
    rows = []
    for t, text in enumerate(a.truths.split(";")):
        truth = [float(v) for v in text.split(",")]
        tdir = os.path.join(a.out, "truth%d" % (t + 1))
        site, obs = make_twin(tdir, a.runs, truth, rockcal, a.threads, a.count,
                              a.position_spread)
        with open(obs) as f:
            if not json.load(f)["runs"]:
                print("truth %s: no run stopped on the terrain at the truth; skipped" % text)
                continue
        yard = None
        if a.reach_yardstick > 0:
            rdir = os.path.join(tdir, "reach")
            secs = run([rockcal, "study", "reach", site, "--observations", obs, "--points",
                        str(a.reach_yardstick), "--out", rdir, "--force", "--quiet",
                        "--threads", str(a.threads)], os.path.join(tdir, "reach.log"))
            with open(os.path.join(rdir, "reach.json")) as f:
                pts = json.load(f)["points"]
            yard = min(pt["misfit"] for pt in pts)
            rows.append({"truth": text, "choice": "reach%d" % a.reach_yardstick,
                         "evaluations": a.reach_yardstick, "seconds": round(secs, 1),
                         "lowest_misfit": round(yard, 4), "misfit": "", "h": "", "r": "",
                         "h_err_pct": "", "r_err_pct": "", "recovered": ""})
        for choice in a.choices.split(","):
            cdir = os.path.join(tdir, choice)
            budget = [] if "--max-evals" in CHOICES[choice] else ["--max-evals", str(a.max_evals)]
            secs = run([rockcal, "calibrate", site, "--observations", obs, "--out", cdir,
                        "--force", "--threads", str(a.threads)] + budget + CHOICES[choice],
                       os.path.join(tdir, choice + ".log"))
            with open(os.path.join(cdir, "parameters.json")) as f:
                par = json.load(f)
            with open(os.path.join(cdir, "calibration.json")) as f:
                cal = json.load(f)
            values = {q["name"]: q["value"] for q in par["parameters"]}
            errs = [abs(values[k] - truth[i]) / (BOX[k][1] - BOX[k][0]) * 100
                    for i, k in enumerate(("hardness", "roughness"))]
            # The lowest misfit any evaluation of any stage found (deterministic
            # groups: the rock count does not change the misfit).
            lowest = min(m["lowest_misfit"] for m in cal["methods"])
            reach_json = os.path.join(cdir, "reach.json")
            if os.path.exists(reach_json):
                with open(reach_json) as f:
                    lowest = min([lowest] + [pt["misfit"] for pt in json.load(f)["points"]])
            evals = sum(m["evaluations"] for m in cal["methods"])
            reach_pts = cal["reach_points"]
            rows.append({"truth": text, "choice": choice,
                         "evaluations": "%s+%s" % (reach_pts, evals),
                         "seconds": round(secs, 1), "lowest_misfit": round(lowest, 4),
                         "misfit": round(par["misfit"], 4),
                         "h": round(values["hardness"], 4), "r": round(values["roughness"], 4),
                         "h_err_pct": round(errs[0], 1), "r_err_pct": round(errs[1], 1),
                         "recovered": max(errs) <= 5.0})
            print(rows[-1], flush=True)
    with open(os.path.join(a.out, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    for r in rows:
        print(r)


if __name__ == "__main__":
    main()
