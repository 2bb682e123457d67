#pragma once
// Pinhole camera: the eye at `position` looking at `look_at`, vertical field of view
// `fov_deg`. Pixel (0, 0) is the top-left corner of the image. An orthographic camera
// (glTF's, gltf_loader.h) shoots parallel rays along the view direction from a film of
// half-height `ortho_half_height` (and half-width that times the image's aspect).

#include <cmath>
#include <cstdint>
#include <optional>

#include "gonio/math/vec3.h"
#include "gonio/render/ray.h"

namespace gonio::render {

// Most pixels a film may have (width x height): its buffers take some 100 bytes a pixel,
// so 2^25 pixels (e.g. 8192 x 4096) stay within a few GB; more is refused up front.
inline constexpr std::int64_t kMaxFilmPixels = std::int64_t(1) << 25;

struct Camera {
  Vec3 position{0, 1, 5}, look_at{0, 1, 0}, up{0, 1, 0};
  Float fov_deg = 40;
  Float ortho_half_height = 0;  // > 0: orthographic
  int width = 640, height = 360;
  // A linear polarizer in front of the film (polarized rendering, issue 15): its
  // transmission axis in degrees counter-clockwise from the image's +x axis (SPEC §1).
  std::optional<Float> polarizer_deg;

  // The basis, computed once before rendering.
  void prepare() {
    forward_ = normalize(look_at - position);
    right_ = normalize(cross(forward_, up));
    up_ = cross(right_, forward_);
    tan_half_ = std::tan(fov_deg * kPi / 360);
  }

  // The image's x axis (to the right) in world space, after prepare(): the s axis of the
  // film's Stokes frame (SPEC §1: Q = I_x − I_y).
  Vec3 image_x() const { return right_; }

  // The ray through the film point (px, py) in pixel units (pixel centres at +0.5).
  Ray generate(Float px, Float py) const {
    const Float aspect = Float(width) / Float(height);
    const Float xn = 2 * px / Float(width) - 1, yn = 1 - 2 * py / Float(height);
    if (ortho_half_height > 0)
      return {position + right_ * (xn * ortho_half_height * aspect) + up_ * (yn * ortho_half_height), forward_};
    const Float x = xn * tan_half_ * aspect;
    const Float y = yn * tan_half_;
    return {position, normalize(forward_ + right_ * x + up_ * y)};
  }

 private:
  Vec3 forward_{0, 0, -1}, right_{1, 0, 0}, up_{0, 1, 0};
  Float tan_half_ = 0.36f;
};

}  // namespace gonio::render
