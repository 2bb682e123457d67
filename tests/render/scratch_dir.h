#pragma once
// A temporary directory for a test's scene, mesh and image files, removed at the end.

#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace gonio::test {

class ScratchDir {
 public:
  explicit ScratchDir(const char* stem = "gonio_render") {
    std::string tmpl = (std::filesystem::temp_directory_path() / (std::string(stem) + "_XXXXXX")).string();
    if (!::mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
    path_ = tmpl;
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  // Writes `contents` to `name` inside the directory and returns its path.
  std::string file(const std::string& name, const std::string& contents) const {
    const std::string p = path(name);
    std::ofstream(p) << contents;
    return p;
  }
  std::string path(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace gonio::test
