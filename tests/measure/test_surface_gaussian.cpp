// The Gaussian random microsurface (include/gonio/measure/gaussian_surface.h): its facet
// slopes are Beckmann-distributed with the requested alpha per axis, its heights have
// the Gaussian autocorrelation it was made with, and it tiles the plane. Every statistic
// is computed here from the heights, with the triangulation of heightfield.h.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "gonio/math/vec3.h"
#include "gonio/measure/gaussian_surface.h"
#include "gonio/microfacet.h"

namespace gm = gonio::measure;

namespace {

// Forward-difference slopes of every triangle: the lower-left triangle of cell (i, j)
// has ((z(i+1, j) − z(i, j))/h, (z(i, j+1) − z(i, j))/h), the upper-right one
// ((z(i+1, j+1) − z(i, j+1))/h, (z(i+1, j+1) − z(i+1, j))/h) (heightfield.h).
struct Slopes {
  std::vector<double> x, y;
};
Slopes facet_slopes(const gm::HeightField& f) {
  Slopes s;
  const double h = f.spacing();
  for (int j = 0; j < f.n; ++j)
    for (int i = 0; i < f.n; ++i) {
      const double z00 = f.at(i, j), z10 = f.at(i + 1, j), z01 = f.at(i, j + 1), z11 = f.at(i + 1, j + 1);
      s.x.push_back((z10 - z00) / h);
      s.y.push_back((z01 - z00) / h);
      s.x.push_back((z11 - z01) / h);
      s.y.push_back((z11 - z10) / h);
    }
  return s;
}

double rms(const std::vector<double>& v) {
  double s = 0;
  for (const double d : v) s += d * d;
  return std::sqrt(s / double(v.size()));
}

gm::HeightField field(double ax, double ay, int n, std::uint64_t seed = 1, double correlation = 0) {
  gm::GaussianSurfaceParams p;
  p.alpha_x = ax;
  p.alpha_y = ay;
  p.resolution = n;
  p.seed = seed;
  p.correlation = correlation;
  return gm::gaussian_height_field(p);
}

double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

}  // namespace

// Beckmann slopes have RMS α/√2 per axis (Walter et al. 2007 eq. 28): within 2% (issue
// 13 item 5), isotropic and anisotropic, the axes not swapped.
TEST(GaussianSurface, RmsSlopePerAxisIsAlphaOverSqrt2) {
  struct Case {
    double ax, ay;
  };
  for (const Case c : {Case{0.3, 0.3}, Case{0.1, 0.1}, Case{1.0, 1.0}, Case{0.2, 0.6}, Case{0.8, 0.25}}) {
    const Slopes s = facet_slopes(field(c.ax, c.ay, 128));
    EXPECT_NEAR(rms(s.x) / (c.ax / std::sqrt(2.0)), 1.0, 0.02) << c.ax << " " << c.ay;
    EXPECT_NEAR(rms(s.y) / (c.ay / std::sqrt(2.0)), 1.0, 0.02) << c.ax << " " << c.ay;
  }
  // size scales heights, not slopes
  gm::GaussianSurfaceParams p;
  p.alpha_x = p.alpha_y = 0.4;
  p.resolution = 64;
  p.size = 250;
  const gm::HeightField f = gm::gaussian_height_field(p);
  EXPECT_EQ(f.size, 250);
  EXPECT_NEAR(rms(facet_slopes(f).x) / (0.4 / std::sqrt(2.0)), 1.0, 0.02);
}

