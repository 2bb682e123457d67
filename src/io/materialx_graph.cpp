// The flat program of a MaterialX node graph (include/gonio/io/materialx_graph.h). Each
// case cites its node: MaterialX Specification v1.39, Standard Nodes, and the GLSL
// reference functions named (libraries/stdlib/genglsl), read for the formulas.

#include "gonio/io/materialx_graph.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gonio::mtlxgraph {

std::uint16_t Program::constant(const Reg& value) {
  init_.push_back(value);
  return std::uint16_t(init_.size() - 1);
}

std::uint16_t Program::emit(Instr instr) {
  instr.out = constant(Reg{});
  code_.push_back(instr);
  return instr.out;
}

namespace {

// mx_aastep without its filter width (a point sample): 1 where x ≥ edge.
double graph_step(double edge, double x) { return x >= edge ? 1.0 : 0.0; }

double graph_smoothstep(double x, double lo, double hi) {
  // mx_smoothstep_float: 0 below low, 1 at or above high, Hermite between.
  if (x >= hi) return 1;
  if (x <= lo) return 0;
  const double t = (x - lo) / (hi - lo);
  return t * t * (3 - 2 * t);
}

}  // namespace

void Program::run(const ShadingPoint& p, std::span<Reg> r) const noexcept {
  std::copy(init_.begin(), init_.end(), r.begin());
  for (const Instr& I : code_) {
    const Reg& a = r[I.in[0]];
    const Reg& b = r[I.in[1]];
    const Reg& c = r[I.in[2]];
    const Reg& d = r[I.in[3]];
    const Reg& e = r[I.in[4]];
    Reg o{};
    const auto each = [&](auto f) {
      for (size_t i = 0; i < 4; ++i) o[i] = f(a[i], b[i], c[i]);
    };
    switch (I.op) {
      case Op::Add: each([](double x, double y, double) { return x + y; }); break;
      case Op::Subtract: each([](double x, double y, double) { return x - y; }); break;
      case Op::Multiply: each([](double x, double y, double) { return x * y; }); break;
      // divide: a zero divisor gives 0 (as the data library's safe variants do), not Inf.
      case Op::Divide: each([](double x, double y, double) { return y == 0 ? 0.0 : x / y; }); break;
      // modulo: x − y floor(x / y) (mx_mod, GLSL's mod).
      case Op::Modulo: each([](double x, double y, double) { return y == 0 ? 0.0 : x - y * std::floor(x / y); }); break;
      case Op::Power: each([](double x, double y, double) { return std::pow(x, y); }); break;
      case Op::Min: each([](double x, double y, double) { return std::min(x, y); }); break;
      case Op::Max: each([](double x, double y, double) { return std::max(x, y); }); break;
      case Op::Clamp: each([](double x, double lo, double hi) { return std::min(std::max(x, lo), hi); }); break;
      case Op::Mix: each([](double bg, double fg, double m) { return bg * (1 - m) + fg * m; }); break;
      case Op::Absval: each([](double x, double, double) { return std::abs(x); }); break;
      case Op::Sign: each([](double x, double, double) { return double((x > 0) - (x < 0)); }); break;
      case Op::Floor: each([](double x, double, double) { return std::floor(x); }); break;
      case Op::Ceil: each([](double x, double, double) { return std::ceil(x); }); break;
      case Op::Round: each([](double x, double, double) { return std::round(x); }); break;
      case Op::Sqrt: each([](double x, double, double) { return std::sqrt(x); }); break;
      case Op::Sin: each([](double x, double, double) { return std::sin(x); }); break;
      case Op::Cos: each([](double x, double, double) { return std::cos(x); }); break;
      case Op::Tan: each([](double x, double, double) { return std::tan(x); }); break;
      case Op::Asin: each([](double x, double, double) { return std::asin(x); }); break;
      case Op::Acos: each([](double x, double, double) { return std::acos(x); }); break;
      // atan2: iny = a, inx = b (ND_atan2: atan(iny, inx)).
      case Op::Atan2: each([](double y, double x, double) { return std::atan2(y, x); }); break;
      case Op::Exp: each([](double x, double, double) { return std::exp(x); }); break;
      case Op::Ln: each([](double x, double, double) { return std::log(x); }); break;
      case Op::Invert: each([](double x, double amount, double) { return amount - x; }); break;
      case Op::Smoothstep: each([](double x, double lo, double hi) { return graph_smoothstep(x, lo, hi); }); break;
      case Op::Dot: {
        double s = 0;
        for (size_t i = 0; i < I.aux; ++i) s += a[i] * b[i];
        o = {s, s, s, s};
        break;
      }
      case Op::Magnitude: {
        double s = 0;
        for (size_t i = 0; i < I.aux; ++i) s += a[i] * a[i];
        s = std::sqrt(s);
        o = {s, s, s, s};
        break;
      }
      case Op::Normalize: {
        double s = 0;
        for (size_t i = 0; i < I.aux; ++i) s += a[i] * a[i];
        s = std::sqrt(s);
        for (size_t i = 0; i < I.aux; ++i) o[i] = s > 0 ? a[i] / s : 0;
        break;
      }
      case Op::Swizzle:
        for (size_t i = 0; i < 4; ++i) o[i] = a[(I.aux >> (2 * i)) & 3u];
        break;
      case Op::Combine: o = {a[0], b[0], c[0], d[0]}; break;
      case Op::Texcoord: o = {p.u, p.v, 0, 0}; break;
      case Op::Position: o = {p.px, p.py, p.pz, 0}; break;
      case Op::Normal: o = {p.nx, p.ny, p.nz, 0}; break;
      case Op::Rotate2d: {
        // mx_rotate_vector2: (ca x + sa y, −sa x + ca y), amount in degrees.
        const double t = b[0] * std::numbers::pi / 180, s = std::sin(t), co = std::cos(t);
        o = {co * a[0] + s * a[1], -s * a[0] + co * a[1], 0, 0};
        break;
      }
      // mx_ramplr: mix(valuel, valuer, clamp(s)); mx_ramptb: mix(valueb, valuet, clamp(t)).
      case Op::Ramplr: {
        const double s = std::clamp(c[0], 0.0, 1.0);
        for (size_t i = 0; i < 4; ++i) o[i] = a[i] * (1 - s) + b[i] * s;
        break;
      }
      case Op::Ramptb: {
        const double t = std::clamp(c[1], 0.0, 1.0);
        for (size_t i = 0; i < 4; ++i) o[i] = b[i] * (1 - t) + a[i] * t;
        break;
      }
      case Op::Ramp4: {
        // NG_ramp4: top = mix(tl, tr, s), bottom = mix(bl, br, s), mix(bottom, top, t).
        const double s = std::clamp(e[0], 0.0, 1.0), t = std::clamp(e[1], 0.0, 1.0);
        for (size_t i = 0; i < 4; ++i) {
          const double top = a[i] * (1 - s) + b[i] * s, bottom = c[i] * (1 - s) + d[i] * s;
          o[i] = bottom * (1 - t) + top * t;
        }
        break;
      }
      // mx_splitlr: mix(valuel, valuer, aastep(center, s)); splittb on t, valuet above.
      case Op::Splitlr: {
        const double m = graph_step(c[0], d[0]);
        for (size_t i = 0; i < 4; ++i) o[i] = a[i] * (1 - m) + b[i] * m;
        break;
      }
      case Op::Splittb: {
        const double m = graph_step(c[0], d[1]);
        for (size_t i = 0; i < 4; ++i) o[i] = b[i] * (1 - m) + a[i] * m;
        break;
      }
      // ifgreater: in1 where value1 > value2, else in2 (ifgreatereq: ≥; ifequal: ==).
      case Op::IfGreater: o = a[0] > b[0] ? c : d; break;
      case Op::IfGreaterEq: o = a[0] >= b[0] ? c : d; break;
      case Op::IfEqual: o = a[0] == b[0] ? c : d; break;
      case Op::Switch: {
        // switch: in(which + 1), `which` truncated and clamped to the inputs (mx_switch).
        const double w = std::isfinite(a[0]) ? std::floor(a[0]) : 0;
        const size_t k = size_t(std::clamp(w, 0.0, double(I.aux - 1)));
        o = r[I.in[1 + k]];
        break;
      }
      case Op::Luminance: {
        // mx_luminance_color3: dot(in, lumacoeffs) in every channel.
        const double y = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        o = {y, y, y, a[3]};
        break;
      }
    }
    r[I.out] = o;
  }
}

}  // namespace gonio::mtlxgraph
