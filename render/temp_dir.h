// A private scratch folder removed with everything in it when the object goes away.
#pragma once

#include <filesystem>
#include <string>

namespace chatterlab::render {

class TempDir {
 public:
  // Creates <system temp>/<prefix>XXXXXX with mode 0700 (mkdtemp). Throws RenderError.
  explicit TempDir(const std::string& prefix = "chatterlab-render-");
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  ~TempDir();

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace chatterlab::render
