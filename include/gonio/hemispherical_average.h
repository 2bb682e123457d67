#pragma once
// The cosine-weighted hemispherical average of an isotropic directional quantity g(μ),
// μ = cos θ:  ḡ = (1/π) ∫ g cos θ dω = 2 ∫₀¹ g(μ) μ dμ  (the "F_avg" and "E_avg" of
// Kulla & Conty 2017, the "F_dr" of Weidlich & Wilkie 2007). The one implementation in
// gonio: every average Fresnel, table mean and deterministic albedo goes through it.
//
// Composite Simpson's rule in double. It is exact for a g that is linear in μ on each
// panel (2 g μ is then quadratic), so the mean of a table's piecewise-linear interpolant
// is computed exactly by integrating node interval by node interval.

#include <array>
#include <cstddef>

namespace gonio {

namespace detail {
inline void add_scaled(double& acc, double w, double v) { acc += w * v; }
template <std::size_t N>
void add_scaled(std::array<double, N>& acc, double w, const std::array<double, N>& v) {
  for (std::size_t i = 0; i < N; ++i) acc[i] += w * v[i];
}
inline void scale(double& acc, double s) { acc *= s; }
template <std::size_t N>
void scale(std::array<double, N>& acc, double s) {
  for (auto& x : acc) x *= s;
}
}  // namespace detail

// 2 ∫_a^b g(μ) μ dμ by Simpson's rule over `panels` equal panels (rounded up to even).
// g returns double or std::array<double, N>.
template <typename G>
auto cosine_weighted_integral(G&& g, double a, double b, int panels) {
  const int n = panels + (panels & 1);
  const double h = (b - a) / n;
  using R = decltype(g(a));
  R acc{};
  for (int i = 0; i <= n; ++i) {
    const double mu = i == n ? b : a + i * h;
    const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    detail::add_scaled(acc, w * 2 * mu, g(mu));
  }
  detail::scale(acc, h / 3);
  return acc;
}

// ḡ = 2 ∫₀¹ g(μ) μ dμ. 2^14 panels keep the error from a kink (a critical angle) near 1e-9.
template <typename G>
auto cosine_weighted_average(G&& g, int panels = 1 << 14) {
  return cosine_weighted_integral(static_cast<G&&>(g), 0.0, 1.0, panels);
}

// The exact mean 2 ∫₀¹ E(μ) μ dμ of the piecewise-linear interpolant of values[m] at
// increasing nodes mu[m] (mu[0] = 0 ... mu[n−1] = 1), one Simpson panel pair per interval.
template <typename Mu, typename Values>
double cosine_weighted_average_of_linear(const Mu& mu, const Values& values, int n) {
  double acc = 0;
  for (int m = 0; m + 1 < n; ++m) {
    const double a = mu[m], b = mu[m + 1], ea = values[m], eb = values[m + 1];
    acc += cosine_weighted_integral([&](double x) { return ea + (eb - ea) * (x - a) / (b - a); }, a, b, 2);
  }
  return acc;
}

}  // namespace gonio
