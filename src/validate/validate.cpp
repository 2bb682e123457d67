// The validator's driver: every property, in SPEC §3's order.

#include "gonio/validate.h"

namespace gonio {

ValidationReport validate(const BxDF& bxdf, const ValidationOptions& opt,
                          const std::function<void()>& before_each_property) {
  ValidationReport report;
  const auto next = [&] {
    if (before_each_property) before_each_property();
  };
  next(), report.properties.push_back(check_finite(bxdf, opt));
  next(), report.properties.push_back(check_reciprocity(bxdf, opt));
  next(), report.properties.push_back(check_energy(bxdf, opt));
  next();
  for (auto& p : check_sampling(bxdf, opt)) report.properties.push_back(std::move(p));
  next(), report.properties.push_back(check_consistency(bxdf, opt));
  next(), report.properties.push_back(check_isotropy(bxdf, opt));
  next(), report.properties.push_back(check_linearity(bxdf, opt));
  next(), report.properties.push_back(check_weights(bxdf, opt));
  return report;
}

}  // namespace gonio
