// RGL `.bsdf` tables (include/gonio/rgl/data.h): parsing and the paper's evaluation and
// sampling (Dupuy & Jakob 2018, §5–6).

#include "gonio/rgl/data.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>

#include "gonio/error.h"
#include "gonio/io/file_cache.h"
#include "gonio/io/tensor_file.h"
#include "gonio/math/constants.h"
#include "gonio/spectrum/cie.h"
#include "gonio/spectrum/color_space.h"
#include "gonio/spectrum/d65.h"

namespace gonio {

namespace {

constexpr float kRglPi = 3.14159265358979f;

// The elevation of a unit vector, accurate near the pole (2 asin(|w − z|/2)).
float rgl_elevation(const Vec3& w) {
  const float d = std::sqrt(w.x * w.x + w.y * w.y + (w.z - 1) * (w.z - 1));
  return 2 * std::asin(std::min(0.5f * d, 1.f));
}

// The paper's unit-square coordinates of a direction (§5: θ by u² π/2, φ linear).
float rgl_theta2u(float theta) { return std::sqrt(std::max(theta, 0.f) * (2 / kRglPi)); }
float rgl_phi2u(float phi) { return (phi + kRglPi) / (2 * kRglPi); }

// Slices of a table with one more, innermost, parameter (n_last values): entry l blended
// with l + 1 by w.
BilinearWarp2D::Slices rgl_extend(const BilinearWarp2D::Slices& s, std::uint32_t n_last, std::uint32_t l, float w) {
  BilinearWarp2D::Slices r;
  r.count = 0;
  for (int k = 0; k < s.count; ++k) {
    const auto ks = std::size_t(k);
    r.offset[std::size_t(r.count)] = s.offset[ks] * n_last + l;
    r.weight[std::size_t(r.count++)] = s.weight[ks] * (1 - w);
    if (w > 0) {
      r.offset[std::size_t(r.count)] = s.offset[ks] * n_last + l + 1;
      r.weight[std::size_t(r.count++)] = s.weight[ks] * w;
    }
  }
  return r;
}

const BilinearWarp2D::Slices kRglNoParams = [] {
  BilinearWarp2D::Slices s;
  s.count = 1;
  s.weight[0] = 1;
  return s;
}();

}  // namespace

bool RglData::locate(const Vec3& a, const Vec3& b, Point& p) const {
  if (!(a.z > 0) || !(b.z > 0)) return false;
  Vec3 m{a.x + b.x, a.y + b.y, a.z + b.z};
  const float len = std::sqrt(m.x * m.x + m.y * m.y + m.z * m.z);
  if (!(len > 0) || !std::isfinite(len)) return false;
  m = {m.x / len, m.y / len, m.z / len};
  p.theta_a = rgl_elevation(a);
  p.phi_a = std::atan2(a.y, a.x);
  const float theta_m = rgl_elevation(m), phi_m = std::atan2(m.y, m.x);
  const float umx = rgl_theta2u(theta_m);
  float umy = rgl_phi2u(isotropic ? phi_m - p.phi_a : phi_m);
  umy -= std::floor(umy);
  const float params[2] = {p.phi_a, p.theta_a};
  p.slices = vndf.locate(params);
  const BilinearWarp2D::Result inv = vndf.invert(umx, umy, p.slices);
  p.us_x = inv.x;
  p.us_y = inv.y;
  const float lum = luminance.eval(inv.x, inv.y, p.slices);
  const float sin_m = std::sin(theta_m);
  const float jac = std::max(2 * kRglPi * kRglPi * umx * sin_m, 1e-6f) * 4 * (a.x * m.x + a.y * m.y + a.z * m.z);
  p.pdf = jac > 0 ? std::max(inv.pdf * lum / jac, 0.f) : 0.f;
  if (jacobian) {
    const float s = sigma.eval(rgl_theta2u(p.theta_a), rgl_phi2u(p.phi_a), kRglNoParams);
    p.factor = s > 0 ? std::max(ndf.eval(umx, umy, kRglNoParams), 0.f) / (4 * s) : 0.f;
  } else {
    p.factor = 1;
  }
  if (!std::isfinite(p.pdf)) p.pdf = 0;
  if (!std::isfinite(p.factor)) p.factor = 0;
  return true;
}

bool RglData::sample(const Vec3& a, float u1, float u2, Vec3& b, Point& p) const {
  if (!(a.z > 0)) return false;
  const float theta_a = rgl_elevation(a), phi_a = std::atan2(a.y, a.x);
  const float params[2] = {phi_a, theta_a};
  const BilinearWarp2D::Slices s = vndf.locate(params);
  const BilinearWarp2D::Result us = luminance.sample(u1, u2, s);
  const BilinearWarp2D::Result um = vndf.sample(us.x, us.y, s);
  const float theta_m = um.x * um.x * (kRglPi / 2);
  const float phi_m = (2 * um.y - 1) * kRglPi + (isotropic ? phi_a : 0.f);
  const float st = std::sin(theta_m);
  const Vec3 m{st * std::cos(phi_m), st * std::sin(phi_m), std::cos(theta_m)};
  const float d = a.x * m.x + a.y * m.y + a.z * m.z;
  b = {2 * d * m.x - a.x, 2 * d * m.y - a.y, 2 * d * m.z - a.z};
  const float len = std::sqrt(b.x * b.x + b.y * b.y + b.z * b.z);
  if (!(len > 0)) return false;
  b = {b.x / len, b.y / len, b.z / len};
  if (!(b.z > 0)) return false;
  return locate(a, b, p);
}

Color RglData::value_rgb(const Point& p) const {
  Color c(0);
  for (std::uint32_t k = 0; k < 3; ++k) {
    const float v = rgb.eval(p.us_x, p.us_y, rgl_extend(p.slices, 3, k, 0));
    c[int(k)] = std::max(v, 0.f) * p.factor;
  }
  return c;
}

float RglData::value_at(const Point& p, float lambda) const {
  if (!spectral) return 0;
  const auto nl = std::uint32_t(wavelengths.size());
  std::uint32_t l = 0;
  float w = 0;
  if (nl > 1) {
    const auto it = std::upper_bound(wavelengths.begin() + 1, wavelengths.end() - 1, lambda);
    l = std::uint32_t(it - wavelengths.begin()) - 1;
    w = std::clamp((lambda - wavelengths[l]) / (wavelengths[l + 1] - wavelengths[l]), 0.f, 1.f);
    if (!std::isfinite(w)) w = 0;
  }
  const float v = spectra.eval(p.us_x, p.us_y, rgl_extend(p.slices, nl, l, w));
  return std::max(v, 0.f) * p.factor;
}

RglData parse_rgl(const TensorFile& tf) {
  RglData d;
  d.label = tf.label();
  const TensorField& desc = tf.require("description", TensorDtype::UInt8, 1);
  d.description.assign(desc.data.begin(), desc.data.end());
  const TensorField& jac = tf.require("jacobian", TensorDtype::UInt8, 1);
  if (jac.shape[0] != 1) tf.fail("jacobian", "shape [" + std::to_string(jac.shape[0]) + "], expected [1]");
  d.jacobian = jac.data[0] != 0;
  const std::vector<float> theta_i = tf.floats("theta_i", 1), phi_i = tf.floats("phi_i", 1);
  auto increasing = [&](const std::vector<float>& v, const char* name, float lo, float hi) {
    if (v.empty()) tf.fail(name, "no values");
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (v[i] < lo || v[i] > hi)
        tf.fail(name, "value " + format_number(v[i]) + " at index " + std::to_string(i) + " outside [" +
                          format_number(lo) + ", " + format_number(hi) + "]");
      if (i > 0 && !(v[i] > v[i - 1])) tf.fail(name, "values not increasing at index " + std::to_string(i));
    }
  };
  increasing(theta_i, "theta_i", 0, kRglPi / 2 + 1e-4f);
  increasing(phi_i, "phi_i", -kRglPi - 1e-3f, kRglPi + 1e-3f);
  const std::uint64_t nt = theta_i.size(), np = phi_i.size();
  d.n_theta_i = nt;
  d.n_phi_i = np;
  d.isotropic = np <= 2;
  if (!d.isotropic) {
    const int reduction = int(std::lround(2 * kRglPi / (phi_i.back() - phi_i.front())));
    if (reduction != 1)
      tf.fail("phi_i", "spans " + format_number(phi_i.back() - phi_i.front()) + " rad: symmetry reduction " +
                           std::to_string(reduction) + ", only a full turn (reduction 1) is read");
  }
  std::vector<std::vector<float>> params2 = {phi_i, theta_i};
  auto shape_text = [](const std::vector<std::uint64_t>& s) {
    std::string t = "[";
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (i) t.append(", ");
      t.append(std::to_string(s[i]));
    }
    t.push_back(']');
    return t;
  };
  auto nonnegative = [&](const std::vector<float>& v, const char* name) {
    for (std::size_t i = 0; i < v.size(); ++i)
      if (v[i] < 0) tf.fail(name, "negative value " + format_number(v[i]) + " at index " + std::to_string(i));
  };
  auto warp = [&](const char* name, const std::vector<float>& v, const std::vector<std::uint64_t>& shape,
                  std::vector<std::vector<float>> params, bool normalize, bool cdf) {
    const std::uint64_t nx = shape.back(), ny = shape[shape.size() - 2];
    if (nx < 2 || ny < 2 || nx > 4096 || ny > 4096)
      tf.fail(name, "shape " + shape_text(shape) + ": each of the last two axes must have 2 to 4096 entries");
    try {
      return BilinearWarp2D(std::uint32_t(nx), std::uint32_t(ny), v, std::move(params), normalize, cdf);
    } catch (const std::invalid_argument& e) {
      tf.fail(name, e.what());
    }
  };
  // The NDF and projected area: interpolated only (Warp2D0, not normalized).
  for (const char* name : {"ndf", "sigma"}) {
    const std::vector<float> v = tf.floats(name, 2);
    nonnegative(v, name);
    const auto& shape = tf.find(name)->shape;
    (std::string(name) == "ndf" ? d.ndf : d.sigma) = warp(name, v, shape, {}, false, false);
  }
  auto check_lead = [&](const char* name, const std::vector<std::uint64_t>& shape) {
    if (shape[0] != np || shape[1] != nt)
      tf.fail(name, "shape " + shape_text(shape) + " does not start with [phi_i, theta_i] = [" + std::to_string(np) +
                        ", " + std::to_string(nt) + "]");
  };
  {
    const std::vector<float> v = tf.floats("vndf", 4);
    nonnegative(v, "vndf");
    const auto& shape = tf.find("vndf")->shape;
    check_lead("vndf", shape);
    d.vndf = warp("vndf", v, shape, params2, true, true);
  }
  std::vector<std::uint64_t> lum_shape;
  {
    const std::vector<float> v = tf.floats("luminance", 4);
    nonnegative(v, "luminance");
    lum_shape = tf.find("luminance")->shape;
    check_lead("luminance", lum_shape);
    d.luminance = warp("luminance", v, lum_shape, params2, true, true);
    d.n_sample = lum_shape[2];
  }
  auto check_value_shape = [&](const char* name, const std::vector<std::uint64_t>& shape, std::uint64_t channels) {
    check_lead(name, shape);
    if (shape[2] != channels || shape[3] != lum_shape[2] || shape[4] != lum_shape[3])
      tf.fail(name, "shape " + shape_text(shape) + ", expected [" + std::to_string(np) + ", " + std::to_string(nt) +
                        ", " + std::to_string(channels) + ", " + std::to_string(lum_shape[2]) + ", " +
                        std::to_string(lum_shape[3]) + "] (luminance's sample grid)");
  };
  d.spectral = tf.find("spectra") != nullptr;
  if (d.spectral) {
    d.wavelengths = tf.floats("wavelengths", 1);
    increasing(d.wavelengths, "wavelengths", 1, 1e5f);
    const std::vector<float> v = tf.floats("spectra", 5);
    const auto& shape = tf.find("spectra")->shape;
    check_value_shape("spectra", shape, d.wavelengths.size());
    if (d.wavelengths.size() < 2) tf.fail("wavelengths", "fewer than 2 wavelengths");
    d.spectra = warp("spectra", v, shape, {phi_i, theta_i, d.wavelengths}, false, false);
  }
  if (tf.find("rgb")) {
    const std::vector<float> v = tf.floats("rgb", 5);
    check_value_shape("rgb", tf.find("rgb")->shape, 3);
    d.rgb = warp("rgb", v, tf.find("rgb")->shape, {phi_i, theta_i, {0.f, 1.f, 2.f}}, false, false);
  } else if (d.spectral) {
    // RGB mode's reduction of a spectral file: each node's spectrum (interpolated linearly
    // between the file's wavelengths, constant beyond them) as a reflectance under D65,
    // in linear sRGB, unclamped (cie.h, color_space.h): rgb = W s with
    // W[c][l] = Σ_c' M[c][c'] ∫ hat_l(λ) D65(λ) x̄_c'(λ) dλ / ∫ ȳ.
    const std::size_t nl = d.wavelengths.size();
    std::vector<std::array<double, 3>> w(nl, {0, 0, 0});
    for (std::size_t l = 0; l < nl; ++l) {
      auto hat = [&](double lambda) {
        const auto& wl = d.wavelengths;
        if (lambda <= wl.front()) return l == 0 ? 1.0 : 0.0;
        if (lambda >= wl.back()) return l == nl - 1 ? 1.0 : 0.0;
        if (l > 0 && lambda >= wl[l - 1] && lambda <= wl[l]) return (lambda - wl[l - 1]) / (wl[l] - wl[l - 1]);
        if (l + 1 < nl && lambda >= wl[l] && lambda <= wl[l + 1]) return (wl[l + 1] - lambda) / (wl[l + 1] - wl[l]);
        return 0.0;
      };
      const XYZ xyz = integrate_xyz([&](double lambda) { return hat(lambda) * double(d65(Float(lambda))); });
      const Color c = xyz_to_linear_srgb(xyz);
      w[l] = {double(c[0]), double(c[1]), double(c[2])};
    }
    const auto& shape = tf.find("spectra")->shape;
    const std::size_t nodes = std::size_t(shape[3] * shape[4]), slices = std::size_t(np * nt);
    const std::vector<float> v = tf.floats("spectra", 5);
    std::vector<float> out(slices * 3 * nodes);
    for (std::size_t s = 0; s < slices; ++s)
      for (std::size_t c = 0; c < 3; ++c)
        for (std::size_t i = 0; i < nodes; ++i) {
          double acc = 0;
          for (std::size_t l = 0; l < nl; ++l) acc += w[l][c] * v[(s * nl + l) * nodes + i];
          out[(s * 3 + c) * nodes + i] = float(acc);
        }
    d.rgb = warp("spectra", out, {np, nt, 3, shape[3], shape[4]}, {phi_i, theta_i, {0.f, 1.f, 2.f}}, false, false);
  } else {
    throw InputError(tf.label() + ": field 'spectra' (or 'rgb') is missing");
  }
  return d;
}

std::shared_ptr<const RglData> load_rgl(const std::string& path) {
  return cached_file<RglData>(path, [&] { return std::make_shared<const RglData>(parse_rgl(TensorFile::read(path))); });
}

}  // namespace gonio
