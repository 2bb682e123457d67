#pragma once
// A file written whole or not at all: the one way gonio writes an output file (images,
// MERL tables, JSON results). The data goes into a temporary of a unique name in the
// target's own directory and takes the requested name by an atomic rename only when
// every write, the flush, fsync and the close have succeeded; on any failure the
// temporary is removed, so neither a partial file nor a stray temporary is left behind.
//
// The target must be absent or a regular file: renaming over a device, a FIFO or a
// socket would replace it (run as root, `-o /dev/full` once replaced the machine's
// /dev/full with a 35 MB table). Through a symbolic link the file replaces the link's
// target, so the link is checked by what it points to.

#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <string_view>

namespace gonio {

// Refuses, with InputError "PATH: cannot write WHAT: REASON", a target that is a
// directory, exists and is not a regular file (a device, FIFO or socket), or is a
// read-only file. `what` names the content ("the image", "the table"). Creates nothing.
void check_output_target(const std::string& path, const std::string& what);

class OutputFile {
 public:
  // check_output_target, then creates "<target>.XXXXXX.part" exclusively (O_EXCL).
  // Throws InputError "PATH: ..." when the file cannot be created.
  explicit OutputFile(const std::string& path, std::string what = "the file");
  ~OutputFile();  // removes the temporary unless committed
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  // Reserves `bytes` on disk now, so that a disk too full is found before the work
  // (InputError "no room for WHAT (up to N MB)"); `bytes` is an upper bound: commit
  // trims the file to what was written.
  void reserve(std::uint64_t bytes);

  // Writes the file through `encode` (which returns the number of bytes it wrote),
  // checks every step and renames it over the target. Once only. Throws InputError
  // "PATH: write failed: REASON" (a full disk, EFBIG, ...) and the like.
  void commit(const std::function<std::uint64_t(std::FILE*)>& encode);
  void commit(std::string_view bytes);

  const std::string& path() const { return path_; }
  const std::string& temporary_path() const { return temp_; }

 private:
  std::string path_, what_, target_, temp_;  // target_: path_ with a symbolic link resolved
  int fd_ = -1;
  bool committed_ = false;
};

// OutputFile(path, what).commit(bytes).
void write_file_whole(const std::string& path, std::string_view bytes, const std::string& what = "the file");

}  // namespace gonio
