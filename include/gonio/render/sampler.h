#pragma once
// Where a camera sample's random numbers come from (scene "render": {"sampler": ...},
// `gonio render --sampler`; docs/scene-format.md):
// - "zsobol" (the default): Owen-scrambled Sobol' points (math/sobol.h) indexed in the
//   Z-order of pixels (Ahmed & Wonka 2020, "Screen-space blue-noise diffusion of Monte
//   Carlo sampling error via hierarchical ordering of pixels", §4; as pbrt-v4's
//   ZSobolSampler): the index of sample i of pixel (x, y) is morton(x, y)·2^k + i, with
//   2^k ≥ the samples per pixel, scrambled per dimension (shuffled_index). A pixel's 2^k
//   samples stay an aligned block of the sequence, so for a power-of-two count they form
//   a (0, k, 2)-net in every pair of dimensions, and neighbouring pixels' blocks are the
//   neighbouring blocks of the same sequence, so their errors are negatively correlated
//   (blue noise on the screen).
// - "sobol": the same points, each pixel its own sequence (index i shuffled per dimension,
//   scrambles hashed from the pixel): stratified within a pixel, independent between
//   pixels.
// - "independent": a hash of (pixel, sample, dimension) per number.
// A sample count that is not a power of two uses the first N of the 2^k indices: still
// unbiased, but the pixel's points are then a part of a net, not a net.
// Every number depends only on (seed, pixel, sample index, dimension), so images are the
// same for any thread count and any split of the samples (`--sample-range`).

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

#include "gonio/math/constants.h"
#include "gonio/math/hash.h"
#include "gonio/math/sobol.h"
#include "gonio/rng.h"

namespace gonio::render {

enum class SamplerType : std::uint8_t { ZSobol, Sobol, Independent };

// "zsobol", "sobol", "independent"; nullopt for any other name.
std::optional<SamplerType> sampler_type_from_name(std::string_view name);
const char* sampler_type_name(SamplerType type);

// The fixed order in which a camera sample consumes dimensions, so that a dimension
// means the same decision in every sample (a sampler's stratification is per dimension).
// Bounce b's numbers start at bounce(b); a number a path does not need (no light to
// choose, no roulette yet) is skipped, never shifted onto the next decision.
namespace dims {
constexpr int kPixel = 0;       // 2D: the position in the pixel
constexpr int kWavelength = 2;  // 1D: the hero wavelength (spectral mode)
constexpr int kLens = 3;        // 2D: reserved for a lens (the camera is a pinhole)
constexpr int kPerBounce = 8;
constexpr int bounce(int b) { return 5 + kPerBounce * b; }
// Two 1-D decisions of a bounce share one 2-D point: each coordinate is stratified, and a
// point costs about as much as a number (the index's shuffle dominates).
constexpr int kChoiceAndLobe = 0;  // 2D: which sampled light, and the BSDF's lobe
constexpr int kLightPosition = 2;  // 2D: the point on the light, or the environment's direction
constexpr int kDirection = 4;      // 2D: the BSDF's direction
constexpr int kRoulette = 6;       // 1D: Russian roulette after the bounce
// + 7: spare. Random walks in media and the diffusion probe's exit draw from the
// sample's own PCG stream (PixelSampler::rng): their count is unbounded.
}  // namespace dims

class PixelSampler {
 public:
  // samples_per_pixel: the render's whole count (not one pass's), which fixes the Z-order
  // index layout; seed: the scene's.
  PixelSampler(SamplerType type, std::int64_t samples_per_pixel, std::uint64_t seed);

  // Sample `sample` of pixel (x, y); resets the PCG stream.
  void start(int x, int y, std::uint64_t sample);

