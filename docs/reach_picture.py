#!/usr/bin/python3
"""Renders the reach_probability band of a rockcal rasters.tif over a
hillshade of the DEM as a PNG, zoomed to
where the rocks went: the picture in README.md (docs/validation.md, Figures).

usage: docs/reach_picture.py DEM.tif RUN_DIR/rasters.tif OUT.png [SCALE]

Needs Debian's python3-gdal and python3-numpy. The classes and colours are
those of the plan view of report.html (share of the rocks released).
"""
import sys

import numpy as np
from osgeo import gdal

BREAKS = [0.0, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5]
COLOURS = ["#ffffb2", "#fed976", "#feb24c", "#fd8d3c", "#fc4e2a", "#e31a1c", "#b10026"]


def main(dem_path, rasters_path, out_path, scale=3):
    gdal.UseExceptions()
    rasters = gdal.Open(rasters_path)
    band = next(rasters.GetRasterBand(k) for k in range(1, rasters.RasterCount + 1)
                if rasters.GetRasterBand(k).GetDescription().startswith("reach_probability:"))
    reach = band.ReadAsArray().astype(float)
    reach[reach == band.GetNoDataValue()] = np.nan
    # The hillshade on the rasters' own grid (the DEM's, for a raster site).
    shade_ds = gdal.DEMProcessing("", gdal.Open(dem_path), "hillshade", format="MEM",
                                  zFactor=1.5, computeEdges=True)
    shade = shade_ds.GetRasterBand(1).ReadAsArray().astype(float)
    shade = shade[: reach.shape[0], : reach.shape[1]]
    grey = np.where(np.isnan(reach), 255.0, 90.0 + 0.6 * shade)
    rgb = np.stack([grey, grey, grey], axis=0)
    for k in range(len(BREAKS)):
        hi = BREAKS[k + 1] if k + 1 < len(BREAKS) else np.inf
        cells = (reach > 0) & (reach >= BREAKS[k]) & (reach < hi)
        colour = [int(COLOURS[k][i:i + 2], 16) for i in (1, 3, 5)]
        for c in range(3):
            rgb[c][cells] = 0.2 * rgb[c][cells] + 0.8 * colour[c]
    # Zoomed to where the rocks went, with a margin of 12 cells.
    rows, cols = np.nonzero(reach > 0)
    r0, r1 = max(rows.min() - 12, 0), min(rows.max() + 13, reach.shape[0])
    c0, c1 = max(cols.min() - 12, 0), min(cols.max() + 13, reach.shape[1])
    rgb = rgb[:, r0:r1, c0:c1]
    rgb = np.repeat(np.repeat(rgb, scale, axis=1), scale, axis=2).astype(np.uint8)
    mem = gdal.GetDriverByName("MEM").Create("", rgb.shape[2], rgb.shape[1], 3, gdal.GDT_Byte)
    for c in range(3):
        mem.GetRasterBand(c + 1).WriteArray(rgb[c])
    gdal.GetDriverByName("PNG").CreateCopy(out_path, mem, options=["ZLEVEL=9"])


if __name__ == "__main__":
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__)
    main(*sys.argv[1:4], *(int(a) for a in sys.argv[4:]))
