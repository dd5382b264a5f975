#!/usr/bin/env python3
"""What an exact posterior gives when the truths lie at the edges of their
range (issue #54): the scene family's "truths at the edges" row draws each
truth in the outer 10 % of its range, where simulation-based calibration's
uniform ranks are not promised (they are for truths drawn from the prior).

A one-value model stands in for each calibrated value: the value t in
[0, 1] (its range), a uniform prior, one observation y ~ N(t, sigma^2),
the exact posterior the normal truncated to [0, 1]. For each sigma the
script prints the mean width of the 5-95 % interval and how often it
holds t, with t drawn at the edges (or, --prior, from the whole range:
90 % at any sigma). Reading a row of the family: find the sigma whose
width matches a value's mean interval width, and its coverage is what
an exact posterior would give there.

  bench/edge_coverage.py [--twins 8000] [--seed 1] [--prior]
"""
import argparse
import random
from statistics import NormalDist

NORMAL = NormalDist()


def quantile(y, sigma, p):
    """The p quantile of N(y, sigma^2) truncated to [0, 1]."""
    lo, hi = NORMAL.cdf(-y / sigma), NORMAL.cdf((1 - y) / sigma)
    u = min(max(lo + p * (hi - lo), 1e-300), 1 - 1e-16)
    return y + sigma * NORMAL.inv_cdf(u)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--twins", type=int, default=8000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--prior", action="store_true", help="truths from the whole range")
    a = ap.parse_args()
    rng = random.Random(a.seed)
    print("| sigma / range | mean 90 % interval width / range | intervals holding the truth |")
    print("|---|---|---|")
    for sigma in (0.01, 0.02, 0.03, 0.05, 0.07, 0.1, 0.13, 0.16, 0.2, 0.25, 0.3, 0.4):
        held, width = 0, 0.0
        for _ in range(a.twins):
            v = rng.random()
            t = v if a.prior else (0.2 * v if v < 0.5 else 0.8 + 0.2 * v)
            y = rng.gauss(t, sigma)
            lo, hi = quantile(y, sigma, 0.05), quantile(y, sigma, 0.95)
            held += lo <= t <= hi
            width += hi - lo
        print("| %.2f | %.3f | %.1f %% |" % (sigma, width / a.twins, 100.0 * held / a.twins))


if __name__ == "__main__":
    main()
