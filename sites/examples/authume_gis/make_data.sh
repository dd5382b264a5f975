#!/usr/bin/env bash
# Builds this example's GIS files from the Authume example's data (needs
# GDAL's command-line tools, Debian package gdal-bin):
#   dem.tif     the terrain, 1 m cells, RGF93 / Lambert-93 (EPSG:2154)
#   zones.gpkg  the three material zones as polygons, attribute "material"
# Both come from the three DTM zone STL files (../authume/data): each
# triangle, Y-up mapped to Z-up, is moved to Lambert-93 by the dataset's
# stated shift (E = x + 888600 m, N = y + 6671300 m). The DEM interpolates
# the TIN's vertices linearly at the cell centres (gdal_grid, on their
# Delaunay triangulation) inside the TIN; the zones are the union of each
# file's triangles in plan.
set -euo pipefail
cd "$(dirname "$0")"
src=../authume/data
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "material,WKT" > "$tmp/triangles.csv"
echo "id,WKT" > "$tmp/vertices.csv"
for m in gray red blue; do
  awk -v m="$m" -v e0=888600 -v n0=6671300 -v tri="$tmp/triangles.csv" -v ver="$tmp/vertices.all" '
    BEGIN { n = 0 }
    $1 == "vertex" {
      e[n] = sprintf("%.4f", $2 + e0); nn[n] = sprintf("%.4f", $4 + n0); z[n] = sprintf("%.4f", $3)
      print "\"POINT Z (" e[n] " " nn[n] " " z[n] ")\"" >> ver
      n++
    }
    $1 == "endloop" {
      printf "%s,\"POLYGON Z ((", m >> tri
      for (k = 0; k <= 3; k++) printf "%s%s %s %s", (k ? "," : ""), e[k % 3], nn[k % 3], z[k % 3] >> tri
      printf "))\"\n" >> tri
      n = 0
    }' "$src/DTM_${m^}_zone.stl"
done
sort -u "$tmp/vertices.all" | awk '{ print NR "," $0 }' >> "$tmp/vertices.csv"
for layer in triangles vertices; do
  ogr2ogr -f GPKG "$tmp/$layer.gpkg" "$tmp/$layer.csv" -nln "$layer" -a_srs EPSG:2154 \
    -oo GEOM_POSSIBLE_NAMES=WKT -oo KEEP_GEOM_COLUMNS=NO
done
gdal_grid -q -a linear:radius=0:nodata=-9999 -ot Float32 -of GTiff -l vertices \
  -txe 888592 888709 -tye 6671728 6671517 -outsize 117 211 \
  -co COMPRESS=DEFLATE -co PREDICTOR=3 "$tmp/vertices.gpkg" "$tmp/dem.tif"
ogr2ogr -f GPKG "$tmp/zones.gpkg" "$tmp/triangles.gpkg" -nln zones -nlt MULTIPOLYGON \
  -dialect sqlite -sql "SELECT ST_Union(CastToXY(geom)) AS geom, material FROM triangles GROUP BY material"
# Outside the TIN (the triangulation also spans its concave bays): nodata.
gdal_rasterize -q -i -burn -9999 -l zones "$tmp/zones.gpkg" "$tmp/dem.tif"
mv "$tmp/dem.tif" dem.tif
mv "$tmp/zones.gpkg" zones.gpkg
echo "wrote dem.tif and zones.gpkg"
