#pragma once
// Height fields built by hand for the instrument's tests (the generators are tested on
// their own): a flat patch, a periodic egg-crate of sines and a V-groove profile.

#include <cmath>

#include "gonio/math/constants.h"
#include "gonio/measure/heightfield.h"

namespace gonio::measure::testsurf {

inline HeightField flat_field() {
  HeightField f;
  f.n = 1;
  f.size = 1;
  f.z = {0.0f};
  return f;
}

// z = a (sin 2πx/L + sin 2πy/L) on n × n samples of spacing 1 (L = n): forward-difference
// slopes up to about 2πa/n per axis.
inline HeightField eggcrate_field(int n, double a) {
  HeightField f;
  f.n = n;
  f.size = n;
  f.z.resize(std::size_t(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      f.z[std::size_t(i) + std::size_t(n) * j] =
          float(a * (std::sin(2 * kPiD * i / n) + std::sin(2 * kPiD * j / n)));
  return f;
}

// Grooves along y with facets of slope ±s (a periodic triangle wave in x; the groove's
// opening angle is 2 atan(1/s)).
inline HeightField vgroove_field(int n, double s) {
  HeightField f;
  f.n = n;
  f.size = n;
  f.z.resize(std::size_t(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) f.z[std::size_t(i) + std::size_t(n) * j] = float(s * std::min(i, n - i));
  return f;
}

}  // namespace gonio::measure::testsurf
