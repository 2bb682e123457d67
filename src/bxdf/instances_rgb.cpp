// The models' one copy for RGB (include/gonio/bxdf/instances.h says why).
#include "gonio/bxdf/instances.h"

namespace gonio {

#define GONIO_BXDF_INSTANCE(M) template struct M<Color>;
GONIO_BXDF_MODEL_TEMPLATES(GONIO_BXDF_INSTANCE)
#undef GONIO_BXDF_INSTANCE
template class BxDFT<Color>;

}  // namespace gonio
