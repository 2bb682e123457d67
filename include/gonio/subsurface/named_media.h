#pragma once
// Media measured by Jensen, Marschner, Levoy & Hanrahan 2001 ("A Practical Model for
// Subsurface Light Transport", SIGGRAPH 2001, Figure 5): the reduced scattering
// coefficient σs′ = (1 − g) σs and the absorption coefficient σa in mm⁻¹ for the red,
// green and blue channels, measured with η = 1.3. (Chicken1's σa is 0.015, 0.077, 0.19
// as pbrt-v3 prints the table; some copies have 0.0015 for red.)

#include <array>
#include <optional>
#include <string_view>

#include "gonio/color.h"

namespace gonio {

struct NamedMedium {
  std::string_view name;
  std::array<double, 3> sigma_s_prime;  // mm⁻¹
  std::array<double, 3> sigma_a;        // mm⁻¹
};

inline constexpr NamedMedium kJensen2001Media[] = {
    {"apple", {2.29, 2.39, 1.97}, {0.0030, 0.0034, 0.046}},
    {"chicken1", {0.15, 0.21, 0.38}, {0.015, 0.077, 0.19}},
    {"chicken2", {0.19, 0.25, 0.32}, {0.018, 0.088, 0.20}},
    {"cream", {7.38, 5.47, 3.15}, {0.0002, 0.0028, 0.0163}},
    {"ketchup", {0.18, 0.07, 0.03}, {0.061, 0.97, 1.45}},
    {"marble", {2.19, 2.62, 3.00}, {0.0021, 0.0041, 0.0071}},
    {"potato", {0.68, 0.70, 0.55}, {0.0024, 0.0090, 0.12}},
    {"skimmilk", {0.70, 1.22, 1.90}, {0.0014, 0.0025, 0.0142}},
    {"skin1", {0.74, 0.88, 1.01}, {0.032, 0.17, 0.48}},
    {"skin2", {1.09, 1.59, 1.79}, {0.013, 0.070, 0.145}},
    {"wholemilk", {2.55, 3.21, 3.77}, {0.0011, 0.0024, 0.014}},
};

// The index the paper measured with; a named medium's default eta.
inline constexpr double kJensen2001Eta = 1.3;

inline const NamedMedium* find_named_medium(std::string_view name) {
  for (const auto& m : kJensen2001Media)
    if (m.name == name) return &m;
  return nullptr;
}

}  // namespace gonio
