#pragma once
// A MaterialX node graph compiled into a flat program (docs/materialx.md, "Node graphs").
// The document reader (src/io/materialx.cpp) compiles, once per material, every node
// upstream of a surface's connected inputs into a list of instructions over a register
// file of 4-lane values; run() evaluates them in order at one shading point: no
// recursion, no allocation, no virtual call. A float is held splatted in all four lanes,
// so that component-wise instructions serve every MaterialX type (float, vector2/3/4,
// color3/4, integer, boolean) and MaterialX's float-second-input variants (e.g.
// multiply_color3FA) alike.
//
// Each instruction follows its node's definition in the MaterialX Specification v1.39
// (documents/Specification/MaterialX.StandardNodes.md, "Standard Nodes") and, where the
// text is short of a formula, the GLSL reference (libraries/stdlib/genglsl/mx_*.glsl).

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace gonio::mtlxgraph {

using Reg = std::array<double, 4>;

// Where a graph is evaluated: texture coordinates (MaterialX's UV0 geometric property),
// the object-space position and normal.
struct ShadingPoint {
  double u = 0.5, v = 0.5;
  double px = 0, py = 0, pz = 0;
  double nx = 0, ny = 0, nz = 1;
};

enum class Op : std::uint8_t {
  Add, Subtract, Multiply, Divide, Modulo, Power, Min, Max,
  Clamp,        // a in [b, c]
  Mix,          // bg = a, fg = b, mix = c: bg (1 − mix) + fg mix
  Absval, Sign, Floor, Ceil, Round, Sqrt, Sin, Cos, Tan, Asin, Acos, Atan2, Exp, Ln,
  Invert,       // amount b − a
  Smoothstep,   // a between low b and high c
  Dot,          // aux = width; splatted
  Magnitude,    // aux = width; splatted
  Normalize,    // aux = width
  Swizzle,      // out[i] = a[aux >> (2 i) & 3], splatted when aux2 = 1
  Combine,      // out = (a.x, b.x, c.x, d.x)
  Texcoord, Position, Normal,
  Rotate2d,     // a rotated by b degrees (counter-clockwise)
  Ramplr, Ramptb,  // a = left/top, b = right/bottom, c = texcoord
  Ramp4,        // a tl, b tr, c bl, d br, e texcoord
  Splitlr, Splittb,  // a, b, c = center, d = texcoord
  IfGreater, IfGreaterEq, IfEqual,  // value1 a, value2 b, in1 c, in2 d
  Switch,       // which = a (lane 0), candidates b.. (aux = count)
  Luminance,    // a, b = coefficients
};

struct Instr {
  Op op = Op::Add;
  std::uint8_t aux2 = 0;
  std::uint16_t out = 0;
  std::uint32_t aux = 0;
  std::array<std::uint16_t, 6> in{};
};

// Largest program: far above the corpus' graphs (the biggest, a Standard Surface through
// the data library, is a few hundred instructions); an enormous graph is refused.
inline constexpr std::size_t kMaxInstructions = 10000;
// Registers are 16-bit indices: constants and results together stay below this.
inline constexpr std::size_t kMaxRegisters = 60000;

class Program {
 public:
  // A register holding `value` before every run (a constant).
  std::uint16_t constant(const Reg& value);
  // A register written by `instr` (its `out` set here).
  std::uint16_t emit(Instr instr);
  std::size_t register_count() const { return init_.size(); }
  std::size_t size() const { return code_.size(); }

  // Evaluates every instruction at `p` into `regs` (register_count() entries). No
  // allocation, no exception; a non-finite result stays where it is, for the caller to
  // refuse (the reader does, naming the input).
  void run(const ShadingPoint& p, std::span<Reg> regs) const noexcept;

 private:
  std::vector<Reg> init_;
  std::vector<Instr> code_;
};

}  // namespace gonio::mtlxgraph
