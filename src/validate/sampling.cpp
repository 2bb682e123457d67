// Properties "chi2" and "pdf_integral": sample() against pdf() on a grid over the whole
// sphere in (cos θ, φ) — cells of equal solid angle. Expected counts integrate pdf over
// each cell by adaptive Simpson; cells expected to hold fewer than 5 samples are pooled
// (the rule of thumb for Pearson's test); the significance 0.001 is shared among the
// outgoing directions tested by Šidák's correction.

#include <algorithm>
#include <utility>

#include "chi2_distribution.h"
#include "common.h"

namespace gonio {

using namespace validation;

namespace {

constexpr int kThetaBins = 64, kPhiBins = 128;
constexpr double kFamilySignificance = 1e-3;

// A sample's position in the grid's coordinates.
struct GridPoint {
  float mu, phi;
};

// ∫∫ pdf(wo, w(μ, φ)) dμ dφ over one cell by adaptive Simpson. A rectangle is halved
// along μ or φ, whichever halving changes the estimate more (a lobe at a pole needs
// only μ splits, a lobe in a wedge of φ only φ splits), until the estimate converges.
// Beyond that, a rectangle is also split wherever the samples that fell in it disagree
// with the integral by more than Poisson noise allows: a lobe narrower than the spacing
// of the quadrature points is then found because the samples sit in it. A correct
// sampler thus makes the integral exact where it matters; a wrong one only makes the
// expected counts more precise, so the test keeps its power.
class CellIntegrator {
 public:
  CellIntegrator(const BxDF& bxdf, const Vec3& wo, double n) : bxdf_(bxdf), wo_(wo), n_(n) {}

  double integrate(double mu0, double mu1, double ph0, double ph1, GridPoint* begin, GridPoint* end) {
    const Rect r{mu0, mu1, ph0, ph1};
    return refine(r, simpson(r), 0, begin, end, 1e-9);
  }

 private:
  struct Rect {
    double mu0, mu1, ph0, ph1;
  };
  // Halvings: error-driven ones stop at 2^-7 of a cell per direction (a discontinuity,
  // e.g. at a critical angle, would otherwise be chased forever); sample-driven ones go
  // on to 2^-20, but stop by themselves once too few samples are left to disagree.
  static constexpr int kMaxErrorDepth = 14, kMaxDepth = 40;

  double pdf_at(double mu, double ph) const {
    const double s = std::sqrt(std::max(0.0, 1 - mu * mu));
    const Vec3 wi{Float(s * std::cos(ph)), Float(s * std::sin(ph)), Float(mu)};
    return bxdf_.pdf(wo_, wi, TransportMode::Radiance);
  }
  double simpson(const Rect& r) const {
    const double mm = (r.mu0 + r.mu1) / 2, pm = (r.ph0 + r.ph1) / 2;
    const double w[3] = {1, 4, 1};
    const double mus[3] = {r.mu0, mm, r.mu1}, phs[3] = {r.ph0, pm, r.ph1};
    double sum = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) sum += w[i] * w[j] * pdf_at(mus[i], phs[j]);
    return sum * (r.mu1 - r.mu0) * (r.ph1 - r.ph0) / 36;
  }
  bool disagrees(double integral, std::ptrdiff_t observed) const {
    const double e = integral * n_, o = double(observed);
    return std::max(e, o) >= 10 && std::abs(o - e) > 3 * std::sqrt(std::max(e, o));
  }
  double refine(const Rect& r, double whole, int depth, GridPoint* begin, GridPoint* end, double tol) {
    const double mm = (r.mu0 + r.mu1) / 2, pm = (r.ph0 + r.ph1) / 2;
    const Rect mu_lo{r.mu0, mm, r.ph0, r.ph1}, mu_hi{mm, r.mu1, r.ph0, r.ph1};
    const Rect ph_lo{r.mu0, r.mu1, r.ph0, pm}, ph_hi{r.mu0, r.mu1, pm, r.ph1};
    const double a0 = simpson(mu_lo), a1 = simpson(mu_hi), b0 = simpson(ph_lo), b1 = simpson(ph_hi);
    const double err_mu = std::abs(a0 + a1 - whole), err_ph = std::abs(b0 + b1 - whole);
    // On a tie (typically both 0: a lobe that no quadrature point touches, found only
    // through its samples) alternate the direction, so both dimensions get resolved.
    const bool split_mu = err_mu == err_ph ? depth % 2 == 0 : err_mu > err_ph;
    const double halves = split_mu ? a0 + a1 : b0 + b1;
    const double err = std::max(err_mu, err_ph);
    const bool converged = err <= 15 * std::max(tol, 1e-5 * std::abs(halves));
    const bool refine_error = !converged && depth < kMaxErrorDepth;
    const bool refine_samples = depth < kMaxDepth && disagrees(whole, end - begin);
    if (!refine_error && !refine_samples) return halves + (halves - whole) / 15;
    GridPoint* mid = split_mu ? std::partition(begin, end, [&](const GridPoint& g) { return g.mu < mm; })
                              : std::partition(begin, end, [&](const GridPoint& g) { return g.phi < pm; });
    return refine(split_mu ? mu_lo : ph_lo, split_mu ? a0 : b0, depth + 1, begin, mid, tol / 2) +
           refine(split_mu ? mu_hi : ph_hi, split_mu ? a1 : b1, depth + 1, mid, end, tol / 2);
  }