  Float get1d(int dim) const {
    const std::uint64_t h = dimension_hash(dim);
    if (type_ == SamplerType::Independent) return fraction_to_float(std::uint32_t(h >> 32));
    // Dimension 0 of the shuffled index (sobol_owen_dim0), the last reversal by tables.
    const std::uint32_t value_reversed = reverse_bits32(shuffled_index_reversed(std::uint32_t(h)));
    return reversed_fraction_to_float(sobol_detail::lk_hash(value_reversed, std::uint32_t(h >> 32)));
  }
  std::array<Float, 2> get2d(int dim) const {
    const std::uint64_t h = dimension_hash(dim);
    if (type_ == SamplerType::Independent) return {fraction_to_float(std::uint32_t(h >> 32)), fraction_to_float(std::uint32_t(h))};
    // The second coordinate's scramble: another function of the same 64 hashed bits (the
    // two coordinates are different Sobol' dimensions, so even equal seeds would not make
    // them equal).
    return sobol_owen_2d_of_reversed(shuffled_index_reversed(std::uint32_t(h)), std::uint32_t(h >> 32),
                                     std::uint32_t(h >> 32) * 0x9e3779b9u ^ std::uint32_t(h));
  }

  // For the draws of unbounded count (random walks): this sample's own stream, seeded on
  // first use (most samples never draw from it).
  Pcg32& rng() {
    if (!rng_seeded_) seed_rng();
    return rng_;
  }

  // The index of the point a dimension uses: the sample's index scrambled by a nested
  // (Owen) scramble in base 2 — each bit flipped by a hash of the bits above it and the
  // dimension (Burley 2020, §5, "shuffling") — so that each dimension visits the pixel's
  // points, and for zsobol the pixels of each aligned block, in an order of its own.
  // Aligned blocks map to aligned blocks, so a pixel's samples stay a net. (Ahmed & Wonka
  // permute each base-4 digit by any of the 24 permutations, a hash per digit; the base-2
  // scramble reaches 8 of them with one hash for all bits: docs/benchmarks-history.md.)
  // Bits above the 32 the points use are folded into the seed, so that pixels far apart
  // still differ.
  // The scramble is reverse(lk(reverse(i))) (owen_scramble); the first reversal is made
  // once per sample, in start(), and the last is left to the caller: this is the index's
  // low 32 bits, bit-reversed, as the points' tables take it (sobol_owen_2d_of_reversed).
  std::uint32_t shuffled_index_reversed(std::uint32_t seed) const {
    const std::uint64_t high = index_ >> 32;
    if (high != 0) seed ^= std::uint32_t(mix64(high + seed));
    return sobol_detail::lk_hash(index_reversed_, seed);
  }

 private:
  // 64 bits for one dimension of this sample: 32 for the index's shuffle, 32 for the
  // point's scramble (zsobol: from the seed alone, as the index carries the pixel; sobol:
  // from the seed and the pixel; independent: the numbers themselves).
  std::uint64_t dimension_hash(int dim) const {
    if (type_ == SamplerType::ZSobol && unsigned(dim) < kTabulatedDims) return zsobol_dim_hash_[std::size_t(dim)];
    return hash_dimension(key_, dim);
  }
  static std::uint64_t hash_dimension(std::uint64_t key, int dim) {
    return mix64(key + 0x9e3779b97f4a7c15ULL * std::uint64_t(dim + 1));
  }
  // zsobol's key is the seed's alone: its hashes of the first dimensions (16 bounces)
  // are made once per render.
  static constexpr unsigned kTabulatedDims = unsigned(dims::bounce(16));
  std::array<std::uint64_t, kTabulatedDims> zsobol_dim_hash_{};

  std::uint64_t pixel_key() const;
  void seed_rng();

  SamplerType type_;
  int log2_spp_ = 0;
  std::uint64_t seed_ = 0;
  std::uint64_t key_ = 0;    // hashed from (seed) for zsobol, (seed, pixel) for sobol, (seed, pixel, sample) for independent
  std::uint64_t index_ = 0;  // zsobol: morton(x, y)·2^k + i; sobol: i
  std::uint32_t index_reversed_ = 0;  // the low 32 bits of index_, bit-reversed
  std::uint64_t morton_ = 0;  // of the sample's pixel
  std::uint64_t sample_ = 0;
  Pcg32 rng_;
  bool rng_seeded_ = false;
};

}  // namespace gonio::render
