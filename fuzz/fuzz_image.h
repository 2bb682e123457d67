#pragma once
// The body of the PNG and EXR targets: bytes → scratch file → render::read_image. Only
// InputError may escape; a decoded image's pixels must be finite.

#include <cmath>
#include <cstdint>

#include "fuzz_util.h"
#include "gonio/error.h"
#include "gonio/render/image.h"

inline int fuzz_read_image(const uint8_t* data, size_t size, const char* extension) {
  const std::string path = gonio_fuzz::write_scratch(data, size, extension);
  for (bool srgb : {true, false}) {
    try {
      const gonio::render::Image img = gonio::render::read_image(path, srgb);
      for (const auto& px : img.pixels())
        for (int c = 0; c < gonio::Color::size(); ++c)
          if (!std::isfinite(px[c])) gonio_fuzz::fail("non-finite pixel", px[c]);
    } catch (const gonio::InputError&) {
      return 0;
    }
  }
  return 0;
}
