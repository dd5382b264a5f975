#!/usr/bin/env python3
"""How often each fit verdict fires on a correct model (issue #38).

A twin of a bundled site: its "field" observations are one simulation of
the site at its own values (the truth) at seed 5000 + k, and `rockcal
score` compares the site at the same values, at seed 9000 + k, with them.
The model is then exactly right, so a verdict that says "poor" is a false
alarm. Each replicate's residuals are judged by two rules:
- the rule before issue #38's third round: poor when any |residual| > 3,
  the stopped share beyond 2 sigma, or more than max(1, N / 10) beyond
  2 sigma; fair when any is beyond 2 sigma; good otherwise;
- the rule rockcal prints now (score.json's "fit"), the chance tests of
  observations::AssessFit.

  bench/verdict_twin.py BUILD_DIR OUT_DIR --site tschamut|authume
                        [--replicates 40] [--threads 1]
  bench/verdict_twin.py --judge calibration.json|score.json ...
                        (both rules on the residuals of earlier runs)

Tschamut: 62 tracked runs, one observed stop a run (`--rocks 62`), 2
simulated rocks a run (the site's count); 73 residuals. Authume: 41
observed stops and masses pooled from one release zone, 41 simulated
rocks; 25 residuals. Prints the count of each verdict under each rule and
writes OUT_DIR/verdicts.csv. A seed fixes every figure.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SITES = {
    "tschamut": os.path.join(HERE, "..", "sites", "examples", "tschamut", "site.json"),
    "authume": os.path.join(HERE, "..", "sites", "examples", "authume", "site.json"),
}


def run(cmd, log):
    with open(log, "w") as f:
        r = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT)
    if r.returncode != 0:
        sys.exit("failed (%d): %s; see %s" % (r.returncode, " ".join(cmd), log))


def field_observations(site, rocks_csv, kind):
    """The observations of one simulated field campaign."""
    with open(rocks_csv) as f:
        rows = list(csv.DictReader(f))
    if kind == "tschamut":
        groups = site["rocks"]
        runs = [{"id": groups[int(r["group"])]["id"], "stop": [float(r["stop_x"]), float(r["stop_y"])]}
                for r in rows if r["outcome"] == "stopped"]
        return {"units": "si", "runs": runs, "error": {"runout": 2.0}}
    stopped = [r for r in rows if r["outcome"] == "stopped"]
    runout = {"stop_points": [[float(r["stop_x"]), float(r["stop_y"])] for r in stopped],
              "masses": [float(r["mass"]) for r in stopped]}
    if len(stopped) < len(rows):
        runout["stopped_fraction"] = len(stopped) / len(rows)
        runout["observed_rocks"] = len(rows)
    return {"units": "si", "runout": runout, "error": {"runout": 1.0}}


def old_verdict(residuals):
    values = [r["residual"] for r in residuals]
    far = [v for v in values if abs(v) > 2]
    share = any(abs(r["residual"]) > 2 for r in residuals if r["quantity"] == "share")
    if any(abs(v) > 3 for v in values) or share or len(far) > max(1, len(values) // 10):
        return "poor"
    return "fair" if far else "good"


def new_verdict(residuals):
    """observations::AssessFit's rule (to judge residuals written before it)."""
    values = [r["residual"] for r in residuals]
    n = len(values)
    k = sum(abs(v) > 2 for v in values)
    q = math.erfc(2 / math.sqrt(2))
    count = sum(math.comb(n, j) * q ** j * (1 - q) ** (n - j) for j in range(k, n + 1)) if k else 1.0
    largest = max(abs(v) for v in values) if values else 0.0
    big = -math.expm1(n * math.log1p(-math.erfc(largest / math.sqrt(2)))) if values else 1.0
    chance = min(count, big)
    return "poor" if chance < 0.01 else "fair" if chance < 0.05 else "good"


def judge(path):
    """Both rules on a calibration.json ("fit") or score.json ("residuals")."""
    with open(path) as f:
        j = json.load(f)
    res = j["fit"] if isinstance(j.get("fit"), list) else j["residuals"]
    print("%s: %d residuals, %d beyond 2 sigma, largest %.2f; old rule %s, new rule %s" % (
        path, len(res), sum(abs(r["residual"]) > 2 for r in res),
        max(abs(r["residual"]) for r in res), old_verdict(res), new_verdict(res)))


def main():
    if len(sys.argv) >= 3 and sys.argv[1] == "--judge":
        for path in sys.argv[2:]:
            judge(path)
        return
    p = argparse.ArgumentParser()
    p.add_argument("build")
    p.add_argument("out")
    p.add_argument("--site", choices=sorted(SITES), required=True)
    p.add_argument("--replicates", type=int, default=40)
    p.add_argument("--threads", type=int, default=1)
    a = p.parse_args()
    rockcal = os.path.join(a.build, "cli", "rockcal")
    site_path = os.path.abspath(SITES[a.site])
    with open(site_path) as f:
        site = json.load(f)
    field_rocks = ["--rocks", "62"] if a.site == "tschamut" else []
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for k in range(1, a.replicates + 1):
        rdir = os.path.join(a.out, "replicate%d" % k)
        os.makedirs(rdir, exist_ok=True)
        run([rockcal, "simulate", site_path, "--out", os.path.join(rdir, "field"), "--force",
             "--quiet", "--seed", str(5000 + k), "--threads", str(a.threads)] + field_rocks,
            os.path.join(rdir, "field.log"))
        obs = field_observations(site, os.path.join(rdir, "field", "rocks.csv"), a.site)
        obs_path = os.path.join(rdir, "observations.json")
        with open(obs_path, "w") as f:
            json.dump(obs, f)
        run([rockcal, "score", site_path, "--observations", obs_path, "--out",
             os.path.join(rdir, "score"), "--force", "--quiet", "--seed", str(9000 + k),
             "--threads", str(a.threads)], os.path.join(rdir, "score.log"))
        with open(os.path.join(rdir, "score", "score.json")) as f:
            score = json.load(f)
        res = score["residuals"]
        largest = max(abs(r["residual"]) for r in res)
        beyond = sum(abs(r["residual"]) > 2 for r in res)
        fit = score.get("fit", {})
        rows.append({"replicate": k, "residuals": len(res), "beyond_2_sigma": beyond,
                     "largest": round(largest, 3), "old": old_verdict(res),
                     "new": fit.get("verdict", new_verdict(res)),
                     "count_chance": fit.get("count_chance", ""),
                     "largest_chance": fit.get("largest_chance", "")})
        print(rows[-1], flush=True)
    with open(os.path.join(a.out, "verdicts.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    for rule in ("old", "new"):
        counts = {v: sum(r[rule] == v for r in rows) for v in ("good", "fair", "poor")}
        print("%s rule: good %d, fair %d, poor %d of %d" % (rule, counts["good"], counts["fair"],
                                                            counts["poor"], len(rows)))


if __name__ == "__main__":
    main()
