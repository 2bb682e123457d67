#include "gonio/metals.h"

#include "metals_table.h"

namespace gonio {

std::optional<ComplexIor> named_metal(std::string_view name) {
  for (const auto& m : detail::metal_table()) {
    if (m.name == name) {
      return ComplexIor{Color(m.n[0], m.n[1], m.n[2]), Color(m.k[0], m.k[1], m.k[2])};
    }
  }
  return std::nullopt;
}

const std::vector<std::string_view>& named_metal_names() {
  static const std::vector<std::string_view> names = [] {
    std::vector<std::string_view> v;
    for (const auto& m : detail::metal_table()) v.push_back(m.name);
    return v;
  }();
  return names;
}

}  // namespace gonio
