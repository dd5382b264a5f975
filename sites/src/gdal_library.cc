// GDAL loaded when a GIS file is first read or written, not when rockcal
// starts. Debian's libgdal brings some 130 libraries, all bound at load
// (BIND_NOW): linked as usual they cost every rockcal process about 45 ms
// before main (a bare program linked to libgdal starts in 43 ms, one
// without it in 1 ms), a twentieth of a 1000-rock simulation of the
// tutorial, which reads no GIS file. So the project does not link GDAL: this
// file defines each GDAL function that it (and its tests) call, and the
// first call opens GDAL's library (ROCKCAL_GDAL_SONAME, the library CMake
// found) and takes every function from it.
//
// Each definition names the function's parameter types once more; GDAL's
// own header, included above them, makes the compiler check that they are
// the declared ones. A function used anew must be added here (the link
// fails until it is).
#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <dlfcn.h>
#include <gdal.h>
#include <gdal_alg.h>
#include <gdal_utils.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <cstring>
#include <stdexcept>
#include <string>

namespace rockcal::sites::gdal {
namespace {

void* OpenLibrary() {
  void* library = dlopen(ROCKCAL_GDAL_SONAME, RTLD_NOW | RTLD_GLOBAL);
  if (!library) {
    const char* why = dlerror();
    throw std::runtime_error(std::string("cannot load GDAL's library " ROCKCAL_GDAL_SONAME " (") +
                             (why ? why : "unknown reason") +
                             "); expected Debian's libgdal (run.sh installs libgdal-dev)");
  }
  return library;
}

// The function `name` of GDAL's library, which the first call loads.
void* LibrarySymbol(const char* name) {
  static void* const library = OpenLibrary();
  void* symbol = dlsym(library, name);
  if (!symbol)
    throw std::runtime_error(std::string("GDAL's library " ROCKCAL_GDAL_SONAME " has no ") + name);
  return symbol;
}

}  // namespace
}  // namespace rockcal::sites::gdal

