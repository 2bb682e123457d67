#pragma once
// The explorer page's files (src/explore/web/), compiled into the binary at build time by
// cmake/embed_files.cmake: an installed gonio serves them with nothing else on disk.

#include <span>
#include <string_view>

namespace gonio::explore {

struct WebFile {
  std::string_view name;  // path under web/, e.g. "index.html", "js/plot.js"
  std::string_view data;
};

std::span<const WebFile> web_files();

// The Content-Type of a file name by its extension ("application/octet-stream" otherwise).
std::string_view content_type(std::string_view name);

}  // namespace gonio::explore