  const BxDF& bxdf_;
  Vec3 wo_;
  double n_;
};

int cell_of(const Vec3& w) {
  const double mu = std::clamp(double(w.z), -1.0, 1.0);
  const int it = std::min(kThetaBins - 1, int((mu + 1) / 2 * kThetaBins));
  double ph = std::atan2(double(w.y), double(w.x));
  if (ph < 0) ph += 2 * kPiD;
  const int ip = std::min(kPhiBins - 1, int(ph / (2 * kPiD) * kPhiBins));
  return it * kPhiBins + ip;
}

struct DirectionResult {
  double p_value = 1;
  double pdf_integral = 0, returned_fraction = 0, allowed = 0;
  std::string note;
};

DirectionResult test_direction(const BxDF& bxdf, const Vec3& wo, std::uint64_t n, Pcg32& rng) {
  DirectionResult d;
  constexpr int kCells = kThetaBins * kPhiBins;
  // Samples first, bucketed by cell, so the integration can look at them.
  std::vector<int> cell_of_sample;
  std::vector<GridPoint> points;
  cell_of_sample.reserve(n);
  points.reserve(n);
  for (std::uint64_t i = 0; i < n; ++i) {
    const auto s = bxdf.sample(wo, rng.next_float(), rng.next_float(), rng.next_float());
    if (!s || s->delta) continue;
    double ph = std::atan2(double(s->wi.y), double(s->wi.x));
    if (ph < 0) ph += 2 * kPiD;
    cell_of_sample.push_back(cell_of(s->wi));
    points.push_back({float(std::clamp(double(s->wi.z), -1.0, 1.0)), float(ph)});
  }
  const std::uint64_t returned = points.size();
  std::vector<std::uint64_t> observed(kCells + 1, 0);
  for (int c : cell_of_sample) ++observed[size_t(c) + 1];
  std::vector<std::uint64_t> offset(kCells + 1, 0);  // prefix sums: start of each cell
  for (int c = 0; c < kCells; ++c) offset[size_t(c) + 1] = offset[size_t(c)] + observed[size_t(c) + 1];
  std::vector<GridPoint> sorted(points.size());
  {
    std::vector<std::uint64_t> cursor(offset.begin(), offset.end() - 1);
    for (size_t i = 0; i < points.size(); ++i) sorted[cursor[size_t(cell_of_sample[i])]++] = points[i];
  }

  std::vector<double> expected(kCells, 0.0);
  CellIntegrator integ(bxdf, wo, double(n));
  const double dmu = 2.0 / kThetaBins, dph = 2 * kPiD / kPhiBins;
  double total = 0;
  for (int it = 0; it < kThetaBins; ++it)
    for (int ip = 0; ip < kPhiBins; ++ip) {
      const int c = it * kPhiBins + ip;
      GridPoint* b = sorted.data() + offset[size_t(c)];
      GridPoint* e = sorted.data() + offset[size_t(c) + 1];
      const double v = integ.integrate(-1 + it * dmu, -1 + (it + 1) * dmu, ip * dph, (ip + 1) * dph, b, e);
      expected[size_t(c)] = v;
      total += v;
    }
  d.pdf_integral = total;
  d.returned_fraction = double(returned) / double(n);
  // Binomial sampling error of the fraction (4σ) plus the integration's tolerance.
  const double f = d.returned_fraction;
  d.allowed = 4 * std::sqrt(std::max(f * (1 - f), 1.0 / double(n)) / double(n)) + 2e-3 * std::max(1.0, total);

  // Pearson's χ² with low-expectation cells pooled.
  std::vector<std::pair<double, double>> cells;  // (expected count, observed count)
  double pooled_e = 0, pooled_o = 0;
  for (size_t c = 0; c < expected.size(); ++c) {
    const double e = expected[c] * double(n), o = double(observed[c + 1]);
    if (e <= 0 && o > 0 && d.note.empty()) {
      d.note = "samples where pdf is 0 (cell " + std::to_string(c) + ": " + fmt(o) + " samples)";
      d.p_value = 0;
    }
    if (e < 5) {
      pooled_e += e;
      pooled_o += o;
    } else {
      cells.emplace_back(e, o);
    }
  }
  if (pooled_e >= 5 || cells.empty()) {
    cells.emplace_back(pooled_e, pooled_o);
  } else if (!cells.empty()) {
    auto smallest = std::min_element(cells.begin(), cells.end());
    smallest->first += pooled_e;
    smallest->second += pooled_o;
  }
  if (cells.size() < 2 || returned == 0) {
    if (returned == 0 && total > 1e-3) {
      d.p_value = 0;
      d.note = "pdf integrates to " + fmt(total) + " but sample() returned nothing";
    }
    return d;
  }
  double chi2 = 0;
  for (const auto& [e, o] : cells) {
    if (e > 0) chi2 += (o - e) * (o - e) / e;
  }
  const double p = chi2_survival(chi2, double(cells.size() - 1));
  if (d.p_value > 0) d.p_value = p;
  if (d.note.empty()) d.note = "chi2 " + fmt(chi2) + " with " + std::to_string(cells.size() - 1) + " dof";
  return d;
}

}  // namespace

