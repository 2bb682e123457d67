// The deterministic microsurfaces of profiles.h.
#include "gonio/measure/profiles.h"

#include <cmath>
#include <stdexcept>

#include "gonio/error.h"
#include "gonio/render/image.h"

namespace gonio::measure {

HeightField flat_height_field(double size) {
  if (!(std::isfinite(size) && size > 0)) throw std::invalid_argument("flat_height_field: size must be positive");
  HeightField f;
  f.n = 1;
  f.size = size;
  f.z.assign(1, 0.0f);
  return f;
}

HeightField vgroove_height_field(double angle_deg, int grooves, double size) {
  if (!(angle_deg > 0 && angle_deg < 90)) throw std::invalid_argument("vgroove_height_field: angle must be in (0, 90)");
  if (grooves < 1 || grooves > kMaxGrooves) throw std::invalid_argument("vgroove_height_field: grooves out of range");
  if (!(std::isfinite(size) && size > 0)) throw std::invalid_argument("vgroove_height_field: size must be positive");
  HeightField f;
  f.n = 2 * grooves;
  f.size = size;
  // One cell per facet: the ridge is tan(angle) · spacing above the valley, so the
  // forward difference over a cell is ±tan(angle) exactly (up to the float of the ridge).
  const auto ridge = static_cast<float>(std::tan(angle_deg * (3.14159265358979323846 / 180)) * f.spacing());
  f.z.resize(static_cast<std::size_t>(f.n) * f.n);
  for (int j = 0; j < f.n; ++j)
    for (int i = 0; i < f.n; ++i) f.z[static_cast<std::size_t>(i) + static_cast<std::size_t>(f.n) * j] = (i % 2) ? ridge : 0.0f;
  return f;
}

HeightField image_height_field(const std::string& path, double height, double size) {
  if (!(std::isfinite(height) && height >= 0)) throw std::invalid_argument("image_height_field: height must be >= 0");
  if (!(std::isfinite(size) && size > 0)) throw std::invalid_argument("image_height_field: size must be positive");
  // PNG codes as data (code / (2^bits − 1)); read_image refuses non-finite EXR texels.
  const render::Image img = render::read_image(path, /*srgb=*/false);
  const int w = img.width(), h = img.height();
  if (w != h)
    throw InputError(path + ": a height image must be square, got " + std::to_string(w) + "x" + std::to_string(h));
  if (w < 1 || w > kMaxImageSide)
    throw InputError(path + ": a height image must be at most " + std::to_string(kMaxImageSide) + " texels on a side, got " +
                     std::to_string(w) + "x" + std::to_string(h));
  HeightField f;
  f.n = w;
  f.size = size;
  f.z.resize(static_cast<std::size_t>(w) * w);
  const double s = height * size;
  for (int r = 0; r < w; ++r)
    for (int x = 0; x < w; ++x) {
      const double z = s * img.at(x, r)[0];
      if (!std::isfinite(z) || std::abs(z) > 3e38)
        throw InputError(path + ": height " + format_number(z) + " at texel (" + std::to_string(x) + ", " +
                         std::to_string(r) + ") is not a finite float");
      f.z[static_cast<std::size_t>(x) + static_cast<std::size_t>(w) * (w - 1 - r)] = static_cast<float>(z);
    }
  return f;
}

}  // namespace gonio::measure
