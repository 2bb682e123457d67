#pragma once
// The models' code is generated once, in the library (src/bxdf/instances*.cpp), for the
// colour types it ships: RGB (Color) and the four wavelengths of a path (SampledSpectrum);
// the polarizing ones also for their Mueller matrices (polarization/instances.h).
// Every other file that includes bxdf.h still sees the members defined in each class, so
// the optimizer may inline one where it pays (a hot loop of the renderer), but it no
// longer emits its own copy of every member it calls; members defined outside their class
// (Blend's, Layered's) are called in the library. Each test file
// re-generated the same twenty models in four colour types: on the clang ASan build of
// the test suite, one test file's compile took 57 s before and 33 s after.
//
// The list of models is kept in one place (GONIO_BXDF_MODEL_TEMPLATES), used for the
// declarations here and for the definitions in the library.

#include "gonio/bxdf.h"

// X(template-name) for every built-in model template of BxDFT<C>::Models. UserBxDFT wraps
// the user's CustomBxDFT, whose own instances live in src/custom_bxdf.cpp.
#define GONIO_BXDF_MODEL_TEMPLATES(X)                                                           \
  X(DiffuseBxDFT) X(MirrorBxDFT) X(ConductorBxDFT) X(DielectricBxDFT) X(RoughConductorBxDFT)    \
  X(RoughDielectricBxDFT) X(OrenNayarBxDFT) X(PhongBxDFT) X(BlinnPhongBxDFT) X(WardBxDFT)       \
  X(AshikhminShirleyBxDFT) X(PlasticBxDFT) X(MeasuredBxDFT) X(BlendBxDFT) X(UserBxDFT)          \
  X(SheenBxDFT) X(EonBxDFT) X(ThinDielectricBxDFT) X(LayeredBxDFT) X(OpenPbrBxDFT)      \
  X(GltfPbrBxDFT) X(PbrNodeBxDFT) X(CharlieSheenBxDFT) X(HairBxDFT) X(RglBxDFT)

namespace gonio {

#define GONIO_BXDF_EXTERN_MODEL(M)        \
  extern template struct M<Color>;        \
  extern template struct M<SampledSpectrum>;
GONIO_BXDF_MODEL_TEMPLATES(GONIO_BXDF_EXTERN_MODEL)
#undef GONIO_BXDF_EXTERN_MODEL

extern template class BxDFT<Color>;
extern template class BxDFT<SampledSpectrum>;

}  // namespace gonio
