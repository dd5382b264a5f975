// Helpers around the GDAL C API for the libraries that read and write GIS
// files (sites, reports): drivers registered once, owning handles, and
// GDAL's error messages caught (never printed) so that each failure becomes
// one error naming the file. rockcal does not link GDAL: its library is
// loaded at the first call of any of its functions (gdal_library.cc), so a
// run that reads and writes no GIS file never loads it. A call throws
// std::runtime_error when the library cannot be loaded.
#ifndef ROCKCAL_SITES_GDAL_UTIL_H_
#define ROCKCAL_SITES_GDAL_UTIL_H_

#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <memory>
#include <string>
#include <vector>

namespace rockcal::sites::gdal {

// Registers GDAL's drivers (once per process).
void Init();

// While alive, GDAL's error messages go to this object instead of stderr;
// message() is the first failure (or warning when there was no failure).
class ErrorCapture final {
 public:
  ErrorCapture();
  ~ErrorCapture();
  ErrorCapture(const ErrorCapture&) = delete;
  ErrorCapture& operator=(const ErrorCapture&) = delete;
  // "" when GDAL reported nothing; otherwise the message, trimmed to one line.
  std::string message() const;
  // True when GDAL reported a failure (not only a warning).
  bool failed() const { return failed_; }
  // The first failure's message, or `fallback` when there was none.
  std::string Cause(const std::string& fallback) const {
    return failure_.empty() ? fallback : message();
  }

 private:
  static void CPL_STDCALL Handle(CPLErr level, CPLErrorNum number, const char* text);
  std::string failure_, warning_;
  bool failed_ = false;
};

struct DatasetCloser {
  void operator()(void* ds) const { GDALClose(static_cast<GDALDatasetH>(ds)); }
};
using Dataset = std::unique_ptr<void, DatasetCloser>;

struct SrsReleaser {
  void operator()(void* srs) const { OSRRelease(static_cast<OGRSpatialReferenceH>(srs)); }
};
using Srs = std::unique_ptr<void, SrsReleaser>;

struct FeatureDestroyer {
  void operator()(void* f) const { OGR_F_Destroy(static_cast<OGRFeatureH>(f)); }
};
using Feature = std::unique_ptr<void, FeatureDestroyer>;

// Every file of an open dataset (the main file and its side files: .aux.xml,
// world file, .shx, .dbf, .prj, ...), as GDAL lists them.
std::vector<std::string> FileList(GDALDatasetH ds);

// The CRS as WKT (GDAL's default WKT 1, or WKT2 when WKT 1 cannot express
// it); "" for a null handle.
std::string WktOf(OGRSpatialReferenceH srs);

// A new spatial reference read from WKT; null (nothing thrown) when it does
// not parse.
Srs SrsFromWkt(const std::string& wkt);

// An in-memory raster of nx x ny Int32 or Float64 cells whose cell centres
// are the nodes (x0 + i s, y0 + j s), row 0 the NORTH row (j = ny - 1),
// every cell set to `fill`; `wkt` (may be empty) as its CRS.
Dataset NodeRaster(int nx, int ny, double x0, double y0, double s, GDALDataType type, double fill,
                   const std::string& wkt);

// Reads band 1 of a NodeRaster into `data` (nx * ny values of `type`, row
// 0 the north row).
void ReadNodeRaster(GDALDatasetH ds, GDALDataType type, void* data);

}  // namespace rockcal::sites::gdal

#endif  // ROCKCAL_SITES_GDAL_UTIL_H_
