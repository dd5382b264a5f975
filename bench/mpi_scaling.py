#!/usr/bin/env python3
"""Scaling of a calibration over MPI ranks against OpenMP threads.

Runs the same short calibration of the Authume example at its 41 rocks per
evaluation (--rocks 41: one stage; a reach check and the misfit at 3 noise
seeds, spread over the ranks as task lists, and the BOBYQA search, spread by
rock blocks) as

  1 rank  x 1 thread    rockcal ... --threads 1
  2 ranks x 1 thread    mpirun -np 2 rockcal ... --threads 1
  1 rank  x 2 threads   rockcal ... --threads 2

`runs` times each (interleaved, so that a change of load on a shared machine
falls on every configuration alike), and prints per configuration the median
wall time of the whole command (mpirun's start included), the median
wall_seconds the calibration itself reports, the speed-up and parallel
efficiency against 1 x 1, the throughput in evaluations per second, and the
cores the run actually had (its CPU seconds over its wall seconds: on a
machine shared with other work, a 2-core configuration may get fewer). It
also checks that every run wrote the same parameters.json and
evaluations.jsonl as the first 1 x 1 run, wall times aside.

usage: bench/mpi_scaling.py ROCKCAL [runs=5] [max_evals=16] [reach=9] [out=/tmp/rockcal-mpi-scaling]
"""
import json
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SITE = os.path.join(HERE, "..", "sites", "examples", "authume")


def timeless(path):
    with open(path) as f:
        return re.sub(r'"(seconds|elapsed|wall_seconds)": ?[-+0-9.eE]+', r'"\1": T', f.read())


def main():
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    rockcal = sys.argv[1]
    runs = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    max_evals = int(sys.argv[3]) if len(sys.argv) > 3 else 16
    reach = int(sys.argv[4]) if len(sys.argv) > 4 else 9
    out = sys.argv[5] if len(sys.argv) > 5 else "/tmp/rockcal-mpi-scaling"
    mpirun = shutil.which("mpirun")
    if not mpirun:
        print("mpirun not found (install libopenmpi-dev)", file=sys.stderr)
        return 2
    os.makedirs(out, exist_ok=True)
    mpi = [mpirun, "-np", "2", "--bind-to", "core", "--oversubscribe"]
    if os.getuid() == 0:
        mpi.append("--allow-run-as-root")
    configs = [("1 rank x 1 thread", [], 1, 1), ("2 ranks x 1 thread", mpi, 1, 2),
               ("1 rank x 2 threads", [], 2, 1)]
    args = ["calibrate", os.path.join(SITE, "site.json"), "--observations",
            os.path.join(SITE, "observations.json"), "--method", "nlopt:bobyqa",
            "--rocks", "41", "--max-evals", str(max_evals), "--reach", str(reach), "--quiet",
            "--force"]
    walls = {c[0]: [] for c in configs}
    loads = []
    cpus = {c[0]: [] for c in configs}
    own = {c[0]: [] for c in configs}
    reference = None
    same = True
    evaluations = 0
    for run in range(runs):
        for name, prefix, threads, _ in configs:
            folder = os.path.join(out, re.sub(r"\W+", "_", name) + "_" + str(run))
            env = dict(os.environ, OMP_NUM_THREADS=str(threads))
            t0 = time.monotonic()
            r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
            subprocess.run(prefix + [rockcal] + args + ["--threads", str(threads), "--out", folder],
                           check=True, env=env, stdout=subprocess.DEVNULL)
            walls[name].append(time.monotonic() - t0)
            r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpus[name].append(r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime)
            loads.append(os.getloadavg()[0])
            with open(os.path.join(folder, "calibration.json")) as f:
                calibration = json.load(f)
            own[name].append(calibration["wall_seconds"])
            files = [timeless(os.path.join(folder, f))
                     for f in ("parameters.json", "evaluations.jsonl", "reach.json", "rocks.csv")]
            if reference is None:
                reference = files
                evaluations = sum(m["evaluations"] for m in calibration["methods"])
            elif files != reference:
                same = False
                print(f"DIFFERENT RESULT: {folder}", file=sys.stderr)
            print(f"run {run + 1}/{runs} {name}: {walls[name][-1]:.2f} s", file=sys.stderr)
    base = statistics.median(walls[configs[0][0]])
    print(f"Authume calibration, --rocks 41 --max-evals {max_evals} --reach {reach} (BOBYQA, 3 "
          f"noise seeds): {evaluations} search evaluations; median of {runs} runs")
    print()
    print("| ranks x threads | wall s (command) | wall s (calibration) | speed-up | efficiency "
          "| search evaluations/s | cores used (CPU s / wall s) |")
    print("|---|---|---|---|---|---|---|")
    for name, _, threads, ranks in configs:
        w = statistics.median(walls[name])
        c = statistics.median(own[name])
        cores = threads * ranks
        used = statistics.median(cpu / wall for cpu, wall in zip(cpus[name], walls[name]))
        print(f"| {name} | {w:.2f} | {c:.2f} | {base / w:.2f} | {base / w / cores:.0%} "
              f"| {evaluations / w:.2f} | {used:.2f} |")
    print()
    print(f"load average (1 min) after each run: median {statistics.median(loads):.1f}, "
          f"{min(loads):.1f} to {max(loads):.1f} on {os.cpu_count()} cores (the runs' own "
          f"load included: a load above the cores means other work shared them)")
    print("results identical to 1 x 1 (wall times aside): " + ("yes" if same else "NO"))
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
