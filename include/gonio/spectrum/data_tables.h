#pragma once
// Tables generated at build time from the repository's data/ files by
// tools/make_spectral_tables.cpp (into build/generated/spectral_tables.cpp): the library
// needs no data file at run time. Used by the spectrum code; not meant for models.

#include "gonio/spectrum/rgb_table_layout.h"

namespace gonio::spectral_data {

// CIE 1931 2° colour-matching functions at 360, 361, …, 830 nm (data/cie/).
inline constexpr int kCieSamples = 471;
inline constexpr int kCieFirstNm = 360;
extern const float kCieX[kCieSamples];
extern const float kCieY[kCieSamples];
extern const float kCieZ[kCieSamples];
// ∫ ȳ dλ of the linear interpolant of the table (trapezoid rule), nm.
extern const double kCieYIntegral;
// The CDF of the spectral renderer's wavelength density (wavelengths.h), piecewise
// constant over the 1 nm bins from kCieFirstNm: at the bins' edges, from 0 to 1.
extern const double kResponseCdf[kCieSamples];
// For u in [k, k + 1)/kResponseGuideSize, the bin holding k/kResponseGuideSize: where the
// search for u's bin starts.
inline constexpr int kResponseGuideSize = 1024;
extern const unsigned short kResponseGuide[kResponseGuideSize];

// CIE illuminant D65, relative power at kD65FirstNm + 5 k nm (data/cie/).
inline constexpr int kD65StepNm = 5;
extern const int kD65FirstNm;
extern const int kD65Samples;
extern const float kD65[];
// 1 / Y_D65, Y_D65 = ∫ D65 ȳ / ∫ ȳ (trapezoid rule on the 1 nm grid, D65 interpolated).
extern const double kD65Scale;

// Refractive index of the Schott glasses of data/glasses/ at their tabulated wavelengths.
struct GlassTable {
  const char* name;
  const float* lambda;  // nm, increasing
  const float* n;
  int size;
};
extern const int kGlassCount;
extern const GlassTable kGlasses[];

// Complex refractive index n + i k of the named metals of data/metals/ at their
// tabulated wavelengths.
struct MetalTable {
  const char* name;
  const float* lambda;  // nm, increasing
  const float* n;
  const float* k;
  int size;
};
extern const int kMetalCount;
extern const MetalTable kMetals[];

// Sigmoid-polynomial coefficients [l][z][y][x][c] (rgb_table_layout.h), fitted by
// gonio's own optimiser to the round trip through XYZ under D65.
extern const float kRgbCoefficients[3][rgb_table::kRes][rgb_table::kRes][rgb_table::kRes][3];

}  // namespace gonio::spectral_data
