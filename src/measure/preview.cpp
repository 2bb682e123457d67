// write_surface_preview (preview.h).
#include "gonio/measure/preview.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "gonio/render/image.h"

namespace gonio::measure {
namespace {

// The light, from the upper left (−x, +y) and 40° above the horizon: slopes facing it
// brighten, slopes facing away darken, which reads as relief.
struct Light {
  double x, y, z;
};
constexpr Light kLight = {-0.5417, 0.5417, 0.6428};  // (−cos40°/√2, cos40°/√2, sin40°)
constexpr double kAmbient = 0.08;

// Lambertian shading of a facet with forward-difference slopes (sx, sy): its normal is
// (−sx, −sy, 1)/√(1 + sx² + sy²) (heightfield.h).
double shade(double sx, double sy) {
  const double nl = (-sx * kLight.x - sy * kLight.y + kLight.z) / std::sqrt(1 + sx * sx + sy * sy);
  return kAmbient + (1 - kAmbient) * std::max(nl, 0.0);
}

// A ramp from deep blue (low) through grey to warm sand (high), t in [0, 1].
Color tint(double t) {
  const double lo[3] = {0.35, 0.45, 0.85}, mid[3] = {0.8, 0.8, 0.8}, hi[3] = {0.95, 0.7, 0.4};
  Color c;
  for (int k = 0; k < 3; ++k)
    c[k] = static_cast<Float>(t < 0.5 ? lo[k] + (mid[k] - lo[k]) * (2 * t) : mid[k] + (hi[k] - mid[k]) * (2 * t - 1));
  return c;
}

}  // namespace

int preview_side(int n, int max_side) {
  if (n < 1 || max_side < 1) throw std::invalid_argument("preview_side: n and max_side must be positive");
  if (n <= max_side) return n * (max_side / n);
  const int cells = (n + max_side - 1) / max_side;  // cells per pixel side
  return n / cells;
}

void write_surface_preview(const HeightField& field, const std::string& path, const PreviewOptions& options) {
  const int n = field.n;
  if (n < 1 || field.z.size() != static_cast<std::size_t>(n) * n)
    throw std::invalid_argument("write_surface_preview: malformed height field");
  const int side = preview_side(n, options.max_side);
  const double inv_h = 1 / field.spacing();
  float zmin = field.z[0], zmax = field.z[0];
  for (const float z : field.z) {
    zmin = std::min(zmin, z);
    zmax = std::max(zmax, z);
  }
  const double zrange = zmax > zmin ? double(zmax) - double(zmin) : 1.0;

  render::Image img(side, side);
  for (int row = 0; row < side; ++row) {
    const int py = side - 1 - row;  // row 0 at the top is the largest y
    for (int px = 0; px < side; ++px) {
      double s = 0, zsum = 0;
      if (n <= side) {
        // Magnified: the pixel centre lies in one triangle of one cell.
        const double x = (px + 0.5) * n / side, y = (py + 0.5) * n / side;
        const int i = static_cast<int>(x), j = static_cast<int>(y);
        const double u = x - i, v = y - j;
        const double z00 = field.at(i, j), z10 = field.at(i + 1, j), z01 = field.at(i, j + 1), z11 = field.at(i + 1, j + 1);
        if (u + v < 1) s = shade((z10 - z00) * inv_h, (z01 - z00) * inv_h);  // lower-left triangle
        else s = shade((z11 - z01) * inv_h, (z11 - z10) * inv_h);            // upper-right triangle
        zsum = z00;
      } else {
        // Reduced: the mean shading of the block of c × c cells (both triangles each).
        const int c = n / side;
        for (int dj = 0; dj < c; ++dj)
          for (int di = 0; di < c; ++di) {
            const int i = px * c + di, j = py * c + dj;
            const double z00 = field.at(i, j), z10 = field.at(i + 1, j), z01 = field.at(i, j + 1), z11 = field.at(i + 1, j + 1);
            s += shade((z10 - z00) * inv_h, (z01 - z00) * inv_h) + shade((z11 - z01) * inv_h, (z11 - z10) * inv_h);
            zsum += z00;
          }
        s /= 2.0 * c * c;
        zsum /= double(c) * c;
      }
      const Color base = options.tint_by_height ? tint(std::clamp((zsum - zmin) / zrange, 0.0, 1.0)) : Color(0.8f);
      img.at(px, row) = base * static_cast<Float>(s);
    }
  }
  render::write_png(img, path, render::PngOptions{0, render::ToneMap::Clamp});
}

}  // namespace gonio::measure
