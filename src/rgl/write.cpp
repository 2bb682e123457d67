// A material written as an RGL .bsdf file (include/gonio/rgl/write.h).

#include "gonio/rgl/write.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "gonio/io/tensor_file.h"
#include "gonio/math/bilinear_warp.h"
#include "gonio/spectrum/rgb_to_spectrum.h"
#include "gonio/spectrum/wavelengths.h"

namespace gonio {

namespace {

constexpr double kRgwPi = 3.14159265358979323846;

Vec3 rgw_dir(double theta, double phi) {
  return {Float(std::sin(theta) * std::cos(phi)), Float(std::sin(theta) * std::sin(phi)), Float(std::cos(theta))};
}

// NDF grid node (ix: θ via u², iy: φ) of an n×ny grid.
struct RgwGrid {
  int nx, ny;
  double theta(int ix) const {
    const double u = double(ix) / (nx - 1);
    return u * u * kRgwPi / 2;
  }
  double phi(int iy) const { return (2.0 * iy / (ny - 1) - 1) * kRgwPi; }
};

// σ(ω) = ∫ D(m) ⟨m, ω⟩₊ dm by the midpoint rule on the grid's cells (D bilinear: the cell
// average of its corners), dm = 2π² u sin θ du dv.
double rgw_sigma(const std::vector<double>& d, const RgwGrid& g, const Vec3& w, int phi_cells_iso) {
  double acc = 0;
  const int ny = phi_cells_iso > 0 ? phi_cells_iso + 1 : g.ny;
  for (int iy = 0; iy + 1 < ny; ++iy) {
    const double v = (iy + 0.5) / (ny - 1);
    const double phi = (2 * v - 1) * kRgwPi;
    for (int ix = 0; ix + 1 < g.nx; ++ix) {
      const double u = (ix + 0.5) / (g.nx - 1);
      const double theta = u * u * kRgwPi / 2;
      const int ry = phi_cells_iso > 0 ? 0 : iy;
      const int ry1 = phi_cells_iso > 0 ? 0 : iy + 1;
      const double dv = 0.25 * (d[std::size_t(ry * g.nx + ix)] + d[std::size_t(ry * g.nx + ix + 1)] +
                                d[std::size_t(ry1 * g.nx + ix)] + d[std::size_t(ry1 * g.nx + ix + 1)]);
      const Vec3 m = rgw_dir(theta, phi);
      const double c = double(m.x) * w.x + double(m.y) * w.y + double(m.z) * w.z;
      if (c <= 0) continue;
      acc += dv * c * 2 * kRgwPi * kRgwPi * u * std::sin(theta) / double(g.nx - 1) / double(ny - 1);
    }
  }
  return acc;
}

}  // namespace

std::vector<std::uint8_t> tabulate_rgl(const BxDF& model, const RglWriteOptions& o) {
  const bool aniso = o.anisotropic;
  const int nt = o.n_theta_i > 0 ? o.n_theta_i : (aniso ? 8 : 16);
  const int np = aniso ? std::max(o.n_phi_i, 3) : 1;
  const int nn = std::max(o.n_ndf, 4), ns = std::max(o.n_sample, 4);
  std::vector<float> wl = o.wavelengths;
  if (wl.empty())
    for (int l = 360; l <= 820; l += 20) wl.push_back(float(l));
  // Isotropic: the NDF has 2 identical φ rows (the readers need 2 nodes per axis).
  const RgwGrid g{nn, aniso ? nn : 2};
  const int iso_phi_cells = aniso ? 0 : 32;  // φ quadrature of σ for an isotropic D
  const std::size_t ng = std::size_t(g.nx) * std::size_t(g.ny);
  // 1. Retro-reflection r(ω) = 4 f(ω, ω) cos θ at the NDF's nodes, then power iteration.
  std::vector<double> retro(ng), d(ng, 1 / kRgwPi), sig(ng, 1);
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      const Vec3 w = rgw_dir(std::min(g.theta(ix), kRgwPi / 2 * 0.9999), aniso ? g.phi(iy) : 0.0);
      const Color f = model.f(w, w, TransportMode::Radiance);
      const double y = 0.2126 * f[0] + 0.7152 * f[1] + 0.0722 * f[2];
      retro[std::size_t(iy * g.nx + ix)] = std::isfinite(y) ? std::max(0.0, 4 * y * double(w.z)) : 0.0;
    }
  auto update_sigma = [&] {
    for (int iy = 0; iy < g.ny; ++iy)
      for (int ix = 0; ix < g.nx; ++ix) {
        if (!aniso && iy > 0) {
          sig[std::size_t(iy * g.nx + ix)] = sig[std::size_t(ix)];
          continue;
        }
        const Vec3 w = rgw_dir(g.theta(ix), aniso ? g.phi(iy) : 0.0);
        sig[std::size_t(iy * g.nx + ix)] = rgw_sigma(d, g, w, iso_phi_cells);
      }
  };
  for (int it = 0; it < 6; ++it) {
    update_sigma();
    for (std::size_t k = 0; k < ng; ++k) d[k] = retro[k] * sig[k];
    // Normalize: σ at the normal is ∫ D cos θm dm.
    const double norm = rgw_sigma(d, g, Vec3{0, 0, 1}, iso_phi_cells);
    if (!(norm > 0)) {
      std::fill(d.begin(), d.end(), 1 / kRgwPi);  // no retro-reflection: a flat (cosine) NDF
      break;
    }
    for (double& v : d) v /= norm;
  }
  // A floor keeps every normal reachable by the VNDF warp (a material that does not
  // retro-reflect still reflects elsewhere): 1e-3 of the mean.
  double mean = 0;
  for (const double v : d) mean += v;
  mean /= double(ng);
  for (double& v : d) v = std::max(v, 1e-3 * mean + 1e-12);
  update_sigma();
  std::vector<float> ndf(ng), sigma(ng);
  for (std::size_t k = 0; k < ng; ++k) {
    ndf[k] = float(d[k]);
    sigma[k] = float(std::max(sig[k], 1e-9));
  }
  const BilinearWarp2D ndf_w(std::uint32_t(g.nx), std::uint32_t(g.ny), ndf, {}, false, false);
  const BilinearWarp2D sigma_w(std::uint32_t(g.nx), std::uint32_t(g.ny), sigma, {}, false, false);
  BilinearWarp2D::Slices one;
  one.count = 1;
  one.weight[0] = 1;

