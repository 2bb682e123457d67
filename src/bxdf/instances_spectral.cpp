// The models' one copy for sampled spectra (include/gonio/bxdf/instances.h says why).
#include "gonio/bxdf/instances.h"

namespace gonio {

#define GONIO_BXDF_INSTANCE(M) template struct M<SampledSpectrum>;
GONIO_BXDF_MODEL_TEMPLATES(GONIO_BXDF_INSTANCE)
#undef GONIO_BXDF_INSTANCE
template class BxDFT<SampledSpectrum>;

}  // namespace gonio
