#pragma once
// The work one evaluation (f, pdf or a sample) of a model may take, as an upper bound in
// steps of the layered model's random walk: what `gonio albedo`, `gonio check` and the
// explorer bound a request by before starting it (docs/cli.md, docs/explore.md). Every
// model but the layered one is closed-form (one step); a layered model walks at most
// `max_depth` vertices, `samples` times, from both ends (layered.h: f = (E(wo, wi) +
// E(wi, wo)) / 2), and may evaluate its bottom at each vertex; a blend evaluates both parts.

#include <algorithm>
#include <type_traits>
#include <variant>

#include "gonio/bxdf.h"

namespace gonio {

template <typename C>
double evaluation_cost(const BxDFT<C>& bxdf) {
  return std::visit(
      [](const auto& m) -> double {
        using M = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<M, LayeredBxDFT<C>>) {
          const double bottom = m.bottom ? evaluation_cost(*m.bottom) : 1.0;
          return 2.0 * double(m.samples) * double(m.max_depth) * std::max(1.0, bottom);
        } else if constexpr (std::is_same_v<M, BlendBxDFT<C>>) {
          return m.parts ? evaluation_cost((*m.parts)[0]) + evaluation_cost((*m.parts)[1]) : 1.0;
        } else {
          return 1.0;
        }
      },
      bxdf.models());
}

// The evaluations `validate` makes of a model (validate.h: ~10⁶ random pairs of `finite`,
// 10⁶ samples per direction of `weights`, the χ² and reciprocity tables, the isotropy and
// linearity repeats), as the work bound counts them.
inline constexpr double kValidationEvaluations = 2e7;

}  // namespace gonio
