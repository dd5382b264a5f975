#!/usr/bin/env python3
"""Reach of a calibration box against observed stop points, without an optimiser.

  bench/reach_ks.py ROCKCAL SITE.json OBS.json [points=80] [rocks=200] [seed=3] [jobs=2]

Samples the site's `calibrate` box with a Latin hypercube (design seed 1), runs
`rockcal simulate --set ...` at each point (simulation seed `seed`), and reports
for each point: the Kolmogorov-Smirnov distance between the simulated and the
observed runout distances (rocks that did not stop counted as farthest), the
share of rocks stopped, the runout p10/p50/p90, and the median runout of the
lightest and the heaviest quarter of the rocks (by the observed masses'
quartiles; the observations file must give "masses"). Distances are measured
from the first rock group's release zone centroid (vertex mean) towards the
mean stop point, as the misfit does by default. Prints the best points by KS
and how many meet: KS <= 0.20, >= 90 % stopped, both quarter medians within
10 m of the observed ones.
"""
import concurrent.futures as cf
import csv
import json
import math
import os
import random
import subprocess
import sys
import tempfile


def median(v):
    v = sorted(v)
    n = len(v)
    return v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2])


def ks(a, b):
    a, b = sorted(a), sorted(b)
    i = j = 0
    d = 0.0
    for x in sorted(set(a + b)):
        while i < len(a) and a[i] <= x:
            i += 1
        while j < len(b) and b[j] <= x:
            j += 1
        d = max(d, abs(i / len(a) - j / len(b)))
    return d


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    rockcal, site_path, obs_path = sys.argv[1:4]
    extra = [int(x) for x in sys.argv[4:8]]
    points, rocks, seed, jobs = (extra + [80, 200, 3, 2][len(extra):])[:4]
    site = json.load(open(site_path))
    obs = json.load(open(obs_path))
    box = [("material.%s.%s" % (m["id"], k), lo, hi)
           for m in site["materials"] for k, (lo, hi) in m.get("calibrate", {}).items()]
    rng = random.Random(1)
    cols = [rng.sample(range(points), points) for _ in box]
    design = [[lo + (hi - lo) * (cols[j][i] + rng.random()) / points
               for j, (_, lo, hi) in enumerate(box)] for i in range(points)]
    release = site["rocks"][0]["release"]
    zone = release.get("zone", [release.get("point")])
    ox = sum(p[0] for p in zone) / len(zone)
    oy = sum(p[1] for p in zone) / len(zone)
    stops = obs["runout"]["stop_points"]
    mx = sum(p[0] for p in stops) / len(stops)
    my = sum(p[1] for p in stops) / len(stops)
    dx, dy = mx - ox, my - oy
    norm = math.hypot(dx, dy)
    dx, dy = dx / norm, dy / norm
    dist = lambda x, y: (x - ox) * dx + (y - oy) * dy
    observed = [dist(*p) for p in stops]
    masses = obs["runout"]["masses"]
    ms = sorted(masses)
    q1, q3 = ms[len(ms) // 4], ms[(3 * len(ms)) // 4]
    obs_light = median([d for d, m in zip(observed, masses) if m < q1])
    obs_heavy = median([d for d, m in zip(observed, masses) if m >= q3])
    work = tempfile.mkdtemp(prefix="reach_ks_")

    def run(i):
        out = os.path.join(work, "p%d" % i)
        args = [rockcal, "simulate", site_path, "--rocks", str(rocks), "--seed", str(seed),
                "--threads", "1", "--quiet", "--out", out]
        for (key, _, _), v in zip(box, design[i]):
            args += ["--set", "%s=%.6g" % (key, v)]
        r = subprocess.run(args, capture_output=True, text=True)
        if r.returncode:
            return i, None, r.stderr.strip()[-300:]
        d, light, heavy, stopped = [], [], [], 0
        for row in csv.DictReader(open(os.path.join(out, "rocks.csv"))):
            x = dist(float(row["stop_x"]), float(row["stop_y"]))
            if row["outcome"] == "stopped":
                stopped += 1
            else:
                x = float("inf")
            d.append(x)
            m = float(row["mass_kg"])
            (light if m < q1 else heavy if m >= q3 else []).append(x)
        s = sorted(d)
        return i, dict(ks=ks(d, observed), stopped=stopped / len(d),
                       p=[s[int(q * len(s))] for q in (0.1, 0.5, 0.9)],
                       light=median(light) if light else float("nan"),
                       heavy=median(heavy) if heavy else float("nan")), None

    results = []
    with cf.ThreadPoolExecutor(jobs) as ex:
        for i, r, err in ex.map(run, range(points)):
            if err:
                print("point %d failed: %s" % (i, err))
            else:
                results.append((i, r))
    print("observed: p10 %.1f p50 %.1f p90 %.1f; lightest quarter %.1f, heaviest %.1f m" % (
        sorted(observed)[int(0.1 * len(observed))], median(observed),
        sorted(observed)[int(0.9 * len(observed))], obs_light, obs_heavy))
    results.sort(key=lambda t: t[1]["ks"])
    ok = [t for t in results if t[1]["ks"] <= 0.2 and t[1]["stopped"] >= 0.9
          and abs(t[1]["light"] - obs_light) <= 10 and abs(t[1]["heavy"] - obs_heavy) <= 10]
    print("%d of %d points meet KS <= 0.20, >= 90 %% stopped and both quarters within 10 m"
          % (len(ok), len(results)))
    for i, r in results[:8]:
        print("%3d KS %.3f stopped %.2f p10/50/90 %s light %.1f heavy %.1f | %s" % (
            i, r["ks"], r["stopped"], "/".join("%.0f" % v for v in r["p"]), r["light"],
            r["heavy"], " ".join("%s=%.3g" % (k.split(".", 1)[1], v)
                                 for (k, _, _), v in zip(box, design[i]))))


if __name__ == "__main__":
    main()
