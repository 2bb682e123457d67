#pragma once
// The `subsurface` material of SPEC §2 (issue 14): a dielectric boundary over a
// homogeneous scattering medium. As a BSDF (`eval`, `sample`, `check`) the material is its
// boundary alone, which is what material_from_json returns for the type; the medium
// belongs to the renderer and `gonio subsurface`, which read it through
// subsurface_from_json.

#include <string>

#include <nlohmann/json_fwd.hpp>

#include "gonio/bxdf.h"
#include "gonio/subsurface/medium.h"

namespace gonio {

enum class SubsurfaceMethod {
  RandomWalk,  // the exact volumetric path inside a closed mesh (random_walk.h)
  Diffusion,   // the separable BSSRDF with a radial diffusion profile (diffusion.h)
};

struct Subsurface {
  Float eta = 1.33f;   // n_inside / n_outside of the boundary
  BxDF boundary;       // `dielectric` (smooth) or `roughdielectric` with `eta`
  Medium medium;       // in 1 / scene unit, after `albedo`/`mfp` or `medium`/`scale`
  SubsurfaceMethod method = SubsurfaceMethod::RandomWalk;
  // The renderer's walk: the probability of the Dwivedi-guided technique per event
  // (guided_walk.h); 0 is the classic walk of random_walk.h.
  Float guide = 0.5f;
  // The renderer's walk under a smooth boundary: next-event estimation from the walk's
  // scattering events through the boundary, weighted by MIS against the walk's own exits
  // (render/path_tracer.cpp, walk_nee).
  bool nee = true;
};

// Reads a material description whose "type" is "subsurface" (SPEC §2) — every form of
// the medium: sigma_s/sigma_a/g, albedo/mfp (inverted numerically), or a named medium of
// Jensen et al. 2001 with scale. Throws InputError naming the field and value, like
// material_from_json (same `where` and `base_dir`).
Subsurface subsurface_from_json(const nlohmann::json& description, const std::string& where = "",
                                const std::string& base_dir = "");

}  // namespace gonio
