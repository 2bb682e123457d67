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

// ∫∫ pdf(wo, w(μ, φ)) dμ dφ over one cell, adaptive Simpson in two dimensions.
class CellIntegrator {
 public:
  CellIntegrator(const BxDF& bxdf, const Vec3& wo) : bxdf_(bxdf), wo_(wo) {}

  double integrate(double mu0, double mu1, double ph0, double ph1) {
    const double whole = simpson(mu0, mu1, ph0, ph1);
    return refine(mu0, mu1, ph0, ph1, whole, 0);
  }

 private:
  double pdf_at(double mu, double ph) const {
    const double s = std::sqrt(std::max(0.0, 1 - mu * mu));
    const Vec3 wi{Float(s * std::cos(ph)), Float(s * std::sin(ph)), Float(mu)};
    return bxdf_.pdf(wo_, wi, TransportMode::Radiance);
  }
  double simpson(double mu0, double mu1, double ph0, double ph1) const {
    const double mm = (mu0 + mu1) / 2, pm = (ph0 + ph1) / 2;
    const double w[3] = {1, 4, 1};
    const double mus[3] = {mu0, mm, mu1}, phs[3] = {ph0, pm, ph1};
    double sum = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) sum += w[i] * w[j] * pdf_at(mus[i], phs[j]);
    return sum * (mu1 - mu0) * (ph1 - ph0) / 36;
  }
  double refine(double mu0, double mu1, double ph0, double ph1, double whole, int depth) {
    const double mm = (mu0 + mu1) / 2, pm = (ph0 + ph1) / 2;
    const double q[4] = {simpson(mu0, mm, ph0, pm), simpson(mm, mu1, ph0, pm),
                         simpson(mu0, mm, pm, ph1), simpson(mm, mu1, pm, ph1)};
    const double sum = q[0] + q[1] + q[2] + q[3];
    const double tol = 1e-9 * std::pow(0.25, depth) + 1e-5 * std::abs(sum);
    if (depth >= 5 || std::abs(sum - whole) <= 15 * tol) return sum + (sum - whole) / 15;
    return refine(mu0, mm, ph0, pm, q[0], depth + 1) + refine(mm, mu1, ph0, pm, q[1], depth + 1) +
           refine(mu0, mm, pm, ph1, q[2], depth + 1) + refine(mm, mu1, pm, ph1, q[3], depth + 1);
  }

  const BxDF& bxdf_;
  Vec3 wo_;
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
  std::vector<double> expected(kThetaBins * kPhiBins, 0.0);
  std::vector<std::uint64_t> observed(expected.size(), 0);
  CellIntegrator integ(bxdf, wo);
  const double dmu = 2.0 / kThetaBins, dph = 2 * kPiD / kPhiBins;
  double total = 0;
  for (int it = 0; it < kThetaBins; ++it)
    for (int ip = 0; ip < kPhiBins; ++ip) {
      const double v = integ.integrate(-1 + it * dmu, -1 + (it + 1) * dmu, ip * dph, (ip + 1) * dph);
      expected[size_t(it * kPhiBins + ip)] = v;
      total += v;
    }
  std::uint64_t returned = 0;
  for (std::uint64_t i = 0; i < n; ++i) {
    const auto s = bxdf.sample(wo, rng.next_float(), rng.next_float(), rng.next_float());
    if (!s || s->delta) continue;
    ++returned;
    ++observed[size_t(cell_of(s->wi))];
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
    const double e = expected[c] * double(n), o = double(observed[c]);
    if (e < 1e-9 * double(n) && o > 0 && d.note.empty()) {
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

}  // namespace gonio
