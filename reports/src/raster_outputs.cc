#include "rockcal/reports/raster_outputs.h"

#include <cpl_error.h>
#include <gdal.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "rockcal/core/format.h"
#include "rockcal/sites/gdal_util.h"

#ifndef ROCKCAL_VERSION
#define ROCKCAL_VERSION "unknown"
#endif

namespace rockcal::reports {
namespace {

namespace fs = std::filesystem;

GDALDriverH Driver(const char* name) {
  sites::gdal::Init();
  GDALDriverH driver = GDALGetDriverByName(name);
  if (driver == nullptr)
    throw std::runtime_error(std::string("GDAL has no ") + name +
                             " driver; cannot write the rasters");
  return driver;
}

bool IsFileName(const std::string& name) {
  if (name.empty()) return false;
  for (char ch : name) {
    const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                    (ch >= '0' && ch <= '9') || ch == '_' || ch == '-';
    if (!ok) return false;
  }
  return true;
}

void CheckShape(const core::RasterSet& r) {
  if (r.nx <= 0 || r.ny <= 0)
    throw std::logic_error("WriteRasterFiles: the raster set has no cells (" +
                           std::to_string(r.nx) + " x " + std::to_string(r.ny) + ")");
  if (!(r.spacing > 0.0) || !std::isfinite(r.spacing) || !std::isfinite(r.x0) ||
      !std::isfinite(r.y0))
    throw std::logic_error("WriteRasterFiles: the raster set has no valid grid (spacing " +
                           core::FormatNumber(r.spacing) + ")");
  if (r.bands.empty()) throw std::logic_error("WriteRasterFiles: the raster set has no band");
  const std::size_t cells = static_cast<std::size_t>(r.nx) * static_cast<std::size_t>(r.ny);
  for (const core::RasterBand& b : r.bands) {
    if (!IsFileName(b.name))
      throw std::logic_error("WriteRasterFiles: band name '" + b.name +
                             "' is not a file name (letters, digits, '_', '-')");
    if (b.values.size() != cells)
      throw std::logic_error("WriteRasterFiles: band " + b.name + " has " +
                             std::to_string(b.values.size()) + " values for " +
                             std::to_string(cells) + " cells");
  }
}

// The band's values as written: rows north first, NaN as kRasterNodata.
// Throws (an internal failure) at a value that is infinite or beyond Float32.
std::vector<float> NorthFirst(const core::RasterSet& r, const core::RasterBand& b) {
  std::vector<float> out(b.values.size());
  for (int j = 0; j < r.ny; ++j) {
    for (int i = 0; i < r.nx; ++i) {
      const double v = b.values[static_cast<std::size_t>(j) * r.nx + i];
      float& f = out[static_cast<std::size_t>(r.ny - 1 - j) * r.nx + i];
      if (std::isnan(v)) {
        f = static_cast<float>(kRasterNodata);
      } else if (!std::isfinite(v) || std::fabs(v) > std::numeric_limits<float>::max()) {
        throw std::runtime_error("internal failure: rasters.tif band " + b.name + " cell (" +
                                 std::to_string(i) + ", " + std::to_string(j) + ") is " +
                                 core::FormatNumber(v) +
                                 ", not a finite Float32 number; nothing written");
      } else {
        f = static_cast<float>(v);
      }
    }
  }
  return out;
}

using Dataset = sites::gdal::Dataset;

// GDAL's creation options: NAME=VALUE strings and the null-terminated list
// of them that GDAL takes.
class Options final {
 public:
  explicit Options(std::vector<std::string> items) : items_(std::move(items)) {
    for (const std::string& i : items_) list_.push_back(i.c_str());
    list_.push_back(nullptr);
  }
  Options(const Options&) = delete;
  Options& operator=(const Options&) = delete;
  CSLConstList list() const { return list_.data(); }

