#include "rockcal/sites/gdal_util.h"

#include <mutex>
#include <stdexcept>

namespace rockcal::sites::gdal {

void Init() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

ErrorCapture::ErrorCapture() {
  CPLErrorReset();
  CPLPushErrorHandlerEx(&ErrorCapture::Handle, this);
}

ErrorCapture::~ErrorCapture() { CPLPopErrorHandler(); }

void CPL_STDCALL ErrorCapture::Handle(CPLErr level, CPLErrorNum, const char* text) {
  auto* self = static_cast<ErrorCapture*>(CPLGetErrorHandlerUserData());
  if (!self) return;
  if (level >= CE_Failure) self->failed_ = true;
  if (!text) return;
  std::string& slot = level >= CE_Failure ? self->failure_ : self->warning_;
  if (level >= CE_Warning && slot.empty()) slot = text;
}

std::string ErrorCapture::message() const {
  std::string m = failure_.empty() ? warning_ : failure_;
  const std::size_t end = m.find('\n');
  if (end != std::string::npos) m.resize(end);
  return m;
}

std::vector<std::string> FileList(GDALDatasetH ds) {
  std::vector<std::string> files;
  char** list = GDALGetFileList(ds);
  for (char** f = list; f && *f; ++f) files.emplace_back(*f);
  CSLDestroy(list);
  return files;
}

std::string WktOf(OGRSpatialReferenceH srs) {
  if (!srs) return "";
  char* text = nullptr;
  std::string wkt;
  if (OSRExportToWkt(srs, &text) == OGRERR_NONE && text) wkt = text;
  CPLFree(text);
  if (wkt.empty()) {
    text = nullptr;
    const char* const options[] = {"FORMAT=WKT2_2019", nullptr};
    if (OSRExportToWktEx(srs, &text, options) == OGRERR_NONE && text) wkt = text;
    CPLFree(text);
  }
  return wkt;
}

Srs SrsFromWkt(const std::string& wkt) {
  Srs srs(OSRNewSpatialReference(nullptr));
  if (OSRSetFromUserInput(static_cast<OGRSpatialReferenceH>(srs.get()), wkt.c_str()) != OGRERR_NONE)
    return nullptr;
  return srs;
}

Dataset NodeRaster(int nx, int ny, double x0, double y0, double s, GDALDataType type, double fill,
                   const std::string& wkt) {
  Init();
  GDALDriverH mem = GDALGetDriverByName("MEM");
  if (!mem) throw std::logic_error("GDAL has no MEM driver");
  Dataset ds(GDALCreate(mem, "", nx, ny, 1, type, nullptr));
  if (!ds) throw std::runtime_error("GDAL cannot create an in-memory raster");
  // The cell (i, r) is centred on node (i, ny - 1 - r).
  double transform[6] = {x0 - 0.5 * s, s, 0.0, y0 + (ny - 1) * s + 0.5 * s, 0.0, -s};
  if (GDALSetGeoTransform(ds.get(), transform) != CE_None ||
      (!wkt.empty() && GDALSetProjection(ds.get(), wkt.c_str()) != CE_None) ||
      GDALFillRaster(GDALGetRasterBand(ds.get(), 1), fill, 0.0) != CE_None)
    throw std::runtime_error("GDAL cannot set up an in-memory raster");
  return ds;
}

void ReadNodeRaster(GDALDatasetH ds, GDALDataType type, void* data) {
  const int nx = GDALGetRasterXSize(ds), ny = GDALGetRasterYSize(ds);
  if (GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Read, 0, 0, nx, ny, data, nx, ny, type, 0, 0) !=
      CE_None)
    throw std::runtime_error("GDAL cannot read an in-memory raster");
}

}  // namespace rockcal::sites::gdal
