#pragma once
// Special functions the models need beyond <cmath>.

#include <cmath>

#include "gonio/math/constants.h"

namespace gonio {

// Inverse error function, single precision: Giles 2012, "Approximating the erfinv
// function" (GPU Computing Gems Jade, ch. 10), the two-branch polynomial in
// w = −ln((1 − x)(1 + x)); relative error below 4e-7 on (−1, 1). x = ±1 clamps to a
// large finite value.
inline Float erf_inv(Float x) {
  x = std::fmax(std::fmin(x, Float(1) - Float(1e-7)), Float(-1) + Float(1e-7));
  Float w = -std::log((Float(1) - x) * (Float(1) + x));
  Float p;
  if (w < Float(5)) {
    w -= Float(2.5);
    p = Float(2.81022636e-08);
    p = Float(3.43273939e-07) + p * w;
    p = Float(-3.5233877e-06) + p * w;
    p = Float(-4.39150654e-06) + p * w;
    p = Float(0.00021858087) + p * w;
    p = Float(-0.00125372503) + p * w;
    p = Float(-0.00417768164) + p * w;
    p = Float(0.246640727) + p * w;
    p = Float(1.50140941) + p * w;
  } else {
    w = std::sqrt(w) - Float(3);
    p = Float(-0.000200214257);
    p = Float(0.000100950558) + p * w;
    p = Float(0.00134934322) + p * w;
    p = Float(-0.00367342844) + p * w;
    p = Float(0.00573950773) + p * w;
    p = Float(-0.0076224613) + p * w;
    p = Float(0.00943887047) + p * w;
    p = Float(1.00167406) + p * w;
    p = Float(2.83297682) + p * w;
  }
  return p * x;
}

}  // namespace gonio
