#pragma once
// The work bound of `gonio albedo` and `gonio check` (docs/cli.md, "Work bound"): a
// layered material multiplies each evaluation by up to 2 × samples × max_depth walk steps
// (evaluation_cost.h), so in-range parameters could ask for days of work. A request whose
// evaluations × steps exceed kMaxCliWork is refused before it starts, with one line and
// exit status 2. Closed-form models cost one step, and the bound never refuses what their
// evaluations alone would be (SPEC §3 allows --samples up to 10¹²).

#include <algorithm>
#include <cstdio>
#include <string>

#include "gonio/error.h"
#include "gonio/bxdf/evaluation_cost.h"

namespace gonio::cli {

// 3–12 ns a step (an albedo-1 medium walking to max_depth 10000: 3.4 ns; a default layered
// material's validation: 27 s for 4·10⁹), so 10¹¹ steps are 6 to 20 minutes of a core.
inline constexpr double kMaxCliWork = 1e11;

template <typename Model>
void check_cli_work(const Model& bxdf, double evaluations, const char* what) {
  const double cost = evaluation_cost(bxdf);
  if (cost * evaluations <= std::max(kMaxCliWork, evaluations)) return;
  char buf[240];
  std::snprintf(buf, sizeof buf,
                "%s: about %.2g evaluations of up to %.3g walk steps each (layered: 2 x samples x max_depth), "
                "above the limit of %.2g steps; lower the layered material's max_depth or samples, or --samples",
                what, evaluations, cost, kMaxCliWork);
  throw InputError(buf);
}

}  // namespace gonio::cli
