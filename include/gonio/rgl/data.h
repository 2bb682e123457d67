#pragma once
// A measured material in the RGL `.bsdf` format (Dupuy & Jakob 2018, "An Adaptive
// Parameterization for Efficient Material Acquisition and Rendering", ACM TOG 37(6)):
// the tables of a tensor_file (io/tensor_file.h) and the paper's evaluation and sampling
// (§5–6), as the public readers do it (rgl-epfl/brdf-loader powitacq, pbrt-v4
// MeasuredBxDF, Mitsuba 3 `measured`). Immutable once loaded; shared by every model that
// points at it. docs/measured.md describes the format and gonio's use of it.
//
// Directions a (the file's θi/φi axis: gonio's wo) and b (gonio's wi), both in the upper
// hemisphere. The file's value is
//   value(a, b) = S(u_s) · D(u_m) / (4 σ(u_a))   (jacobian = 1; S(u_s) alone when 0)
//             = f(wo = a, wi = b) · cos θ_b     (SPEC §2)
// with m = (a + b)/|a + b|, u_m = (√(2θm/π), (φm − [isotropic] φa + π)/2π mod 1),
// u_a = (√(2θa/π), (φa + π)/2π), u_s = VNDF⁻¹(u_m | φa, θa) the point of the sample space
// whose VNDF warp gives m, S the spectra (or rgb) table at u_s, D the NDF and σ the
// projected area. Sampling b from a: u_s ~ luminance(· | φa, θa), u_m = VNDF(u_s), then
// m, then b = 2(a·m)m − a; its density per solid angle is
//   p(b) = L(u_s) · V(u_m) / (2π² u_m,θ sin θm · 4 (a·m))
// (the luminance and VNDF densities on [0,1]², then the Jacobians u_m → m and m → b).

#include <memory>
#include <string>
#include <vector>

#include "gonio/color.h"
#include "gonio/math/bilinear_warp.h"
#include "gonio/math/vec3.h"

namespace gonio {

class TensorFile;

struct RglData {
  std::string label;        // the file, for messages
  std::string description;  // the file's `description`
  bool isotropic = true;
  bool jacobian = true;
  bool spectral = false;  // the file holds `spectra` (else only `rgb`)
  std::vector<float> wavelengths;  // nm, spectral files
  std::size_t n_theta_i = 0, n_phi_i = 0, n_sample = 0;  // resolution, for messages and docs
  BilinearWarp2D ndf, sigma, vndf, luminance;
  BilinearWarp2D rgb;      // params φi, θi, channel (0, 1, 2): the file's or reduced from spectra
  BilinearWarp2D spectra;  // params φi, θi, λ (spectral files only)
  // The reciprocity threshold of `gonio check`: the table's interpolation error
  // (docs/measured.md).
  float reciprocity_tolerance = 0.2f;

  // Where (a, b) falls in the tables.
  struct Point {
    BilinearWarp2D::Slices slices;  // φa, θa
    float phi_a = 0, theta_a = 0;
    float us_x = 0, us_y = 0;  // sample-space point
    float factor = 0;          // D/(4σ) (1 without jacobian)
    float pdf = 0;             // p(b) per solid angle
  };
  // false when a or b is at or below the horizon or a + b vanishes.
  bool locate(const Vec3& a, const Vec3& b, Point& p) const;
  // b sampled from a (true when b lands above the horizon).
  bool sample(const Vec3& a, float u1, float u2, Vec3& b, Point& p) const;
  // f·cos θ_b at the located point, linear sRGB (negatives clamped to 0).
  Color value_rgb(const Point& p) const;
  // f·cos θ_b at wavelength λ (nm) at the located point (spectral files).
  float value_at(const Point& p, float lambda) const;
};

// Parses the fields of an RGL file; every missing, mistyped, misshapen or non-finite field
// is an InputError naming the file and the field.
RglData parse_rgl(const TensorFile& file);
// Reads and parses a file once per path (a cache like load_measured's).
std::shared_ptr<const RglData> load_rgl(const std::string& path);

}  // namespace gonio
