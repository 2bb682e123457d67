#pragma once
// The named metals' RGB constants, generated at build time from data/metals/*.csv by
// tools/make_metal_table.cpp (the generated file defines metal_table()).

#include <span>
#include <string_view>

namespace gonio::detail {

struct MetalEntry {
  std::string_view name;
  float n[3];  // the measured n at 650 nm (r), 550 nm (g), 450 nm (b)
  float k[3];  // fitted so that F0(n, k) is the colour of the reflectance spectrum
};

std::span<const MetalEntry> metal_table();

}  // namespace gonio::detail
