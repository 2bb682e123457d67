// The validator's driver: every property, in SPEC §3's order.

#include "gonio/validate.h"

namespace gonio {

ValidationReport validate(const BxDF& bxdf, const ValidationOptions& opt) {
  ValidationReport report;
  report.properties.push_back(check_finite(bxdf, opt));
  report.properties.push_back(check_reciprocity(bxdf, opt));
  report.properties.push_back(check_energy(bxdf, opt));
  for (auto& p : check_sampling(bxdf, opt)) report.properties.push_back(std::move(p));
  report.properties.push_back(check_consistency(bxdf, opt));
  report.properties.push_back(check_isotropy(bxdf, opt));
  report.properties.push_back(check_linearity(bxdf, opt));
  report.properties.push_back(check_weights(bxdf, opt));
  return report;
}

}  // namespace gonio
