// Versions of the numerical libraries that compute the project's numbers (results.json
// provenance): Eigen and Ceres from their headers at build time, FFTW from the library linked.
#pragma once

#include <string>

namespace chatterlab {

struct LibraryVersions {
  std::string eigen;  // "3.4.0"
  std::string ceres;  // "2.1.0"
  std::string fftw;   // "fftw-3.3.10-sse2-avx" (fftw_version)
};

LibraryVersions library_versions();

}  // namespace chatterlab