 private:
  std::vector<std::string> items_;
  std::vector<const char*> list_;
};

// An in-memory dataset of the bands `first` .. `last` - 1 with the frame's
// geotransform and CRS; `described`: with each band's description and unit
// (the GeoTIFF keeps them; an ASCII grid would need a side file for them).
Dataset MemoryDataset(const core::RasterSet& r, std::vector<std::vector<float>>& values,
                      std::size_t first, std::size_t last, const RasterFrame& frame, bool described,
                      const sites::gdal::ErrorCapture& errors) {
  Dataset ds(GDALCreate(Driver("MEM"), "", r.nx, r.ny, static_cast<int>(last - first), GDT_Float32,
                        nullptr));
  if (!ds)
    throw std::runtime_error("cannot build the rasters in memory: " +
                             errors.Cause("GDAL's MEM driver failed"));
  std::array<double, 6> transform = RasterGeoTransform(r, frame.units);
  GDALSetGeoTransform(ds.get(), transform.data());
  if (!frame.crs_wkt.empty() && GDALSetProjection(ds.get(), frame.crs_wkt.c_str()) != CE_None)
    throw std::runtime_error("cannot use the site's CRS for the rasters: " +
                             errors.Cause("GDAL does not read its WKT"));
  for (std::size_t k = first; k < last; ++k) {
    GDALRasterBandH band = GDALGetRasterBand(ds.get(), static_cast<int>(k - first) + 1);
    GDALSetRasterNoDataValue(band, kRasterNodata);
    if (described) {
      GDALSetDescription(band, RasterBandDescription(r.bands[k]).c_str());
      GDALSetRasterUnitType(band, r.bands[k].unit.c_str());
    }
    if (GDALRasterIO(band, GF_Write, 0, 0, r.nx, r.ny, values[k].data(), r.nx, r.ny, GDT_Float32, 0,
                     0) != CE_None)
      throw std::runtime_error("cannot build the rasters in memory: " +
                               errors.Cause("writing band " + r.bands[k].name + " failed"));
  }
  return ds;
}

// Copies `source` to `path` with `driver` and closes it; throws naming
// `shown` and GDAL's cause.
void CopyTo(const char* driver, GDALDatasetH source, const std::string& path,
            const Options& options, const std::string& shown) {
  sites::gdal::ErrorCapture errors;
  Dataset copy(GDALCreateCopy(Driver(driver), path.c_str(), source, FALSE, options.list(), nullptr,
                              nullptr));
  if (copy) copy.reset();  // closing writes the last blocks: failures land in `errors`
  if (!errors.failed() && std::filesystem::exists(path)) return;
  throw std::runtime_error("cannot write " + shown + ": " + errors.Cause("GDAL failed"));
}

std::string Pid() { return std::to_string(::getpid()); }

}  // namespace

std::array<double, 6> RasterGeoTransform(const core::RasterSet& rasters, sites::Units units) {
  const double metres = sites::LengthToSI(1.0, units);
  // Back from SI to the file's unit: to 12 significant digits, which drops
  // the noise of the round trip (198.00000000000003 ft) and keeps 1e-5 ft
  // of a state-plane coordinate.
  auto to_file = [metres](double v) {
    if (metres == 1.0) return v;
    char text[32];
    std::snprintf(text, sizeof text, "%.12g", v / metres);
    return std::strtod(text, nullptr);
  };
  const double s = to_file(rasters.spacing);
  const double west = to_file(rasters.x0 - 0.5 * rasters.spacing);
  const double north = to_file(rasters.y0 + (rasters.ny - 0.5) * rasters.spacing);
  return {west, s, 0.0, north, 0.0, -s};
}

std::string RasterBandDescription(const core::RasterBand& band) {
  return band.name + ": " + band.description + " [" + band.unit + "]";
}

void WriteRasterFiles(const std::string& folder, const core::RasterSet& rasters,
                      const RasterFrame& frame) {
  CheckShape(rasters);
  std::vector<std::vector<float>> values;
  for (const core::RasterBand& b : rasters.bands) values.push_back(NorthFirst(rasters, b));

  const std::string tif = folder + "/rasters.tif", tif_temp = tif + ".tmp-" + Pid();
  const std::string asc = folder + "/rasters", asc_temp = asc + ".tmp-" + Pid();
  const std::string asc_old = asc + ".old-" + Pid();
  std::error_code ec;
  auto clean = [&] {
    std::error_code ignored;
    fs::remove(tif_temp, ignored);
    fs::remove(tif_temp + ".aux.xml", ignored);
    fs::remove_all(asc_temp, ignored);
  };
  try {
    {
      sites::gdal::ErrorCapture errors;
      Dataset all = MemoryDataset(rasters, values, 0, rasters.bands.size(), frame, true, errors);
      GDALSetMetadataItem(all.get(), "ROCKS_RELEASED", std::to_string(rasters.released).c_str(),
                          nullptr);
      GDALSetMetadataItem(all.get(), "TIFFTAG_SOFTWARE", "rockcal " ROCKCAL_VERSION, nullptr);
      const Options options({"COMPRESS=DEFLATE", "INTERLEAVE=BAND", "BIGTIFF=IF_SAFER"});
      CopyTo("GTiff", all.get(), tif_temp, options, tif);
    }
    fs::remove_all(asc_temp, ec);
    if (!fs::create_directory(asc_temp, ec))
      throw std::runtime_error("cannot write " + asc + "/ (its temporary folder " + asc_temp +
                               "): " + ec.message());
    for (std::size_t k = 0; k < rasters.bands.size(); ++k) {
      sites::gdal::ErrorCapture errors;
      Dataset one = MemoryDataset(rasters, values, k, k + 1, frame, false, errors);
      const Options options({"SIGNIFICANT_DIGITS=7"});
      const std::string name = rasters.bands[k].name + ".asc";
      CopyTo("AAIGrid", one.get(), asc_temp + "/" + name, options, asc + "/" + name);
    }
    // Into place: the folder (an earlier one moved aside first), then the GeoTIFF.
    if (fs::exists(fs::symlink_status(asc, ec))) {
      fs::remove_all(asc_old, ec);
      fs::rename(asc, asc_old, ec);
      if (ec)
        throw std::runtime_error("cannot replace " + asc +
                                 "/ (moving the old one aside): " + ec.message());
    }
    fs::rename(asc_temp, asc, ec);
    if (ec)
      throw std::runtime_error("cannot write " + asc + "/ (renaming its temporary folder " +
                               asc_temp + "): " + ec.message());
    fs::remove_all(asc_old, ec);
    fs::rename(tif_temp, tif, ec);
    if (ec)
      throw std::runtime_error("cannot write " + tif + " (renaming its temporary file " + tif_temp +
                               "): " + ec.message());
  } catch (...) {
    clean();
    throw;
  }
}

RasterFrame SiteRasterFrame(const sites::Site& site) {
  RasterFrame frame;
  frame.crs_wkt = site.crs_wkt;
  frame.units = site.units;
  return frame;
}

}  // namespace rockcal::reports
