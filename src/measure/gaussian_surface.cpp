// Spectral synthesis of a Gaussian random height field (gaussian_surface.h).
//
// A stationary Gaussian process on the periodic patch is a sum of Fourier modes with
// independent complex Gaussian coefficients whose variance is the power spectrum S(k) at
// the mode's wave vector; a real field needs a Hermitian spectrum, c(−k) = conj c(k), so
// only the half plane kx ≥ 0 is drawn and FFTW's complex-to-real transform supplies the
// rest. For the Gaussian autocorrelation C(x, y) = σ² exp(−x²/ℓx² − y²/ℓy²) the power
// spectrum is its Fourier transform S(k) = σ² π ℓx ℓy exp(−(kx² ℓx² + ky² ℓy²)/4), so a
// coefficient's amplitude is √S ∝ exp(−(kx² ℓx² + ky² ℓy²)/8); σ is fixed afterwards by
// the slope normalisation.
//
// Both axes reach their RMS slope exactly: by Parseval the realised field's mean squared
// forward difference along x is Σ |c_k|² |e^{i kx h} − 1|² = Σ |c_k|² 4 sin²(kx h/2)
// (likewise along y), a function of ℓx and ℓy for the drawn coefficients. With
// ℓx = ℓ e^{t/2} and ℓy = ℓ e^{−t/2} (geometric mean ℓ), the ratio Vx/Vy falls
// monotonically in t; t is solved so that Vx/Vy = (alpha_x/alpha_y)², and one height
// scale then makes Vx = alpha_x²/2 and hence Vy = alpha_y²/2. For an isotropic alpha this
// only removes the sampling noise between the two axes (t stays near 0); for an
// anisotropic one ℓx/ℓy ≈ alpha_y/alpha_x, as for an isotropic surface stretched along
// the smoother axis.
#include "gonio/measure/gaussian_surface.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include <fftw3.h>

#include "gonio/rng.h"

namespace gonio::measure {
namespace {

constexpr double kTwoPi = 6.283185307179586476925;

// One draw of the standard normal distribution (Box & Muller 1958), both values used.
struct NormalSource {
  Pcg32 rng;
  double spare = 0;
  bool has_spare = false;