std::vector<PropertyResult> check_sampling(const BxDF& bxdf, const ValidationOptions& opt) {
  PropertyResult chi2{"chi2", std::nullopt, 0, true, "delta lobes only: no density to test"};
  PropertyResult integral{"pdf_integral", std::nullopt, 0, true, ""};
  const auto dirs = test_outgoing_directions(bxdf);
  const std::uint64_t n = scaled(opt, 1'000'000, 20'000);
  Pcg32 rng = rng_for(opt, 4);
  const double alpha = 1 - std::pow(1 - kFamilySignificance, 1.0 / double(dirs.size()));
  double min_p = 1, worst_ratio = -1;
  for (const auto& wo : dirs) {
    const DirectionResult d = test_direction(bxdf, wo, n, rng);
    if (!is_delta_only(bxdf.flags()) && d.p_value <= min_p) {
      min_p = d.p_value;
      chi2.detail = "worst at wo " + describe(wo) + ": " + d.note;
    }
    const double diff = std::abs(d.pdf_integral - d.returned_fraction);
    if (diff / d.allowed > worst_ratio) {
      worst_ratio = diff / d.allowed;
      integral.figure = diff;
      integral.threshold = d.allowed;
      integral.detail = "at wo " + describe(wo) + ": integral of pdf " + fmt(d.pdf_integral) +
                        ", fraction of non-delta samples " + fmt(d.returned_fraction);
    }
  }
  integral.pass = worst_ratio <= 1;
  if (!is_delta_only(bxdf.flags())) {
    chi2.figure = min_p;
    chi2.threshold = alpha;
    chi2.pass = min_p >= alpha;
  }
  return {chi2, integral};
}

// Property "weights": the weight of every sample stays within a modest multiple of the
// directional albedo, so that no rare region of directions carries a weight that
// dominates an estimate (a variance disaster: Ward and Ashikhmin–Shirley at grazing gave
// weights of 10¹³–10¹⁶ on a probe).
//
// The bound. In importance mode a weight w = f |cos θi| / pdf is the energy one sample
// carries; its mean over samples is the directional albedo ρ(wo) (proved against pdf and
// f by chi2 and consistency). Since E[w²] ≤ max(w) E[w], a sampler whose weights stay
// below K ρ has a relative variance Var(w)/ρ² ≤ K − 1: it never needs more than K times
// the samples of a perfect sampler (w ≡ ρ) for the same noise. K = kWeightFactor = 100.
// Sound samplers here stay below ~45 even at 89.99° (measured on the built-in sweep:
// lobe choice by estimated energy, G2/G1 of visible-normal sampling, energy-compensation
// mixtures, a Blinn–Phong lobe mostly below the horizon), while a weight that grows
// without bound towards grazing exceeds it by orders of magnitude. ρ is the mean weight
// of the same samples: a rare huge weight W among n raises it only to ρ + W/n, so
// max/mean ≥ min(W/(2ρ), n/2) still exposes it. Weights and albedo are compared in their
// largest channel; a weight below 10⁻⁴ is never a disaster.
namespace {
constexpr double kWeightFactor = 100;
}

PropertyResult check_weights(const BxDF& bxdf, const ValidationOptions& opt) {
  PropertyResult r{"weights", 0.0, kWeightFactor, true, ""};
  auto dirs = test_outgoing_directions(bxdf);
  // Grazing incidence, where unguarded 1/cos θ terms live; for anisotropic models also
  // along both axes of anisotropy.
  const Float deg = Float(kPiD / 180);
  for (Float th : {Float(89.9), Float(89.99)}) dirs.push_back(direction_from_angles(th * deg, Float(0.3)));
  if (!bxdf.is_isotropic())
    for (Float ph : {Float(0), Float(kPiD / 2)}) dirs.push_back(direction_from_angles(Float(89.99) * deg, ph));
  const std::uint64_t n = scaled(opt, 1'000'000, 20'000);
  Pcg32 rng = rng_for(opt, 9);
  double worst = 0;
  // A non-reciprocal model is sampled for what it defines, radiance transport.
  const TransportMode mode =
      bxdf.nonreciprocal_reason().empty() ? TransportMode::Importance : TransportMode::Radiance;
  for (const auto& wo : dirs) {
    double sum[kColorChannels] = {}, max_w = 0;
    Vec3 max_wi{};
    for (std::uint64_t i = 0; i < n; ++i) {
      const auto s = bxdf.sample(wo, rng.next_float(), rng.next_float(), rng.next_float(), mode);
      if (!s) continue;
      for (int c = 0; c < kColorChannels; ++c) sum[c] += s->weight[c];
      const double w = s->weight.max_component();
      if (w > max_w || !(w == w)) {
        max_w = w;
        max_wi = s->wi;
      }
    }
    double rho = 0;
    for (int c = 0; c < kColorChannels; ++c) rho = std::max(rho, sum[c] / double(n));
    const double ratio = !(max_w == max_w) ? 1e300 : max_w <= 1e-4 ? 0 : rho > 0 ? max_w / rho : 1e300;
    if (ratio > worst || r.detail.empty()) {
      worst = std::max(worst, ratio);
      r.detail = "max weight " + fmt(max_w) + " (wi " + describe(max_wi) + ") against albedo " + fmt(rho) +
                 " at wo " + describe(wo);
    }
  }
  r.figure = worst;
  r.pass = worst <= kWeightFactor;
  if (mode == TransportMode::Radiance) r.detail = "radiance mode (not reciprocal): " + r.detail;
  return r;
}

}  // namespace gonio
