// The polarizing models' one copy for Mueller matrices (include/gonio/bxdf/instances.h
// says why).
#include "gonio/polarization/instances.h"

namespace gonio {

#define GONIO_POLARIZING_INSTANCE(M) \
  template struct M<MuellerT<Color>>; \
  template struct M<MuellerT<SampledSpectrum>>;
GONIO_POLARIZING_MODEL_TEMPLATES(GONIO_POLARIZING_INSTANCE)
#undef GONIO_POLARIZING_INSTANCE
template class PolarizedBxDFT<Color>;
template class PolarizedBxDFT<SampledSpectrum>;

}  // namespace gonio
