// The adversarial sweep in CI (tools/adversarial_sweep.h; the full run of ≥ 10⁸ calls is
// build/bin/gonio_adversarial, recorded in docs/robustness.md): every material at extreme
// parameters and directions must give no NaN, Inf or negative value, samples that agree
// with eval at their own direction, and weights within 10× the albedo bound. Plus the
// regression tests of the findings of issue 9 in the models they concern, each at the
// exact inputs the probe reported.

#include <gtest/gtest.h>

#include <cmath>

#include "../../tools/adversarial_sweep.h"
#include "gonio/material.h"
#include "test_scale.h"

namespace gonio {
namespace {

TEST(AdversarialSweep, ExtremeMaterialsAndDirections) {
  const std::uint64_t draws = test::scaled(3000, 300);
  const auto materials = adversarial::extreme_materials();
  for (size_t k = 0; k < materials.size(); ++k) {
    SCOPED_TRACE(materials[k]);
    BxDF m;
    ASSERT_NO_THROW(m = parse_material(materials[k]));
    const auto t = adversarial::sweep(m, draws, 77 + k);
    EXPECT_EQ(t.failures(), 0u) << "value " << t.value << ", agree " << t.agree << ", weight " << t.weight
                                << "; first: " << t.first_failure;
  }
}

}  // namespace
}  // namespace gonio
