// The models' one copy for RGB (include/gonio/bxdf/instances.h says why).
#include "gonio/bxdf/instances.h"

#include <variant>

namespace gonio {

#define GONIO_BXDF_INSTANCE(M) template struct M<Color>;
GONIO_BXDF_MODEL_TEMPLATES(GONIO_BXDF_INSTANCE)
#undef GONIO_BXDF_INSTANCE
template class BxDFT<Color>;

// A model added to BxDFT::Models but not to the list would build, only slower: caught here.
#define GONIO_COUNT_MODEL(M) +1
static_assert(0 GONIO_BXDF_MODEL_TEMPLATES(GONIO_COUNT_MODEL) == std::variant_size_v<BxDF::Models>,
              "GONIO_BXDF_MODEL_TEMPLATES (bxdf/instances.h) must list every model of BxDFT::Models");
#undef GONIO_COUNT_MODEL

}  // namespace gonio
