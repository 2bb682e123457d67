#pragma once
// A measured isotropic BRDF ready for rendering: the MERL table (merl.h) with
// interpolation, and a tabulated importance-sampling distribution built at load time.
//
// Evaluation. f(wo, wi) is interpolated trilinearly between bin centres in the table's
// own coordinates: u = 90 √(θh/(π/2)) − ½ (the θh axis is non-uniform), v = θd/1° − ½,
// w = φd/1° − ½ taken modulo 180 (φd is periodic with period 180°, SPEC §2). Beyond the
// outermost centres (θh < 0.0028° or > 89.0°, θd < 0.5° or > 89.5°) the nearest centre's
// value holds. Entries that were not measured are left out and the weights of the
// measured ones renormalised; where all eight neighbours are missing, f = 0.
//
// Sampling. For isotropic f the density of wi given wo depends only on θo and on wi's
// place relative to wo. Per bin of θo (kThetaOBins, narrowing towards grazing), the target
// f(wo, wi) cos θi is tabulated at the nodes of a grid of wi in spherical coordinates
// around the mirror direction of wo: the angle θ' from it cut at √(sin(θ'/2)) uniform
// (fine near the specular peak, like MERL's own θh axis: the first cell ends at 0.028°), the azimuth φ' around it in [0, π] (f
// is symmetric under the mirror through the plane of incidence; the sign is drawn
// separately). Centred on the mirror direction, the horizon cuts the cells along a smooth
// curve even at grazing incidence (over half vectors it leaves a sliver no grid
// resolves). The density is bilinear in (cos θ', φ') between the nodes — continuous and
// bounded, per unit solid angle since dω = d(cos θ') dφ' — and sampled as bilinear patches
// (a cell by its mass, then the point within it; pbrt-v4's SampleBilinear). A fraction
// kDefensive of samples is cosine-distributed, so that the pdf is positive wherever f is
// (Hesterberg 1995, defensive mixtures).

#include <array>
#include <cstdint>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "gonio/color.h"
#include "gonio/math/constants.h"
#include "gonio/math/vec3.h"
#include "gonio/merl.h"

namespace gonio {

class MeasuredData {
 public:
  static constexpr int kThetaOBins = 32, kThetaCells = 64, kPhiCells = 32;
  static constexpr Float kDefensive = 0.1f;

  explicit MeasuredData(MerlTable table, std::string path = {});

  const MerlTable& table() const { return table_; }
  const std::string& path() const { return path_; }

  // f for wo, wi both above the surface (z > 0, unit length); 0 if either is not.
  Color lookup(const Vec3& wo, const Vec3& wi) const;
  // The sampling density of wi given wo (both z > 0), per unit solid angle.
  Float pdf(const Vec3& wo, const Vec3& wi) const;
  // lookup and pdf together.
  struct Eval {
    Color f;
    Float pdf;
  };
  Eval eval(const Vec3& wo, const Vec3& wi) const;
  // A direction wi for wo (z > 0) from three uniform numbers; z ≤ 0 when the drawn half
  // vector reflects wo below the surface (no sample).
  Vec3 sample(const Vec3& wo, Float u_lobe, Float u1, Float u2) const;

 private:
  struct Cell {
    int theta_bin, ix, iphi;
  };
  void build_sampler();
  int theta_o_bin(const Vec3& wo) const;
  // The tabulated density (the bin has a table), given the azimuth of wi around the mirror
  // direction of wo (measured_data.cpp, pdf_azimuth_args) in [−π, π].
  Float tabulated_pdf(const Vec3& wo, const Vec3& wi, int theta_o_bin, Float azimuth) const;
  // The sampling density of sample(): kDefensive of cosine plus the tabulated density, or
  // cosine alone where θo's bin has no table (the one formula that eval and pdf use).
  Float mixture_pdf(const Vec3& wo, const Vec3& wi, int theta_o_bin, Float azimuth) const;

  MerlTable table_;
  std::string path_;
  // Per θo bin: the normalised density at the cells' corners ((kThetaCells + 1) ×
  // (kPhiCells + 1)), the cells' probabilities (kThetaCells × kPhiCells), the marginal CDF over
  // θ' (kThetaCells + 1) and the conditional CDFs over φ' (kThetaCells × (kPhiCells + 1)).
  std::vector<float> node_, cell_prob_, marginal_cdf_, conditional_cdf_;
  // Guide tables of the CDFs (cdf_guide.h), twice as many steps as intervals: the same
  // intervals as a binary search, found in less than one step on average.
  static constexpr int kThetaGuide = 2 * kThetaCells, kPhiGuide = 2 * kPhiCells;
  std::vector<std::uint8_t> marginal_guide_, conditional_guide_;
  std::array<bool, kThetaOBins> has_table_{};  // false: the bin's target was 0 everywhere
  std::array<float, kThetaCells + 1> cos_edge_{};  // cos θ' at the cells' edges
  std::array<float, kThetaCells> inv_cos_width_{};  // 1 / (cos_edge_[i] − cos_edge_[i + 1])
  // θo bins by cos θo (theta_o_bin): the bin at the top of each of kBinLutSize steps, and
  // each bin's lower edge in cos θo.
  static constexpr int kBinLutSize = 1024;
  std::array<std::uint8_t, kBinLutSize> bin_lut_{};
  std::array<float, kThetaOBins> bin_cos_lo_{};
};

// The table at `path`, read once per process and shared: materials that name the same
// file (a scene's, a blend's parts) hold one copy. Throws InputError as read_merl.
std::shared_ptr<const MeasuredData> load_measured(const std::string& path);

}  // namespace gonio