  double next() {
    if (has_spare) {
      has_spare = false;
      return spare;
    }
    double u1 = 0;
    do u1 = rng.next_double(); while (u1 <= 0);  // log(0) excluded
    const double u2 = rng.next_double();
    const double r = std::sqrt(-2 * std::log(u1));
    spare = r * std::sin(kTwoPi * u2);
    has_spare = true;
    return r * std::cos(kTwoPi * u2);
  }
};

// FFTW's planner is not thread-safe (FFTW manual §5.4); execution is.
std::mutex& fftw_planner_mutex() {
  static std::mutex m;
  return m;
}

struct FftwFree {
  void operator()(void* p) const { fftw_free(p); }
};

// A mode of the half spectrum that carries weight: its signed wave numbers (cycles per
// patch), its drawn coefficient and its multiplicity in the full spectrum (1 on the
// kx = 0 column, whose conjugate partners are stored explicitly; 2 elsewhere).
struct Mode {
  int p, q;           // kx = 2π p, ky = 2π q (patch side 1)
  std::size_t index;  // in FFTW's n × (n/2 + 1) complex array
  double power;       // |g|² · multiplicity
  double dx2, dy2;    // 4 sin²(π p/n), 4 sin²(π q/n): |e^{i k h} − 1|² with h = 1/n
};

// Mean squared forward difference per axis for correlation lengths (lx, ly), up to the
// common factor that the final height scale removes.
void slope_variances(const std::vector<Mode>& modes, double lx, double ly, double& vx, double& vy) {
  vx = vy = 0;
  const double ax = kTwoPi * kTwoPi * lx * lx / 4, ay = kTwoPi * kTwoPi * ly * ly / 4;
  for (const Mode& m : modes) {
    // |√S|² = S ∝ exp(−(kx² ℓx² + ky² ℓy²)/4)
    const double w = m.power * std::exp(-(ax * m.p * m.p + ay * m.q * m.q));
    vx += w * m.dx2;
    vy += w * m.dy2;
  }
}

// Whether the x slopes are steeper than wanted, Vx > target · Vy, at ℓx = ℓ e^{t/2},
// ℓy = ℓ e^{−t/2}.
bool too_steep_x(const std::vector<Mode>& modes, double target, double ell, double t) {
  double vx = 0, vy = 0;
  slope_variances(modes, ell * std::exp(t / 2), ell * std::exp(-t / 2), vx, vy);
  return vx > target * vy;
}

void check(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("gaussian_height_field: " + what);
}

}  // namespace

double default_gaussian_correlation(int resolution) {
  return std::max(1.0 / 32, 8.0 / std::max(resolution, 1));
}

CorrelationLengths nominal_correlation_lengths(const GaussianSurfaceParams& params) {
  const double ell = params.correlation > 0 ? params.correlation : default_gaussian_correlation(params.resolution);
  const double r = std::sqrt(params.alpha_y / params.alpha_x);
  return {ell * r, ell / r};
}

HeightField gaussian_height_field(const GaussianSurfaceParams& params) {
  using P = GaussianSurfaceParams;
  const int n = params.resolution;
  check(n >= P::kMinResolution && n <= P::kMaxResolution, "resolution out of range");
  check(params.alpha_x > 0 && params.alpha_x <= 2 && params.alpha_y > 0 && params.alpha_y <= 2, "alpha out of range");
  check(std::isfinite(params.size) && params.size > 0, "size must be positive");
  const double ell = params.correlation > 0 ? params.correlation : default_gaussian_correlation(n);
  check(ell * n >= P::kMinCorrelationCells && ell <= P::kMaxCorrelation, "correlation out of range");
  const CorrelationLengths lengths = nominal_correlation_lengths(params);
  for (const double l : {lengths.x, lengths.y})
    check(l * n >= P::kMinCorrelationCells && l <= P::kMaxCorrelation, "anisotropy stretches a correlation length out of range");

  const int half = n / 2 + 1;  // kx = 0 .. ⌊n/2⌋
  const auto signed_index = [n](int k) { return k <= n / 2 ? k : k - n; };
  const bool even = n % 2 == 0;

  // Draw every coefficient of the half plane, in a fixed order (row q, then p), so that
  // the field depends on the seed alone.
  std::vector<std::complex<double>> g(static_cast<std::size_t>(n) * half);
  NormalSource normal{Pcg32(params.seed, 0x6761757373ULL)};  // stream "gauss"
  for (int qi = 0; qi < n; ++qi)
    for (int p = 0; p < half; ++p) {
      const double re = normal.next(), im = normal.next();
      g[static_cast<std::size_t>(qi) * half + p] = {re * std::sqrt(0.5), im * std::sqrt(0.5)};
    }
  // Hermitian symmetry on the kx = 0 column: c(0, −q) = conj c(0, q). The mean (k = 0)
  // and the Nyquist modes (|p| or |q| = n/2 for even n, their own conjugate partners,
  // which a real field would need real) are left out: at ≥ 2 cells per correlation
  // length they carry less than 1e-4 of the variance.
  for (int qi = 1; qi < n; ++qi)
    if (qi > n - qi) g[static_cast<std::size_t>(qi) * half] = std::conj(g[static_cast<std::size_t>(n - qi) * half]);

  // Solve Vx/Vy = (αx/αy)² for t by bisection (Vx/Vy decreases as ℓx grows), first
  // within ±1 of the continuous-field guess (the realised ratio is within a few percent
  // of it), else in a range doubled until it brackets the root. Only the modes whose amplitude at the extreme lengths of the
  // search exceeds exp(−50) of the largest take part: for ℓ = 1/32 a few ten thousand.
  const double t_guess = std::log(params.alpha_y / params.alpha_x);  // ℓx/ℓy = e^t = αy/αx
  const double target = (params.alpha_x / params.alpha_y) * (params.alpha_x / params.alpha_y);
  std::vector<Mode> modes;
  double lo = 0, hi = 0;
  for (double search = 1;; search *= 2) {
    if (search > 64) throw std::logic_error("gaussian_height_field: anisotropy not reached within the search range");
    const double lx_min = ell * std::exp((t_guess - search) / 2), ly_min = ell * std::exp(-(t_guess + search) / 2);
    modes.clear();
    for (int qi = 0; qi < n; ++qi)
      for (int p = 0; p < half; ++p) {
        const int q = signed_index(qi);
        if (p == 0 && q == 0) continue;
        if (even && (p == n / 2 || std::abs(q) == n / 2)) continue;
        const double e = kTwoPi * kTwoPi * (lx_min * lx_min * p * p + ly_min * ly_min * q * q) / 4;
        if (e > 100) continue;
        const std::size_t idx = static_cast<std::size_t>(qi) * half + p;
        const double sp = std::sin(kTwoPi / 2 * p / n), sq = std::sin(kTwoPi / 2 * q / n);
        modes.push_back({p, q, idx, std::norm(g[idx]) * (p == 0 ? 1 : 2), 4 * sp * sp, 4 * sq * sq});
      }
    lo = t_guess - search;
    hi = t_guess + search;
    if (too_steep_x(modes, target, ell, lo) && !too_steep_x(modes, target, ell, hi)) break;
  }
  while (hi - lo > 1e-10) {
    const double mid = (lo + hi) / 2;
    (too_steep_x(modes, target, ell, mid) ? lo : hi) = mid;
  }
  const double t = (lo + hi) / 2;
  const double lx = ell * std::exp(t / 2), ly = ell * std::exp(-t / 2);

  // The spectrum: c_k = g_k √S(k) (up to a constant), then the inverse transform.
  const std::size_t n_real = static_cast<std::size_t>(n) * n;
  std::unique_ptr<fftw_complex[], FftwFree> spec(fftw_alloc_complex(static_cast<std::size_t>(n) * half));
  std::unique_ptr<double[], FftwFree> real(fftw_alloc_real(n_real));
  if (!spec || !real) throw std::bad_alloc();
  std::fill_n(&spec[0][0], 2 * static_cast<std::size_t>(n) * half, 0.0);
  const double ax = kTwoPi * kTwoPi * lx * lx / 8, ay = kTwoPi * kTwoPi * ly * ly / 8;
  for (const Mode& m : modes) {
    const std::complex<double> c = g[m.index] * std::exp(-(ax * m.p * m.p + ay * m.q * m.q));
    spec[m.index][0] = c.real();
    spec[m.index][1] = c.imag();
  }
  fftw_plan plan = nullptr;
  {
    const std::lock_guard<std::mutex> lock(fftw_planner_mutex());
    // FFTW_ESTIMATE: the same algorithm every run, so the same bits for a seed.
    plan = fftw_plan_dft_c2r_2d(n, n, spec.get(), real.get(), FFTW_ESTIMATE);
  }
  if (!plan) throw std::runtime_error("gaussian_height_field: FFTW could not plan a " + std::to_string(n) + "² transform");
  fftw_execute(plan);  // row-major [y][x]: real[i + n j] is z at (i, j), the HeightField layout
  {
    const std::lock_guard<std::mutex> lock(fftw_planner_mutex());
    fftw_destroy_plan(plan);
  }

  // The realised mean squared slope along x (h = 1/n), then one scale for both axes.
  double sum_dx2 = 0;
  for (int j = 0; j < n; ++j) {
    const double* row = real.get() + static_cast<std::size_t>(j) * n;
    for (int i = 0; i < n; ++i) {
      const double d = (row[(i + 1) % n] - row[i]) * n;
      sum_dx2 += d * d;
    }
  }
  const double rms_x = std::sqrt(sum_dx2 / static_cast<double>(n_real));
  if (!(rms_x > 0) || !std::isfinite(rms_x)) throw std::logic_error("gaussian_height_field: degenerate field");
  // Beckmann slopes have variance α²/2 per axis (Walter et al. 2007 eq. 28).
  const double scale = params.alpha_x / std::sqrt(2.0) / rms_x * params.size;

  HeightField f;
  f.n = n;
  f.size = params.size;
  f.z.resize(n_real);
  for (std::size_t k = 0; k < n_real; ++k) f.z[k] = static_cast<float>(real[k] * scale);
  return f;
}

}  // namespace gonio::measure