  std::vector<float> theta_i(static_cast<std::size_t>(nt)), phi_i(static_cast<std::size_t>(np));
  for (int t = 0; t < nt; ++t) theta_i[std::size_t(t)] = float(o.theta_i_max_deg * kRgwPi / 180 * t / (nt - 1));
  for (int p = 0; p < np; ++p) phi_i[std::size_t(p)] = aniso ? float((2.0 * p / (np - 1) - 1) * kRgwPi) : 0.f;
  const std::size_t nvn = std::size_t(nn) * std::size_t(nn), nsn = std::size_t(ns) * std::size_t(ns);
  const std::size_t slices = std::size_t(np) * std::size_t(nt), nl = wl.size();
  std::vector<float> vndf(slices * nvn), lum(slices * nsn), rgb(slices * 3 * nsn), spectra(slices * nl * nsn);
  for (int p = 0; p < np; ++p)
    for (int t = 0; t < nt; ++t) {
      const std::size_t s = std::size_t(p) * std::size_t(nt) + std::size_t(t);
      const double phi_a = phi_i[std::size_t(p)], theta_a = theta_i[std::size_t(t)];
      const Vec3 a = rgw_dir(theta_a, phi_a);
      const float u_ax = float(std::sqrt(theta_a * 2 / kRgwPi)), u_ay = float((phi_a + kRgwPi) / (2 * kRgwPi));
      const float sig_a = sigma_w.eval(u_ax, u_ay, one);
      // 2. The VNDF on the (u_θm, u_φm) grid (φm relative to φa when isotropic), as a
      // density on [0,1]²: ⟨a, m⟩₊ D(m)/σ(a) · 2π² u sin θm.
      float* v = vndf.data() + s * nvn;
      for (int iy = 0; iy < nn; ++iy)
        for (int ix = 0; ix < nn; ++ix) {
          const double u = double(ix) / (nn - 1), vy = double(iy) / (nn - 1);
          const double theta_m = u * u * kRgwPi / 2, phi_rel = (2 * vy - 1) * kRgwPi;
          const double phi_m = phi_rel + (aniso ? 0.0 : phi_a);
          const Vec3 m = rgw_dir(theta_m, phi_m);
          const double c = double(a.x) * m.x + double(a.y) * m.y + double(a.z) * m.z;
          const float dm = ndf_w.eval(float(u), float(vy), one);
          v[iy * nn + ix] = c > 0 ? float(c * dm / sig_a * 2 * kRgwPi * kRgwPi * u * std::sin(theta_m)) : 0.f;
        }
      const auto nodes = static_cast<std::uint32_t>(nn);
      const BilinearWarp2D vw(nodes, nodes, std::span<const float>(v, nvn), {}, true, true);
      // 3. The sample grid through the VNDF warp: values f·cos/(D/4σ).
      double lsum = 0;
      float* lv = lum.data() + s * nsn;
      for (int j = 0; j < ns; ++j)
        for (int i = 0; i < ns; ++i) {
          const std::size_t k = std::size_t(j) * std::size_t(ns) + std::size_t(i);
          const BilinearWarp2D::Result um = vw.sample(float(i) / float(ns - 1), float(j) / float(ns - 1), one);
          const double theta_m = double(um.x) * um.x * kRgwPi / 2;
          const double phi_m = (2.0 * um.y - 1) * kRgwPi + (aniso ? 0.0 : phi_a);
          const Vec3 m = rgw_dir(theta_m, phi_m);
          const double c = double(a.x) * m.x + double(a.y) * m.y + double(a.z) * m.z;
          const Vec3 b{Float(2 * c * m.x - a.x), Float(2 * c * m.y - a.y), Float(2 * c * m.z - a.z)};
          Color val(0);
          if (b.z > 0 && c > 0) {
            const Color f = model.f(a, b, TransportMode::Radiance);
            const float factor = ndf_w.eval(um.x, um.y, one) / (4 * sig_a);
            if (factor > 0)
              for (int ch = 0; ch < 3; ++ch) val[ch] = std::isfinite(f[ch]) ? std::max(0.f, f[ch] * b.z / factor) : 0.f;
          }
          for (int ch = 0; ch < 3; ++ch) rgb[(s * 3 + std::size_t(ch)) * nsn + k] = val[ch];
          for (std::size_t l = 0; l < nl; ++l)
            spectra[(s * nl + l) * nsn + k] = rgb_unbounded(val, SampledWavelengths::single(wl[l]))[0];
          const double y = 0.2126 * val[0] + 0.7152 * val[1] + 0.0722 * val[2];
          lv[k] = float(y);
          lsum += y;
        }
      const float floor = float(1e-3 * lsum / double(nsn) + 1e-12);
      for (std::size_t k = 0; k < nsn; ++k) lv[k] += floor;
    }
  const auto n64 = [](auto x) { return std::uint64_t(x); };
  std::vector<TensorField> fields;
  TensorField desc;
  desc.name = "description";
  desc.dtype = TensorDtype::UInt8;
  desc.shape = {o.description.size()};
  desc.data.assign(o.description.begin(), o.description.end());
  fields.push_back(desc);
  TensorField jac;
  jac.name = "jacobian";
  jac.dtype = TensorDtype::UInt8;
  jac.shape = {1};
  jac.data = {1};
  fields.push_back(jac);
  fields.push_back(float_field("theta_i", {n64(nt)}, theta_i));
  fields.push_back(float_field("phi_i", {n64(np)}, phi_i));
  fields.push_back(float_field("ndf", {n64(g.ny), n64(g.nx)}, ndf));
  fields.push_back(float_field("sigma", {n64(g.ny), n64(g.nx)}, sigma));
  fields.push_back(float_field("vndf", {n64(np), n64(nt), n64(nn), n64(nn)}, vndf));
  fields.push_back(float_field("luminance", {n64(np), n64(nt), n64(ns), n64(ns)}, lum));
  fields.push_back(float_field("wavelengths", {n64(nl)}, wl));
  fields.push_back(float_field("spectra", {n64(np), n64(nt), n64(nl), n64(ns), n64(ns)}, spectra));
  fields.push_back(float_field("rgb", {n64(np), n64(nt), 3, n64(ns), n64(ns)}, rgb));
  return encode_tensor_file(fields);
}

}  // namespace gonio
