#pragma once
// A material written as an RGL `.bsdf` tensor file (SPEC §3 `gonio tabulate ... --format
// rgl`; Dupuy & Jakob 2018, §4–5), acquired as the paper's pipeline does on a virtual
// gonioreflectometer that can evaluate f exactly:
//  1. the NDF from retro-reflection by the paper's power iteration (§4): at ω = wi = wo
//     the microfacet BRDF is f(ω, ω) = D(ω) G1(ω)/(4 cos²θ) with G1 = cos θ/σ(ω), so
//     D_{k+1}(ω) = 4 f(ω, ω) cos θ σ_k(ω), σ_k(ω) = ∫ D_k(m) ⟨m, ω⟩₊ dm, each iterate
//     normalized to ∫ D cos θm dm = 1 (for a material that is no microfacet model, D is
//     the paper's "pseudo-NDF": the spectra absorb the rest);
//  2. σ, and the VNDF D_ω(m) = ⟨ω, m⟩₊ D(m)/σ(ω) on the paper's (√(2θ/π), φ) grid;
//  3. at each incident node, the sample grid warped by the VNDF to microfacet normals and
//     reflected: there the value f·cos θ divided by D/(4σ) (jacobian = 1) as rgb and
//     spectra, and its luminance (plus a floor, so every direction stays reachable).
// Every field SPEC §3 lists is written: description, jacobian, theta_i, phi_i, ndf, sigma,
// vndf, luminance, wavelengths, spectra, rgb.

#include <cstdint>
#include <string>
#include <vector>

#include "gonio/bxdf.h"

namespace gonio {

struct RglWriteOptions {
  bool anisotropic = false;  // write φi over [−π, π] (else one φi, φm relative to it)
  int n_theta_i = 0;         // 0: 16 isotropic, 8 anisotropic
  int n_phi_i = 17;          // anisotropic only
  int n_ndf = 64;            // NDF, σ and VNDF nodes per axis
  int n_sample = 32;         // luminance/spectra nodes per axis
  float theta_i_max_deg = 88;
  // Wavelengths of `spectra`: 360, 380, ..., 820 nm unless given.
  std::vector<float> wavelengths;
  std::string description = "gonio";
};

// The file's bytes (encode_tensor_file). The spectra are the RGB values upsampled as
// unbounded spectra (Jakob & Hanika 2019), as gonio's spectral mode upsamples RGB data.
std::vector<std::uint8_t> tabulate_rgl(const BxDF& model, const RglWriteOptions& options);

}  // namespace gonio