// Defines GDAL's function `name` (return type `ret`, parameters `params`,
// passed on as `args`) as a call of the library's.
#define ROCKCAL_GDAL_FORWARD(ret, name, params, args)            \
  ret name params {                                              \
    static const auto function = [] {                            \
      decltype(&::name) f = nullptr;                             \
      void* symbol = rockcal::sites::gdal::LibrarySymbol(#name); \
      std::memcpy(&f, &symbol, sizeof f);                        \
      return f;                                                  \
    }();                                                         \
    return function args;                                        \
  }

ROCKCAL_GDAL_FORWARD(void, CPLErrorReset, (), ())
ROCKCAL_GDAL_FORWARD(void*, CPLGetErrorHandlerUserData, (), ())
ROCKCAL_GDAL_FORWARD(void, CPLPopErrorHandler, (), ())
ROCKCAL_GDAL_FORWARD(void, CPLPushErrorHandlerEx, (CPLErrorHandler a0, void* a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(void, CSLDestroy, (char** a0), (a0))
ROCKCAL_GDAL_FORWARD(void, GDALAllRegister, (), ())
ROCKCAL_GDAL_FORWARD(void, GDALClose, (GDALDatasetH a0), (a0))
ROCKCAL_GDAL_FORWARD(GDALDatasetH, GDALCreate,
                     (GDALDriverH a0, const char* a1, int a2, int a3, int a4, GDALDataType a5,
                      CSLConstList a6),
                     (a0, a1, a2, a3, a4, a5, a6))
ROCKCAL_GDAL_FORWARD(GDALDatasetH, GDALCreateCopy,
                     (GDALDriverH a0, const char* a1, GDALDatasetH a2, int a3, CSLConstList a4,
                      GDALProgressFunc a5, void* a6),
                     (a0, a1, a2, a3, a4, a5, a6))
ROCKCAL_GDAL_FORWARD(int, GDALDataTypeIsComplex, (GDALDataType a0), (a0))
ROCKCAL_GDAL_FORWARD(OGRLayerH, GDALDatasetCreateLayer,
                     (GDALDatasetH a0, const char* a1, OGRSpatialReferenceH a2,
                      OGRwkbGeometryType a3, CSLConstList a4),
                     (a0, a1, a2, a3, a4))
ROCKCAL_GDAL_FORWARD(OGRLayerH, GDALDatasetGetLayer, (GDALDatasetH a0, int a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(OGRLayerH, GDALDatasetGetLayerByName, (GDALDatasetH a0, const char* a1),
                     (a0, a1))
ROCKCAL_GDAL_FORWARD(int, GDALDatasetGetLayerCount, (GDALDatasetH a0), (a0))
ROCKCAL_GDAL_FORWARD(CPLErr, GDALFillRaster, (GDALRasterBandH a0, double a1, double a2),
                     (a0, a1, a2))
ROCKCAL_GDAL_FORWARD(const char*, GDALGetDataTypeName, (GDALDataType a0), (a0))
ROCKCAL_GDAL_FORWARD(GDALDriverH, GDALGetDatasetDriver, (GDALDatasetH a0), (a0))
ROCKCAL_GDAL_FORWARD(const char*, GDALGetDescription, (GDALMajorObjectH a0), (a0))
ROCKCAL_GDAL_FORWARD(GDALDriverH, GDALGetDriverByName, (const char* a0), (a0))
ROCKCAL_GDAL_FORWARD(const char*, GDALGetDriverShortName, (GDALDriverH a0), (a0))
ROCKCAL_GDAL_FORWARD(char**, GDALGetFileList, (GDALDatasetH a0), (a0))
ROCKCAL_GDAL_FORWARD(CPLErr, GDALGetGeoTransform, (GDALDatasetH a0, double* a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(char**, GDALGetMetadata, (GDALMajorObjectH a0, const char* a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(const char*, GDALGetMetadataItem,
                     (GDALMajorObjectH a0, const char* a1, const char* a2), (a0, a1, a2))
ROCKCAL_GDAL_FORWARD(GDALRasterBandH, GDALGetRasterBand, (GDALDatasetH a0, int a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(int, GDALGetRasterCount, (GDALDatasetH a0), (a0))
ROCKCAL_GDAL_FORWARD(GDALDataType, GDALGetRasterDataType, (GDALRasterBandH a0), (a0))
ROCKCAL_GDAL_FORWARD(double, GDALGetRasterNoDataValue, (GDALRasterBandH a0, int* a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(double, GDALGetRasterOffset, (GDALRasterBandH a0, int* a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(double, GDALGetRasterScale, (GDALRasterBandH a0, int* a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(const char*, GDALGetRasterUnitType, (GDALRasterBandH a0), (a0))
ROCKCAL_GDAL_FORWARD(int, GDALGetRasterXSize, (GDALDatasetH a0), (a0))
ROCKCAL_GDAL_FORWARD(int, GDALGetRasterYSize, (GDALDatasetH a0), (a0))
ROCKCAL_GDAL_FORWARD(OGRSpatialReferenceH, GDALGetSpatialRef, (GDALDatasetH a0), (a0))
ROCKCAL_GDAL_FORWARD(GDALDatasetH, GDALOpenEx,
                     (const char* a0, unsigned int a1, const char* const* a2, const char* const* a3,
                      const char* const* a4),
                     (a0, a1, a2, a3, a4))
ROCKCAL_GDAL_FORWARD(CPLErr, GDALRasterIO,
                     (GDALRasterBandH a0, GDALRWFlag a1, int a2, int a3, int a4, int a5, void* a6,
                      int a7, int a8, GDALDataType a9, int a10, int a11),
                     (a0, a1, a2, a3, a4, a5, a6, a7, a8, a9, a10, a11))
ROCKCAL_GDAL_FORWARD(CPLErr, GDALRasterizeGeometries,
                     (GDALDatasetH a0, int a1, const int* a2, int a3, const OGRGeometryH* a4,
                      GDALTransformerFunc a5, void* a6, const double* a7, CSLConstList a8,
                      GDALProgressFunc a9, void* a10),
                     (a0, a1, a2, a3, a4, a5, a6, a7, a8, a9, a10))
ROCKCAL_GDAL_FORWARD(void, GDALSetDescription, (GDALMajorObjectH a0, const char* a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(CPLErr, GDALSetGeoTransform, (GDALDatasetH a0, double* a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(CPLErr, GDALSetMetadataItem,
                     (GDALMajorObjectH a0, const char* a1, const char* a2, const char* a3),
                     (a0, a1, a2, a3))
ROCKCAL_GDAL_FORWARD(CPLErr, GDALSetProjection, (GDALDatasetH a0, const char* a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(CPLErr, GDALSetRasterNoDataValue, (GDALRasterBandH a0, double a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(CPLErr, GDALSetRasterUnitType, (GDALRasterBandH a0, const char* a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(CPLErr, GDALSetSpatialRef, (GDALDatasetH a0, OGRSpatialReferenceH a1),
                     (a0, a1))
ROCKCAL_GDAL_FORWARD(GDALDatasetH, GDALWarp,
                     (const char* a0, GDALDatasetH a1, int a2, GDALDatasetH* a3,
                      const GDALWarpAppOptions* a4, int* a5),
                     (a0, a1, a2, a3, a4, a5))
ROCKCAL_GDAL_FORWARD(void, GDALWarpAppOptionsFree, (GDALWarpAppOptions * a0), (a0))
ROCKCAL_GDAL_FORWARD(GDALWarpAppOptions*, GDALWarpAppOptionsNew,
                     (char** a0, GDALWarpAppOptionsForBinary* a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(const char*, OGRGeometryTypeToName, (OGRwkbGeometryType a0), (a0))
ROCKCAL_GDAL_FORWARD(int, OGR_FD_GetFieldCount, (OGRFeatureDefnH a0), (a0))
ROCKCAL_GDAL_FORWARD(OGRFieldDefnH, OGR_FD_GetFieldDefn, (OGRFeatureDefnH a0, int a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(int, OGR_FD_GetFieldIndex, (OGRFeatureDefnH a0, const char* a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(OGRFeatureH, OGR_F_Create, (OGRFeatureDefnH a0), (a0))
ROCKCAL_GDAL_FORWARD(void, OGR_F_Destroy, (OGRFeatureH a0), (a0))
ROCKCAL_GDAL_FORWARD(GIntBig, OGR_F_GetFID, (OGRFeatureH a0), (a0))
ROCKCAL_GDAL_FORWARD(const char*, OGR_F_GetFieldAsString, (OGRFeatureH a0, int a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(OGRGeometryH, OGR_F_GetGeometryRef, (OGRFeatureH a0), (a0))
ROCKCAL_GDAL_FORWARD(int, OGR_F_IsFieldSetAndNotNull, (OGRFeatureH a0, int a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(void, OGR_F_SetFieldString, (OGRFeatureH a0, int a1, const char* a2),
                     (a0, a1, a2))
ROCKCAL_GDAL_FORWARD(OGRErr, OGR_F_SetGeometryDirectly, (OGRFeatureH a0, OGRGeometryH a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(OGRFieldDefnH, OGR_Fld_Create, (const char* a0, OGRFieldType a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(void, OGR_Fld_Destroy, (OGRFieldDefnH a0), (a0))
ROCKCAL_GDAL_FORWARD(const char*, OGR_Fld_GetNameRef, (OGRFieldDefnH a0), (a0))
ROCKCAL_GDAL_FORWARD(OGRwkbGeometryType, OGR_GT_Flatten, (OGRwkbGeometryType a0), (a0))
ROCKCAL_GDAL_FORWARD(OGRGeometryH, OGR_G_Clone, (OGRGeometryH a0), (a0))
ROCKCAL_GDAL_FORWARD(OGRErr, OGR_G_CreateFromWkt,
                     (char** a0, OGRSpatialReferenceH a1, OGRGeometryH* a2), (a0, a1, a2))
ROCKCAL_GDAL_FORWARD(void, OGR_G_DestroyGeometry, (OGRGeometryH a0), (a0))
ROCKCAL_GDAL_FORWARD(OGRwkbGeometryType, OGR_G_GetGeometryType, (OGRGeometryH a0), (a0))
ROCKCAL_GDAL_FORWARD(int, OGR_G_GetGeometryCount, (OGRGeometryH a0), (a0))
ROCKCAL_GDAL_FORWARD(OGRGeometryH, OGR_G_GetGeometryRef, (OGRGeometryH a0, int a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(int, OGR_G_GetPointCount, (OGRGeometryH a0), (a0))
ROCKCAL_GDAL_FORWARD(double, OGR_G_GetX, (OGRGeometryH a0, int a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(double, OGR_G_GetY, (OGRGeometryH a0, int a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(int, OGR_G_IsEmpty, (OGRGeometryH a0), (a0))
ROCKCAL_GDAL_FORWARD(OGRErr, OGR_L_CreateFeature, (OGRLayerH a0, OGRFeatureH a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(OGRErr, OGR_L_CreateField, (OGRLayerH a0, OGRFieldDefnH a1, int a2),
                     (a0, a1, a2))
ROCKCAL_GDAL_FORWARD(OGRFeatureDefnH, OGR_L_GetLayerDefn, (OGRLayerH a0), (a0))
ROCKCAL_GDAL_FORWARD(const char*, OGR_L_GetName, (OGRLayerH a0), (a0))
ROCKCAL_GDAL_FORWARD(OGRFeatureH, OGR_L_GetNextFeature, (OGRLayerH a0), (a0))
ROCKCAL_GDAL_FORWARD(OGRSpatialReferenceH, OGR_L_GetSpatialRef, (OGRLayerH a0), (a0))
ROCKCAL_GDAL_FORWARD(void, OGR_L_ResetReading, (OGRLayerH a0), (a0))
ROCKCAL_GDAL_FORWARD(OGRErr, OSRExportToWkt, (OGRSpatialReferenceH a0, char** a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(OGRErr, OSRExportToWktEx,
                     (OGRSpatialReferenceH a0, char** a1, const char* const* a2), (a0, a1, a2))
ROCKCAL_GDAL_FORWARD(const char*, OSRGetAuthorityCode, (OGRSpatialReferenceH a0, const char* a1),
                     (a0, a1))
ROCKCAL_GDAL_FORWARD(const char*, OSRGetAuthorityName, (OGRSpatialReferenceH a0, const char* a1),
                     (a0, a1))
ROCKCAL_GDAL_FORWARD(double, OSRGetLinearUnits, (OGRSpatialReferenceH a0, char** a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(const char*, OSRGetName, (OGRSpatialReferenceH a0), (a0))
ROCKCAL_GDAL_FORWARD(OGRErr, OSRImportFromEPSG, (OGRSpatialReferenceH a0, int a1), (a0, a1))
ROCKCAL_GDAL_FORWARD(int, OSRIsGeographic, (OGRSpatialReferenceH a0), (a0))
ROCKCAL_GDAL_FORWARD(int, OSRIsSameEx,
                     (OGRSpatialReferenceH a0, OGRSpatialReferenceH a1, const char* const* a2),
                     (a0, a1, a2))
ROCKCAL_GDAL_FORWARD(OGRSpatialReferenceH, OSRNewSpatialReference, (const char* a0), (a0))
ROCKCAL_GDAL_FORWARD(void, OSRRelease, (OGRSpatialReferenceH a0), (a0))
ROCKCAL_GDAL_FORWARD(OGRErr, OSRSetFromUserInput, (OGRSpatialReferenceH a0, const char* a1),
                     (a0, a1))
ROCKCAL_GDAL_FORWARD(void, VSIFree, (void* a0), (a0))

#undef ROCKCAL_GDAL_FORWARD
