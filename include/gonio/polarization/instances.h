#pragma once
// The polarizing models' code for Mueller matrices, generated once in the library
// (src/polarization/instances.cpp); why: bxdf/instances.h.

#include "gonio/bxdf/instances.h"
#include "gonio/polarization/polarized_bxdf.h"

// X(template-name) for every model of PolarizedBxDFT<C>::Polarizing.
#define GONIO_POLARIZING_MODEL_TEMPLATES(X) \
  X(ConductorBxDFT) X(DielectricBxDFT) X(RoughConductorBxDFT) X(RoughDielectricBxDFT) X(PlasticBxDFT) \
  X(ThinDielectricBxDFT) X(OpenPbrBxDFT)

namespace gonio {

#define GONIO_EXTERN_POLARIZING_MODEL(M)     \
  extern template struct M<MuellerT<Color>>; \
  extern template struct M<MuellerT<SampledSpectrum>>;
GONIO_POLARIZING_MODEL_TEMPLATES(GONIO_EXTERN_POLARIZING_MODEL)
#undef GONIO_EXTERN_POLARIZING_MODEL

extern template class PolarizedBxDFT<Color>;
extern template class PolarizedBxDFT<SampledSpectrum>;

}  // namespace gonio
