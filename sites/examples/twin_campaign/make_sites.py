#!/usr/bin/env python3
"""Writes the two site files of the twin campaign (synthetic, SI units).

Two slopes whose one material each ("talus" on the fan, "scree" in the
gully) carries the class "ground", so that a campaign calibrates one
hardness and one roughness for both:
  fan/site.json    a 30 degree slope 24 m long onto a flat runout, 120 m in
                   all; the observations are stop points only;
  gully/site.json  a 42 degree slope 40 m long onto a flat, with partitions
                   at x = 14 m and x = 28 m on the slope; the observations are
                   bounce heights there only.
Points every 2 m, 20 m across. The site files hold the starting values
(hardness 0.3, roughness 0.15 m), not the truth. Deterministic.
"""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
SPACING = 2.0
WIDTH = 20.0


def points(slope_deg, slope_len, length):
    top = slope_len * math.tan(math.radians(slope_deg))
    out = []
    y = 0.0
    while y <= WIDTH + 1e-9:
        x = 0.0
        while x <= length + 1e-9:
            z = (slope_len - x) * math.tan(math.radians(slope_deg)) if x < slope_len else 0.0
            out.append([round(x, 6), round(y, 6), round(z, 6)])
            x += SPACING
        y += SPACING
    return out, top


def site(name, material, slope_deg, slope_len, length, partitions):
    pts, _ = points(slope_deg, slope_len, length)
    return {
        "name": name,
        "units": "si",
        "surface": {"resolution": SPACING, "sphere_spacing": SPACING, "points": pts},
        "materials": [{
            "id": material, "class": "ground", "hardness": 0.3, "roughness": 0.15,
            "contact_time": 0.02,
            "calibrate": {"hardness": [0.1, 0.8], "roughness": [0.05, 0.6]}}],
        "partitions": partitions,
        "rocks": [{"count": 300, "shape": "sphere", "size": [0.4, 0.8], "unit_weight": 26,
                   "release": {"zone": [[1, 8], [4, 8], [4, 12], [1, 12]], "height": 0}}],
        "simulation": {"seed": 2, "max_time": 20},
    }


def write(folder, doc):
    os.makedirs(os.path.join(HERE, folder), exist_ok=True)
    with open(os.path.join(HERE, folder, "site.json"), "w") as f:
        json.dump(doc, f, separators=(", ", ": "))
        f.write("\n")


write("fan", site("fan", "talus", 30.0, 24.0, 120.0, []))
write("gully", site("gully", "scree", 42.0, 40.0, 60.0,
                    [{"id": "P1", "x": 14}, {"id": "P2", "x": 28}]))
