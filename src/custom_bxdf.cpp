#include "gonio/bxdf/custom.h"

namespace gonio {

// Out of line so the vtables have one home.
template class CustomBxDFT<Color>;
template class CustomBxDFT<SampledSpectrum>;

}  // namespace gonio