// The area-weighted histogram of facet normals is D(m) cos θm (every triangle has the same
// projected area; Walter et al. 2007 §3), with D gonio's Beckmann. Ten bins in θm, each
// compared with the integral of 2π D(θ) cos θ sin θ over it (Simpson's rule).
TEST(GaussianSurface, FacetNormalHistogramIsBeckmann) {
  for (const double alpha : {0.1, 0.3, 0.6, 1.0}) {  // seeds differ: not one surface scaled
    const gonio::MicrofacetDistribution d{gonio::MicrofacetType::Beckmann, float(alpha), float(alpha)};
    const auto density = [&](double th) {  // 2π D(θ) cos θ sin θ
      const gonio::Vec3 m(float(std::sin(th)), 0, float(std::cos(th)));
      return 2 * 3.14159265358979323846 * d.D(m) * std::cos(th) * std::sin(th);
    };
    // Bin edges where tan θ = α·(0.25, 0.5, ..., 2.25): about 1 to 20% of the facets each.
    std::vector<double> edges{0};
    for (int k = 1; k <= 9; ++k) edges.push_back(std::atan(alpha * 0.25 * k));
    edges.push_back(1.5707963267948966);
    const Slopes s = facet_slopes(field(alpha, alpha, 256, static_cast<std::uint64_t>(alpha * 10)));
    std::vector<double> observed(edges.size() - 1, 0);
    for (std::size_t k = 0; k < s.x.size(); ++k) {
      const double th = std::atan(std::hypot(s.x[k], s.y[k]));
      const auto b = std::upper_bound(edges.begin(), edges.end(), th) - edges.begin() - 1;
      observed[static_cast<std::size_t>(std::min<std::ptrdiff_t>(b, std::ptrdiff_t(observed.size()) - 1))] += 1;
    }
    double total_expected = 0;
    for (std::size_t b = 0; b + 1 < edges.size(); ++b) {
      const int steps = 2000;  // Simpson, even
      const double a = edges[b], w = (edges[b + 1] - a) / steps;
      double sum = density(a) + density(edges[b + 1]);
      for (int i = 1; i < steps; ++i) sum += (i % 2 ? 4 : 2) * density(a + i * w);
      const double expected = sum * w / 3;
      total_expected += expected;
      const double got = observed[b] / double(s.x.size());
      // Neighbouring facets are correlated: the tolerance is for the ~4000 correlation
      // areas of the patch, not for half a million independent normals.
      EXPECT_NEAR(got, expected, 0.005 + 0.05 * expected) << "alpha " << alpha << " bin " << b;
    }
    EXPECT_NEAR(total_expected, 1.0, 1e-4) << alpha;  // the integration itself
  }
}

// Not only the variance: the standardised slopes follow the normal distribution (the
// Kolmogorov–Smirnov distance to Φ, and the kurtosis), and x and y slopes are uncorrelated.
TEST(GaussianSurface, SlopesAreGaussian) {
  const double ax = 0.3, ay = 0.5;
  const Slopes s = facet_slopes(field(ax, ay, 256, 3));
  for (int axis = 0; axis < 2; ++axis) {
    std::vector<double> u = axis ? s.y : s.x;
    const double sd = (axis ? ay : ax) / std::sqrt(2.0);
    double m4 = 0;
    for (double& v : u) {
      v /= sd;
      m4 += v * v * v * v;
    }
    m4 /= double(u.size());
    EXPECT_NEAR(m4, 3.0, 0.15) << "kurtosis, axis " << axis;
    std::sort(u.begin(), u.end());
    double ks = 0;
    for (std::size_t k = 0; k < u.size(); k += 7) ks = std::max(ks, std::abs(normal_cdf(u[k]) - (k + 0.5) / double(u.size())));
    EXPECT_LT(ks, 0.02) << "KS distance, axis " << axis;
  }
  double sxy = 0;
  for (std::size_t k = 0; k < s.x.size(); ++k) sxy += s.x[k] * s.y[k];
  EXPECT_NEAR(sxy / double(s.x.size()) / (ax / std::sqrt(2.0) * ay / std::sqrt(2.0)), 0.0, 0.05);
}

