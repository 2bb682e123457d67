#include "gonio/metals.h"

#include <array>

namespace gonio {
namespace {

struct MetalEntry {
  std::string_view name;
  // n and k at 650 nm (r), 550 nm (g), 450 nm (b), linearly interpolated from
  // data/metals/<name>.csv (published measurements as tabulated in pbrt-v4).
  float n[3];
  float k[3];
};

constexpr std::array<MetalEntry, 5> kMetals{{
    {"Au", {0.1678f, 0.3504f, 1.5085f}, {3.1378f, 2.7141f, 1.8789f}},
    {"Ag", {0.1394f, 0.1248f, 0.1517f}, {4.1288f, 3.3396f, 2.4704f}},
    {"Cu", {0.2166f, 0.9582f, 1.1658f}, {3.6377f, 2.5771f, 2.3939f}},
    {"Al", {1.4748f, 0.9586f, 0.6180f}, {7.7941f, 6.6870f, 5.4694f}},
    {"CuZn", {0.4440f, 0.5270f, 1.0940f}, {3.6950f, 2.7650f, 1.8290f}},
}};

}  // namespace

std::optional<ComplexIor> named_metal(std::string_view name) {
  for (const auto& m : kMetals) {
    if (m.name == name) {
      return ComplexIor{Color(m.n[0], m.n[1], m.n[2]), Color(m.k[0], m.k[1], m.k[2])};
    }
  }
  return std::nullopt;
}

const std::vector<std::string_view>& named_metal_names() {
  static const std::vector<std::string_view> names = [] {
    std::vector<std::string_view> v;
    for (const auto& m : kMetals) v.push_back(m.name);
    return v;
  }();
  return names;
}

}  // namespace gonio
