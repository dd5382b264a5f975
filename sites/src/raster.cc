#include "rockcal/sites/raster.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rockcal/core/error.h"
#include "rockcal/core/format.h"
#include "rockcal/core/numbers.h"
#include "rockcal/sites/gdal_util.h"
#include "rockcal/sites/gridding.h"
#include "rockcal/sites/input_file.h"

namespace rockcal::sites {
namespace {

using core::kNaN;
constexpr long kMaxCells = 100'000'000;

using core::FormatNumber;

}  // namespace

double RasterGrid::at(int i, int j) const {
  const double v = values[static_cast<std::size_t>(nrows - 1 - j) * ncols + i];
  return nodata && v == *nodata ? kNaN : v;
}

core::HeightGrid RasterToHeightGrid(const RasterGrid& grid, double length_scale, double spacing) {
  return ResampleNodes(
      grid.ncols, grid.nrows, grid.cellsize * length_scale, grid.x_center * length_scale,
      grid.y_center * length_scale, [&](int i, int j) { return grid.at(i, j) * length_scale; },
      spacing);
}

namespace {

// The raster's geotransform into gt: north-up (no rotation), square cells
// with columns running west to east.
void ReadGeoTransform(const std::string& path, GDALDatasetH h, double gt[6]) {
  if (GDALGetGeoTransform(h, gt) != CE_None) {
    throw InputError(path,
                     "has no georeferencing (no geotransform); expected a georeferenced raster "
                     "(a GeoTIFF's own geotransform, or a world file beside the image)");
  }
  if (gt[2] != 0.0 || gt[4] != 0.0) {
    throw InputError(path, "has a rotated geotransform (rotation terms " + FormatNumber(gt[2]) +
                               ", " + FormatNumber(gt[4]) +
                               "); rotated rasters are not supported: expected a north-up "
                               "raster (warp it first, e.g. gdalwarp)");
  }
  const double w = gt[1], hgt = gt[5];
  if (!(w > 0.0) || !std::isfinite(w)) {
    throw InputError(path, "has a pixel width of " + FormatNumber(w) +
                               "; expected columns running west to east (width > 0)");
  }
  if (!(std::abs(std::abs(hgt) - w) <= 1e-9 * w)) {
    throw InputError(path, "has cells of " + FormatNumber(w) + " x " + FormatNumber(std::abs(hgt)) +
                               ", not square; expected square cells (resample first, e.g. "
                               "gdalwarp -tr " +
                               FormatNumber(w) + " " + FormatNumber(w) + ")");
  }
}

// The band's values as elevations: its scale and offset applied, its
// nodata and non-finite values NaN. Fails when none is left.
void ToElevations(const std::string& path, GDALRasterBandH band, int band_index,
                  std::vector<double>* values) {
  int has_nodata = 0, has_scale = 0, has_offset = 0;
  const double nodata = GDALGetRasterNoDataValue(band, &has_nodata);
  double scale = GDALGetRasterScale(band, &has_scale);
  double offset = GDALGetRasterOffset(band, &has_offset);
  if (!has_scale) scale = 1.0;
  if (!has_offset) offset = 0.0;
  std::size_t valid = 0;
  for (double& v : *values) {
    if ((has_nodata && v == nodata) || !std::isfinite(v)) {
      v = kNaN;
    } else {
      v = v * scale + offset;
      ++valid;
    }
  }
  if (valid == 0) {
    throw InputError(path, "every cell of band " + std::to_string(band_index) + " is nodata" +
                               (has_nodata ? " (" + FormatNumber(nodata) + ")" : "") +
                               "; expected elevations");
  }
}

}  // namespace

RasterFile ReadRaster(const std::string& path, int band_index) {
  if (path.rfind("/vsi", 0) != 0) CheckInputFile(path);  // GDAL's virtual paths excepted
  gdal::Init();
  gdal::ErrorCapture errors;
  auto gdal_said = [&] {
    const std::string m = errors.message();
    return m.empty() ? std::string() : " (GDAL: " + m + ")";
  };
  gdal::Dataset ds(
      GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
  if (!ds) {
    throw InputError(path, "not a raster GDAL can read" + gdal_said() +
                               "; expected a GeoTIFF or another raster format GDAL reads");
  }
  GDALDatasetH h = ds.get();
  RasterFile out;
  out.driver = GDALGetDriverShortName(GDALGetDatasetDriver(h));
  out.files = gdal::FileList(h);
  if (out.files.empty()) out.files.push_back(path);
  const int bands = GDALGetRasterCount(h);
  if (bands < 1) throw InputError(path, "holds no raster band; expected a raster of elevations");
  if (band_index < 1 || band_index > bands) {
    throw InputError(path, "has " + std::to_string(bands) + " band(s); band " +
                               std::to_string(band_index) + " does not exist (expected 1 to " +
                               std::to_string(bands) + ")");
  }
  double gt[6];
  ReadGeoTransform(path, h, gt);
  const double w = gt[1], hgt = gt[5];
  const int nx = GDALGetRasterXSize(h), ny = GDALGetRasterYSize(h);
  if (nx < 2 || ny < 2) {
    throw InputError(path, "has " + std::to_string(nx) + " x " + std::to_string(ny) +
                               " cells; expected at least 2 x 2");
  }
  if (static_cast<long>(nx) * ny > kMaxCells) {
    throw InputError(path, "raster of " + std::to_string(nx) + " x " + std::to_string(ny) +
                               " cells is too large (limit 1e8 cells); expected a clipped raster");
  }
  GDALRasterBandH band = GDALGetRasterBand(h, band_index);
  if (GDALDataTypeIsComplex(GDALGetRasterDataType(band))) {
    throw InputError(path, "band " + std::to_string(band_index) + " holds complex numbers (" +
                               GDALGetDataTypeName(GDALGetRasterDataType(band)) +
                               "); expected real elevations");
  }
  RasterGrid& g = out.grid;
  g.ncols = nx;
  g.nrows = ny;
  g.cellsize = w;
  g.values.resize(static_cast<std::size_t>(nx) * ny);
  if (GDALRasterIO(band, GF_Read, 0, 0, nx, ny, g.values.data(), nx, ny, GDT_Float64, 0, 0) !=
      CE_None) {
    throw InputError(path,
                     "cannot read the values of band " + std::to_string(band_index) + gdal_said());
  }
  ToElevations(path, band, band_index, &g.values);
  // Rows north to south as stored (height < 0), or south to north (> 0).
  if (hgt > 0.0) {
    for (int r = 0; r < ny / 2; ++r) {
      std::swap_ranges(g.values.begin() + static_cast<std::ptrdiff_t>(r) * nx,
                       g.values.begin() + static_cast<std::ptrdiff_t>(r + 1) * nx,
                       g.values.begin() + static_cast<std::ptrdiff_t>(ny - 1 - r) * nx);
    }
  }
  g.x_center = gt[0] + 0.5 * w;
  g.y_center = hgt < 0.0 ? gt[3] + (ny - 0.5) * hgt : gt[3] + 0.5 * hgt;
  out.crs_wkt = gdal::WktOf(GDALGetSpatialRef(h));
  return out;
}

}  // namespace rockcal::sites
