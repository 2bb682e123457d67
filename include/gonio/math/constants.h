#pragma once
// Numeric constants shared by the models. gonio evaluates models in single precision
// (what renderers use); accumulations over many samples are done in double.

namespace gonio {

using Float = float;

inline constexpr Float kPi = 3.14159265358979323846f;
inline constexpr Float kInvPi = 0.318309886183790671538f;
inline constexpr Float kInv2Pi = 0.159154943091895335769f;
inline constexpr Float kInv4Pi = 0.0795774715459476678845f;
inline constexpr Float kPiOver2 = 1.57079632679489661923f;
inline constexpr Float kPiOver4 = 0.785398163397448309616f;
inline constexpr double kPiD = 3.14159265358979323846;

// Largest float strictly below 1: uniform samples are mapped into [0, 1).
inline constexpr Float kOneMinusEpsilon = 0x1.fffffep-1f;

}  // namespace gonio
