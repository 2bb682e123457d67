#pragma once
// SampledSpectrum: the values of a spectral quantity at the kSpectrumSamples wavelengths
// of one path (SampledWavelengths) — gonio's colour type with 4 channels (color.h), so
// that every model evaluates it as it evaluates RGB.

#include "gonio/color.h"
