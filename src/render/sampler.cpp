// The camera samples' random numbers (sampler.h).

#include "gonio/render/sampler.h"

#include <algorithm>
#include <bit>

namespace gonio::render {
namespace {

int ceil_log2(std::uint64_t n) { return n <= 1 ? 0 : std::bit_width(n - 1); }

}  // namespace

std::optional<SamplerType> sampler_type_from_name(std::string_view name) {
  if (name == "zsobol") return SamplerType::ZSobol;
  if (name == "sobol") return SamplerType::Sobol;
  if (name == "independent") return SamplerType::Independent;
  return std::nullopt;
}

const char* sampler_type_name(SamplerType type) {
  switch (type) {
    case SamplerType::ZSobol: return "zsobol";
    case SamplerType::Sobol: return "sobol";
    case SamplerType::Independent: break;
  }
  return "independent";
}

PixelSampler::PixelSampler(SamplerType type, std::int64_t samples_per_pixel, std::uint64_t seed)
    : type_(type), seed_(seed) {
  log2_spp_ = ceil_log2(std::uint64_t(std::max<std::int64_t>(samples_per_pixel, 1)));
  if (type_ == SamplerType::ZSobol) {
    key_ = mix64(seed_ ^ 0x5a0b01ULL);
    for (unsigned d = 0; d < kTabulatedDims; ++d) zsobol_dim_hash_[d] = hash_dimension(key_, int(d));
  }
}

void PixelSampler::start(int x, int y, std::uint64_t sample) {
  morton_ = morton2(std::uint32_t(x), std::uint32_t(y));
  sample_ = sample;
  rng_seeded_ = false;
  switch (type_) {
    case SamplerType::ZSobol: index_ = (morton_ << log2_spp_) | sample; break;
    case SamplerType::Sobol: index_ = sample, key_ = pixel_key(); break;
    case SamplerType::Independent: index_ = sample, key_ = splitmix64(pixel_key() ^ mix64(sample)); break;
  }
  index_reversed_ = reverse_bits32(std::uint32_t(index_));
}

std::uint64_t PixelSampler::pixel_key() const { return mix64(seed_ ^ mix64(morton_ + 0x632be59bd9b4e019ULL)); }

void PixelSampler::seed_rng() {
  rng_.seed_stream(splitmix64(pixel_key() + sample_), morton_);
  rng_seeded_ = true;
}

}  // namespace gonio::render
