#include "analysis/common/library_versions.h"

#include <ceres/version.h>
#include <fftw3.h>

#include <Eigen/Core>

namespace chatterlab {

LibraryVersions library_versions() {
  LibraryVersions v;
  v.eigen = std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
            std::to_string(EIGEN_MINOR_VERSION);
  v.ceres = CERES_VERSION_STRING;
  v.fftw = fftw_version;
  return v;
}

}  // namespace chatterlab