// The heights' autocorrelation is the Gaussian C(r) = σ² exp(−r²/ℓ²) of the spectrum:
// C(ℓ/2)/C(0) = e^{−1/4}, C(ℓ)/C(0) = e^{−1}, C(2ℓ)/C(0) = e^{−4}, along x and y. The
// estimate from one patch of 32 × 32 correlation areas scatters by about 0.01 at ℓ/2,
// 0.02 at ℓ and 0.03 at 2ℓ (six seeds); a spectrum amplitude of S instead of √S would
// give e^{−1/2} = 0.61 at ℓ.
TEST(GaussianSurface, AutocorrelationIsGaussian) {
  const int n = 512, cells = 16;  // ℓ = 16 cells, 32 lengths per patch
  const gm::HeightField f = field(0.3, 0.3, n, 5, double(cells) / n);
  double c0 = 0, mean = 0;
  for (const float z : f.z) mean += z;
  mean /= double(f.z.size());
  EXPECT_NEAR(mean, 0.0, 1e-6 * f.size) << "the mean height is 0 (no k = 0 mode)";
  for (const float z : f.z) c0 += (z - mean) * (z - mean);
  for (const double lag : {0.5, 1.0, 2.0}) {
    const int d = static_cast<int>(lag * cells);
    double cx = 0, cy = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        cx += (f.at(i, j) - mean) * (f.at(i + d, j) - mean);
        cy += (f.at(i, j) - mean) * (f.at(i, j + d) - mean);
      }
    const double tol = lag < 1 ? 0.03 : (lag < 2 ? 0.05 : 0.08);
    EXPECT_NEAR(cx / c0, std::exp(-lag * lag), tol) << "x, lag " << lag << " ℓ";
    EXPECT_NEAR(cy / c0, std::exp(-lag * lag), tol) << "y, lag " << lag << " ℓ";
  }
}

// Periodic: the difference across the wrap (column n−1 to column 0, row n−1 to row 0) is
// an ordinary slope, not a seam. A field that does not tile has there the difference of
// two independent heights, ~ℓ/h times larger.
TEST(GaussianSurface, TilesWithoutSeam) {
  const int n = 256;
  const gm::HeightField f = field(0.3, 0.3, n, 11);
  const double h = f.spacing();
  double wx = 0, wy = 0;
  for (int k = 0; k < n; ++k) {
    const double dx = (f.z[std::size_t(n) * k] - f.z[std::size_t(n) * k + n - 1]) / h;
    const double dy = (f.z[std::size_t(k)] - f.z[std::size_t(n) * (n - 1) + k]) / h;
    wx += dx * dx;
    wy += dy * dy;
  }
  const double want = 0.3 / std::sqrt(2.0);
  EXPECT_NEAR(std::sqrt(wx / n) / want, 1.0, 0.35);
  EXPECT_NEAR(std::sqrt(wy / n) / want, 1.0, 0.35);
}

TEST(GaussianSurface, DeterministicPerSeedDifferentAcrossSeeds) {
  const gm::HeightField a = field(0.3, 0.3, 64, 42), b = field(0.3, 0.3, 64, 42), c = field(0.3, 0.3, 64, 43);
  EXPECT_EQ(a.z, b.z);
  double ac = 0, aa = 0, cc = 0;
  for (std::size_t k = 0; k < a.z.size(); ++k) {
    ac += double(a.z[k]) * c.z[k];
    aa += double(a.z[k]) * a.z[k];
    cc += double(c.z[k]) * c.z[k];
  }
  EXPECT_LT(std::abs(ac) / std::sqrt(aa * cc), 0.5) << "seeds 42 and 43 give unrelated surfaces";
  for (const float z : a.z) ASSERT_TRUE(std::isfinite(z));
}

// The default correlation length: ≥ 8 cells, and 1/32 of the patch once that allows it.
TEST(GaussianSurface, DefaultCorrelation) {
  EXPECT_DOUBLE_EQ(gm::default_gaussian_correlation(512), 1.0 / 32);
  EXPECT_DOUBLE_EQ(gm::default_gaussian_correlation(2048), 1.0 / 32);
  EXPECT_DOUBLE_EQ(gm::default_gaussian_correlation(128), 8.0 / 128);
  for (int n = gm::GaussianSurfaceParams::kMinResolution; n <= gm::GaussianSurfaceParams::kMaxResolution; n *= 2)
    EXPECT_GE(gm::default_gaussian_correlation(n) * n, 8.0) << n;
}
