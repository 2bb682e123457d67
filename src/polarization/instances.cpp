// The polarizing models' one copy for Mueller matrices (include/gonio/bxdf/instances.h
// says why).
#include "gonio/polarization/instances.h"

#include <variant>

namespace gonio {

#define GONIO_POLARIZING_INSTANCE(M) \
  template struct M<MuellerT<Color>>; \
  template struct M<MuellerT<SampledSpectrum>>;
GONIO_POLARIZING_MODEL_TEMPLATES(GONIO_POLARIZING_INSTANCE)
#undef GONIO_POLARIZING_INSTANCE
template class PolarizedBxDFT<Color>;
template class PolarizedBxDFT<SampledSpectrum>;

// As in src/bxdf/instances_rgb.cpp: the list must name every polarizing model (the
// variant's first alternative, std::monostate, stands for the depolarizing ones).
#define GONIO_COUNT_MODEL(M) +1
static_assert(0 GONIO_POLARIZING_MODEL_TEMPLATES(GONIO_COUNT_MODEL) + 1 ==
                  std::variant_size_v<PolarizedBxDF::Polarizing>,
              "GONIO_POLARIZING_MODEL_TEMPLATES (polarization/instances.h) must list every polarizing model");
#undef GONIO_COUNT_MODEL

}  // namespace gonio
