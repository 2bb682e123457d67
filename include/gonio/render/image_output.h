#pragma once
// An image file on its way to disk. The file is created under a unique temporary name in
// the output's own directory when the object is made, so that an output that cannot be
// written (a missing or read-only directory, a path that is a directory, no space) is
// found before any rendering; the image goes into that file and takes the requested
// name only when every byte is on disk, by an atomic rename. Two renders to the same
// path never share a file: each has its own temporary, and the last to finish wins
// whole. A temporary that never received its image is removed.

#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "gonio/io/output_file.h"
#include "gonio/render/image.h"

namespace gonio::render {

class ImageOutput {
 public:
  // Creates "<path>.XXXXXX.part" (exclusively: O_CREAT | O_EXCL). Throws InputError
  // "<path>: <problem>" when the extension is not .exr or .png, when `path` is a directory
  // or something else than a regular file, or when the file cannot be created.
  explicit ImageOutput(const std::string& path);
  // The temporary is removed unless the image was committed (OutputFile).
  ImageOutput(const ImageOutput&) = delete;
  ImageOutput& operator=(const ImageOutput&) = delete;

  // Reserves on disk the most space an image of this size can take in the output's
  // format, so that a disk too full for it is found now (InputError "no space").
  // `exr_layers`: how many RGB layers an OpenEXR output holds (write_exr_layers).
  void reserve(int width, int height, int exr_layers = 1);

  // Writes the image in the format the extension names (.exr: linear float; .png:
  // tone-mapped sRGB with `png`) and renames it over the path. Once only. Throws
  // InputError on any failure; the temporary is then removed by the destructor.
  void write(const Image& img, const PngOptions& png = {});
  // The same in a given format, whatever the extension (write_exr and write_png).
  void write_exr(const Image& img);
  void write_png(const Image& img, const PngOptions& png = {});
  // OpenEXR with several images of one size as named layers (image.h, ExrLayer).
  void write_exr_layers(const std::vector<ExrLayer>& layers);

  const std::string& path() const { return path_; }
  const std::string& temporary_path() const { return file_.temporary_path(); }

  // Upper bounds of the file sizes of the two encoders (bytes), for reserve().
  static std::uint64_t max_exr_bytes(int width, int height, int layers = 1);
  static std::uint64_t max_png_bytes(int width, int height);

 private:
  enum class Format { Unknown, Exr, Png };
  // Encodes into the temporary (encode returns the file's length), checks every step,
  // renames.
  void finish(const std::function<std::uint64_t(std::FILE*)>& encode);

  std::string path_;
  OutputFile file_;  // the temporary, its checks and its rename (gonio/io/output_file.h)
  Format format_ = Format::Unknown;
};

}  // namespace gonio::render
