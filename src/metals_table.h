#pragma once
// The named metals' RGB constants, generated at build time from data/metals/*.csv by
// tools/make_metal_table.cpp (the generated file defines metal_table()).

#include <span>
#include <string_view>

namespace gonio::detail {

struct MetalEntry {
  std::string_view name;
  float n[3];  // at 650 nm (r), 550 nm (g), 450 nm (b)
  float k[3];
};

std::span<const MetalEntry> metal_table();

}  // namespace gonio::detail
