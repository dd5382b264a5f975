#!/usr/bin/env python3
"""Writes points.csv, the terrain of the tutorial site (US units, feet).

A 600 ft x 200 ft slope, x downslope, y across: steep bedrock from 300 ft
down to 170 ft (x 0-90), a talus / boulder field down to 45 ft (x 90-250)
with bumps of +-1.5 ft, a gentle runout down to 20 ft (x 250-500) and a
slight rise to 25 ft at the end (x 500-600), where rocks come to rest. Along
the centre line y = 100 ft; the slope is a shallow valley (its sides rise by
up to 20 ft towards y = 0 and y = 200 ft) with a gully down the middle, so
rocks are channelled rather than sent off the sides. Points every 10 ft.
Deterministic: run it again and the file is the same.
"""
import math

SPACING = 10.0


BEDROCK_END, TALUS_END, RUNOUT_END = 90.0, 250.0, 500.0  # x (ft) where the parts meet
LENGTH = 600.0


def base(x):
    """Elevation along the centre line (ft), piecewise linear."""
    if x <= BEDROCK_END:  # about 55 degrees
        return 300.0 - 130.0 * x / BEDROCK_END
    if x <= TALUS_END:  # about 38 degrees
        return 170.0 - 125.0 * (x - BEDROCK_END) / (TALUS_END - BEDROCK_END)
    if x <= RUNOUT_END:  # about 5.7 degrees
        return 45.0 - 25.0 * (x - TALUS_END) / (RUNOUT_END - TALUS_END)
    return 20.0 + 5.0 * (x - RUNOUT_END) / (LENGTH - RUNOUT_END)  # a slight rise


def elevation(x, y):
    valley = 20.0 * ((y - 100.0) / 100.0) ** 2
    gully = -8.0 * math.exp(-((y - 100.0) / 30.0) ** 2) * math.sin(math.pi * min(x, 400.0) / 400.0)
    bumps = 0.0
    if BEDROCK_END < x < TALUS_END:  # boulder field: bumps of +-1.5 ft, tapered at the ends
        taper = math.sin(math.pi * (x - BEDROCK_END) / (TALUS_END - BEDROCK_END))
        bumps = 1.5 * taper * math.sin(2 * math.pi * x / 37.0) * math.sin(2 * math.pi * y / 29.0)
    return base(x) + valley + gully + bumps


def main():
    with open("points.csv", "w") as out:
        out.write("x,y,z\n")
        for j in range(int(200 / SPACING) + 1):
            for i in range(int(LENGTH / SPACING) + 1):
                x, y = i * SPACING, j * SPACING
                out.write(f"{x:g},{y:g},{elevation(x, y):.2f}\n")


if __name__ == "__main__":
    main()
