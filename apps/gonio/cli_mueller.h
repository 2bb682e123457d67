#pragma once
// Printing Mueller matrices (SPEC §1, §3; issue 15): a 4×4 matrix as a row-major array of
// four rows, and a colour-valued one as an array of one matrix per channel.

#include <string>

#include "cli_io.h"
#include "gonio/polarization/mueller.h"

namespace gonio::cli {

// [[m00,m01,m02,m03],[m10,...],...]; `entry(i, j)` gives the printed number.
template <typename Entry>
std::string json_4x4(Entry&& entry) {
  std::string s = "[";
  for (int i = 0; i < 4; ++i) {
    s += i ? ",[" : "[";
    // Appended piece by piece: `"," + std::string` makes GCC 12 report a false -Wrestrict
    // (its inlined insert at position 0).
    for (int j = 0; j < 4; ++j) {
      if (j) s += ',';
      s += json_number(entry(i, j));
    }
    s += "]";
  }
  return s + "]";
}

inline std::string json_mueller(const Mueller& m) {
  return json_4x4([&](int i, int j) { return m(i, j); });
}

// One matrix per channel; in spectral mode at one wavelength, the one channel printed
// (slot 0, as json_color).
template <typename C>
std::string json_mueller_channels(const MuellerT<C>& m) {
  const int n = std::is_same_v<C, SampledSpectrum> ? 1 : C::size();
  std::string s = "[";
  for (int ch = 0; ch < n; ++ch) {
    if (ch) s += ',';
    s += json_4x4([&](int i, int j) { return m(i, j)[ch]; });
  }
  return s + "]";
}

}  // namespace gonio::cli
