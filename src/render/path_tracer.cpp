// Path tracing of the reflection equation (lecture eqs. 1 and 2), with next-event
// estimation and multiple importance sampling (Veach 1997, §9.2, power heuristic β = 2).

#include "gonio/render/path_tracer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

#include "gonio/error.h"
#include "gonio/polarization/fresnel_factor.h"
#include "gonio/polarization/polarized_bxdf.h"
#include "gonio/render/subsurface_probe.h"
#include "gonio/render/subsurface_walk.h"
#include "gonio/render/walk_nee_plane.h"
#include "gonio/subsurface/diffusion.h"
#include "gonio/subsurface/guided_walk.h"
#include "gonio/subsurface/openpbr_interior.h"
#include "gonio/subsurface/random_walk.h"
#include "gonio/subsurface/sw_bxdf.h"

namespace gonio::render {
namespace {

// Power heuristic of Veach 1997, eq. 9.13 with β = 2, for one sample of each strategy.
Float power_heuristic(Float pdf_a, Float pdf_b) {
  const Float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  return a + b > 0 ? a / (a + b) : Float(0);
}

// Shading normals are an approximation: a direction can lie above the shading surface and
// below the geometric one. Light must not pass through the geometric surface (a leak), so
// a pair of directions counts only when the geometric sides agree with the lobe the
// shading frame assigns (Veach 1997, §5.3).
bool sides_agree(const Vec3& wo_world, const Vec3& wi_world, const Vec3& ng, const Vec3& wo, const Vec3& wi) {
  const bool geometric_reflection = dot(wo_world, ng) * dot(wi_world, ng) > 0;
  const bool shading_reflection = wo.z * wi.z > 0;
  return geometric_reflection == shading_reflection;
}

// What the throughput of a path is, and how it meets a vertex: here a colour (RGB or
// spectral), which needs no reference frames. PolarizedShading below replaces it by a
// Mueller matrix per channel.
template <typename Colour>
struct ScalarTransport {
  using Radiance = Colour;
  static Colour start(const Ray&) { return Colour(1); }
  static void at_vertex(Colour&, const Frame&, const Vec3& /*wo*/, const Vec3& /*wo_world*/) {}
  static void leave(const Frame&, const Vec3& /*wi*/) {}
  static Float magnitude(const Colour& beta) { return beta.max_component(); }
  // L += beta · x (x: light reaching the vertex, already through its BSDF) and
  // L += beta · Le · w (emission seen directly).
  static void add(Colour& L, const Colour& beta, const Colour& x) { L += beta * x; }
  static void add(Colour& L, const Colour& beta, const Colour& Le, Float w) { L += beta * Le * w; }
  static bool finite(const Colour& L) { return L.is_finite(); }
};

// What differs between RGB and spectral transport: the model at a hit and the lights'
// emission. The estimator below is one template over the two (and over their polarized
// forms).
struct RgbShading : ScalarTransport<Color> {
  using C = Color;
  using U = Color;
  // The model at a textured shading point: a slot of the calling thread's (radiance()),
  // not a member: GCC 12 zero-filled a member std::optional's 3 KB of BxDF storage at every
  // construction of this state, even list-initialized, a memset per camera sample.
  std::optional<BxDF>* textured = nullptr;
  // Whether media are walked (RGB; not as the base of polarized shading): then a material
  // with a volume form (Material::subsurface) shades with its boundary.
  bool walks = true;
  // `inside`: wo is behind the geometric normal (Material::inside).
  const BxDF& bxdf(const Material& m, const Vec2& uv, bool inside) {
    if (inside && m.inside && (walks || !m.subsurface_bsdf_fallback)) return *m.inside;
    if (walks && m.subsurface) return m.subsurface->boundary;
    return m.at(uv, *textured);
  }
  // An emitting surface's radiance, given in linear sRGB (surface_emission below).
  Color surface(const Color& rgb) const { return rgb; }
  // σa of an absorbing interior (Material::absorption).
  Color absorption(const Material& m) const { return *m.absorption; }
  static void attenuate(Color& beta, const Color& sigma_a, Float t) { beta *= map(sigma_a, [t](Float s) { return std::exp(-s * t); }); }
  Color point(const PointLight& l) const { return l.intensity; }
  Color area(const AreaLight&, const Color& rgb) const { return rgb; }
  Color environment(const Environment&, const Vec3&, const Color& rgb) const { return rgb; }
};

struct SpectralShading : ScalarTransport<SampledSpectrum> {
  using C = SampledSpectrum;
  using U = SampledSpectrum;
  SampledWavelengths& w;
  SpectralScratch& scratch;
  // The textured model and the vertex's spectral model: slots of the calling thread's
  // (SpectralSlots), for the reason RgbShading::textured gives (6 KB zero-filled per camera
  // sample when they were members).
  std::optional<BxDF>* textured;
  SpectralBxDF* model;
  // The previous vertex's model is no longer needed when the next one is made, so the
  // scratch space of blends is reused.
  const SpectralBxDF& bxdf(const Material& m, const Vec2& uv, bool inside) {
    scratch.reset();
    // A volume form is RGB-only: its inside model only with an absorbing interior.
    const bool in = inside && m.inside && !m.subsurface_bsdf_fallback;
    *model = to_spectral(in ? *m.inside : m.at(uv, *textured), m.spectra, w, scratch, m.textured_colours);
    return *model;
  }
  // Upsampled as an illuminant, as a light given in RGB is (lights.h).
  C surface(const Color& rgb) const { return rgb_illuminant(rgb, w); }
  // σa(λ) = −ln T(λ)/d from the upsampled transmission_color T (openpbr_interior.h).
  C absorption(const Material& m) const {
    const SampledSpectrum t = m.absorption_colour->eval(w);
    C sigma;
    for (int i = 0; i < C::size(); ++i) sigma[i] = openpbr::extinction_from_colour(t[i], m.absorption_depth);
    return sigma;
  }
  static void attenuate(C& beta, const C& sigma_a, Float t) { beta *= map(sigma_a, [t](Float s) { return std::exp(-s * t); }); }
  C point(const PointLight& l) const { return emission_spectrum(l.spectrum, l.intensity, w); }
  C area(const AreaLight& l, const Color&) const { return area_light_spectrum(l, w); }
  C environment(const Environment& e, const Vec3& dir, const Color&) const { return e.radiance(dir, w); }
};

struct SpectralSlots {
  std::optional<BxDF> textured;
  SpectralBxDF model;
};

// Polarized transport (issue 15; docs/polarization.md, "Polarized rendering"). The
// throughput `beta` is the Mueller matrix (per channel) from the light's end of the
// current segment to the camera's film; it expects the Stokes vector of the light on that
// segment in the frame whose s axis is `s_seg` (world space, ⊥ the segment; p = d × s for
// the light's direction of travel d, towards the camera). At a vertex the BSDF gives its
// matrix in the s/p frames of wo and wi (polarization/fresnel_factor.h): `beta` is turned
// onto wo's frame first, and the segment before the vertex takes wi's frame. The lights
// emit unpolarized light, so of the matrix reaching a light only column 0 is needed.
template <typename Base>
struct PolarizedShading {
  using U = typename Base::C;
  using C = MuellerT<U>;
  using Radiance = std::array<U, 4>;  // S0..S3, each a colour
  Base base;
  // The camera's image x axis and its polarizer (null: none), from Camera.
  Vec3 image_x;
  const MuellerT<U>* polarizer;
  // Untextured RGB materials' polarized models, made once (null: make one per vertex).
  const std::vector<std::optional<PolarizedBxDF>>* cached;
  std::optional<PolarizedBxDFT<U>> model;
  Vec3 s_seg{1, 0, 0};

  const PolarizedBxDFT<U>& bxdf(const Material& m, const Vec2& uv, bool inside) {
    const bool in = inside && m.inside && !m.subsurface_bsdf_fallback;
    if constexpr (std::is_same_v<U, Color>) {
      const size_t i = static_cast<size_t>(&m - cached_base);
      if (!in && m.textures.empty() && cached && (*cached)[i]) return *(*cached)[i];
    }
    return model.emplace(base.bxdf(m, uv, in));
  }
  const Material* cached_base = nullptr;  // &scene.materials[0], for the cache's index

  U surface(const Color& rgb) const { return base.surface(rgb); }
  U absorption(const Material& m) const { return base.absorption(m); }
  // Absorption does not polarize: every entry of the Mueller matrix scales alike.
  static void attenuate(C& beta, const U& sigma_a, Float t) {
    const U k = map(sigma_a, [t](Float s) { return std::exp(-s * t); });
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) beta(r, c) = beta(r, c) * k;
  }
  U point(const PointLight& l) const { return base.point(l); }
  U area(const AreaLight& l, const Color& rgb) const { return base.area(l, rgb); }
  U environment(const Environment& e, const Vec3& d, const Color& rgb) const { return base.environment(e, d, rgb); }

  // The film's frame (SPEC §1: image axes, Q = I_x − I_y): s along the image's x axis
  // projected ⊥ the ray, p = d × s along its y axis for d = −ray.d.
  C start(const Ray& ray) {
    const Vec3 d = -ray.d;
    s_seg = normalize(image_x - d * dot(d, image_x));
    if (polarizer) return *polarizer;
    C one;
    for (int i = 0; i < 4; ++i) one(i, i) = U(1);
    return one;
  }
  void at_vertex(C& beta, const Frame& frame, const Vec3& wo, const Vec3& wo_world) const {
    // S_seg = R(α) S_wo, α the turn about the light's direction (wo) from wo's s to s_seg.
    Float c2, s2;
    polarization_detail::frame_turn(wo_world, frame.to_world(stokes_s_axis(wo)), s_seg, c2, s2);
    beta.rotate_incident(c2, s2);
  }
  void leave(const Frame& frame, const Vec3& wi) { s_seg = frame.to_world(stokes_s_axis(wi)); }
  static Float magnitude(const C& beta) { return beta.m00().max_component(); }
  // Column 0 of beta · x: the Stokes vector of unpolarized light through x, then beta.
  static void add(Radiance& L, const C& beta, const C& x) {
    for (int r = 0; r < 4; ++r) {
      U v = beta(r, 0) * x(0, 0);
      for (int k = 1; k < 4; ++k) v += beta(r, k) * x(k, 0);
      L[size_t(r)] += v;
    }
  }
  static void add(Radiance& L, const C& beta, const U& Le, Float w) {
    for (int r = 0; r < 4; ++r) L[size_t(r)] += beta(r, 0) * Le * w;
  }
  static bool finite(const Radiance& L) {
    return std::all_of(L.begin(), L.end(), [](const U& v) { return v.is_finite(); });
  }
};

// Half the diagonal of the box holding every shape and point light: the environment's
// power estimate (light_sampler.h) needs the scene's size.
Float scene_radius(const Scene& scene) {
  constexpr Float inf = std::numeric_limits<Float>::infinity();
  Vec3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  auto add = [&](const Vec3& p, Float r) {
    lo = {std::min(lo.x, p.x - r), std::min(lo.y, p.y - r), std::min(lo.z, p.z - r)};
    hi = {std::max(hi.x, p.x + r), std::max(hi.y, p.y + r), std::max(hi.z, p.z + r)};
  };
  for (const Sphere& s : scene.spheres) add(s.center, s.radius);
  for (const Mesh& m : scene.meshes)
    for (const Vec3& p : m.positions) add(p, 0);
  for (const PointLight& l : scene.point_lights)
    if (!l.directional) add(l.position, 0);
  if (!(hi.x >= lo.x)) return 1;
  const Float r = length(hi - lo) / 2;
  return std::isfinite(r) && r > 0 ? r : Float(1);
}

// The radiance an emitting `openpbr` surface sends towards w, n its geometric normal (the
// emitting side; both sides when thin-walled). Black for every other material.
// A textured material's at the hit's texture coordinates uv.
Color surface_emission(const Material& m, const Vec3& n, const Vec3& w, const Vec2& uv = {}) {
  if (!m.emits) return Color(0);
  Float mu = dot(n, w);
  if (m.emits_both_sides) mu = std::abs(mu);
  if (!(mu > 0)) return Color(0);
  std::optional<BxDF> scratch;
  const BxDF& at = m.at(uv, scratch);
  if (const auto* g = std::get_if<GltfPbrBxDF>(&at.models())) return g->emission();
  const auto* model = std::get_if<OpenPbrBxDF>(&at.models());
  return model ? model->emission(mu) : Color(0);
}

}  // namespace

PathTracer::PathTracer(const Scene& scene, const Accel& accel)
    : scene_(scene),
      accel_(accel),
      light_sampler_(scene.area_lights, scene.environment.is_black() ? nullptr : &scene.environment, scene_radius(scene),
                     scene.settings.light_sampler) {
  // The media are RGB (σs, σa per channel); carrying them at a path's wavelengths is not
  // done yet, and rendering them grey or wrong would not say so.
  if (scene.settings.spectral)
    for (const Material& m : scene.materials)
      if (m.subsurface && !m.subsurface_bsdf_fallback)
        throw InputError("spectral rendering: material" + (m.name.empty() ? std::string() : " \"" + m.name + "\"") +
                         " has a scattering medium (a subsurface material, or an openpbr one with transmission_depth and "
                         "transmission_scatter), which renders in RGB only (its medium is not carried per "
                         "wavelength yet); render without --spectral and \"spectral\": true");
  walk_dwivedi_.resize(scene.materials.size());
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    if (!scene.materials[i].subsurface) continue;
    const Medium& medium = scene.materials[i].subsurface->medium;
    const Color sigma_t = medium.sigma_t();
    for (size_t c = 0; c < 3; ++c) {
      const double albedo = sigma_t[int(c)] > 0 ? double(medium.sigma_s[int(c)]) / double(sigma_t[int(c)]) : 0.0;
      walk_dwivedi_[i][c] = dwivedi_kappa(albedo);
      walk_dwivedi_[i][c + 3] = dwivedi_pdf_mu(0, walk_dwivedi_[i][c]);
    }
  }
  make_walk_grid();
  if (scene.settings.polarized) {
    for (const Material& m : scene.materials)
      if (m.subsurface && !m.subsurface_bsdf_fallback)
        throw InputError("polarized rendering: material" + (m.name.empty() ? std::string() : " \"" + m.name + "\"") +
                         " has a scattering medium (a subsurface material, or an openpbr one with transmission_depth and "
                         "transmission_scatter), which is not carried with Stokes vectors yet; render "
                         "without --polarized and \"polarized\": true");
    polarized_models_.reserve(scene.materials.size());
    for (const Material& m : scene.materials)
      polarized_models_.push_back(m.textures.empty() ? std::optional<PolarizedBxDF>(PolarizedBxDF(m.bxdf)) : std::nullopt);
    if (scene.camera.polarizer_deg) {
      polarizer_rgb_ = broadcast<Color>(mueller_linear_polarizer(*scene.camera.polarizer_deg * kPi / 180));
      polarizer_spectral_ = broadcast<SampledSpectrum>(mueller_linear_polarizer(*scene.camera.polarizer_deg * kPi / 180));
    }
  }
}

bool PathTracer::occluded(const Vec3& p, const Vec3& ng, const Vec3& dir, Float dist, PathStats& stats) const {
  ++stats.rays;
  const Vec3 o = offset_ray_origin(p, ng, dir);
  if (std::isinf(dist)) return accel_.occluded(o, dir, dist);
  // Aim from the offset origin at the light point itself, and stop just short of it, so
  // that the light's own surface does not count as a blocker.
  const Vec3 d = p + dir * dist - o;
  const Float len = length(d);
  return accel_.occluded(o, d / len, len * Float(0.9999));
}

// ---- Next-event estimation from inside a medium (issue 38) ----
//
// A walk under a smooth boundary finds light only when its last direction, refracted
// out, happens to hit an emitter: the exit vertex is a delta refraction, where no light
// can be sampled. From each scattering event x of the walk a second strategy proposes
// the direction d towards a light, in the spirit of Koerner, Novák, Kutz, Habel & Jarosz
// 2016 ("Subdivision next-event estimation for path-traced subsurface scattering",
// EGSR), who connect a walk's vertices to the lights through the boundary: a plane
// (walk_nee_plane: the tangent plane at x's nearest surface point) stands in for the
// boundary near x; a light point is sampled as seen from y0, x's projection on that plane,
// giving ω outside; d is the direction inside that Snell's law (through the plane)
// refracts into ω. Along d the true boundary is then found (y, its normal), the true
// Fresnel transmission and refraction are taken there, and a ray from y finds what emits
// along the refracted direction. The plane only shapes the proposal: its density over d
// is exact,
//   p_nee(d) = p_light(y0 → ω(d)) · |dω/dd|,  |dω/dd| = η² cos θ_d / cos θ_ω
// (the solid-angle form of Snell's law, n_in² cos θ_in dω_in = n_out² cos θ_out dω_out;
// Veach 1997, §5.2), with p_light the mixture over every light the sampler could have
// chosen whose solid angle from y0 contains ω. The walk's own exit along d (a segment
// that reached the boundary: direction density p_dir(d), survival e^{−σt s}) is the other
// strategy; the two share every path x → y → emitter and are combined by the balance
// heuristic (Veach 1997, eq. 9.10),
//   w_nee = q_rr p_nee / (q_rr p_nee + p_walk),  w_walk = p_walk / (q_rr p_nee + p_walk),
// where q_rr is the probability with which x estimates at all (Russian roulette on the
// transmittance to the plane) and p_walk = p_dir(d) · e^{−σt s} with p_dir and σt taken
// channel-independently (the phase/Dwivedi mixture with the channels' Dwivedi densities
// averaged, the transmittance averaged over channels): any pair of weights that sums to 1
// for every path keeps the sum unbiased, and a weight that does not depend on the walk's
// sampled channel keeps the walk's path-level channel MIS (guided_walk.h) intact. The
// walk's weight applies to the emission its exit finds directly (an area light or the
// environment), nothing else of the continued path.
//
// Estimating at each of hundreds of deep events would cost rays for nothing (the
// transmittance to the boundary is e^{−σt h}): x estimates with probability
// q_rr = max(e^{−σt,min h}, kWalkNeeFloor), h its depth below the entry plane, and the
// estimate is divided by it. The floor keeps q_rr > 0 where the plane is a poor guide to
// the true boundary (a walk that wandered round a corner), so nothing is left out.
inline constexpr Float kWalkNeeFloor = 1.0f / 32;
// How far (in the medium's longest mean free path) an event looks for its nearest surface:
// deeper events estimate rarely and little (the transmittance e^{−σt s} to the boundary),
// and a smaller reach makes the query cheaper.
inline constexpr int kWalkNeePlaneReach = 4;
// Events this near the entry point (in the same unit) take the entry point's tangent plane
// without a query: on a surface of curvature radius ρ it stands within r²/(2ρ) of the
// surface, a tenth of a mean free path on marble's bunny (r = 2 mean free paths ≈ 0.9 mm,
// ρ ≈ 1 cm).
inline constexpr int kWalkNeeEntryRadius = 2;

struct WalkNeeState {
  int material = -1;
  Vec3 p0, n;       // the entry point and its outward normal (the walk's guide; the fallback plane)
  Float eta = 1;    // n_inside / n_outside of the smooth boundary
  Color sigma_t;
  Float sigma_min = 0;
  Float g = 0, q = 0;
  double kappa[3] = {}, dnorm[3] = {};
};

// The plane through which an event's estimate is proposed: y0, x's projection on it, and
// its normal n, pointing out of the medium.
struct WalkNeePlane {
  Vec3 y0, n;
};

namespace {

// Where the ray o + t·dir (t > 0) meets an area light's surface: the point and the
// light's normal there. (Any crossing: the density of sample_area_light along dir does
// not depend on which.)
bool walk_ray_hits_light(const AreaLight& light, const Vec3& o, const Vec3& dir, Vec3& on, Vec3& n_light) {
  if (const auto* q = std::get_if<QuadLight>(&light)) {
    const Vec3 nq = cross(q->edge1, q->edge2);
    const Float nn = length_squared(nq), dn = dot(dir, nq);
    if (!(nn > 0) || dn == 0) return false;
    const Float t = dot(q->corner - o, nq) / dn;
    if (!(t > 0)) return false;
    on = o + dir * t;
    const Vec3 r = on - q->corner;
    const Float a = dot(cross(r, q->edge2), nq) / nn, b = dot(cross(q->edge1, r), nq) / nn;
    if (!(a >= 0 && a <= 1 && b >= 0 && b <= 1)) return false;
    n_light = nq / std::sqrt(nn);
    return true;
  }
  const auto& sp = std::get<SphereLight>(light);
  const Vec3 oc = o - sp.center;
  const Float b = dot(oc, dir), c = length_squared(oc) - sp.radius * sp.radius;
  const Float disc = b * b - c;
  if (!(disc >= 0)) return false;
  const Float t = -b - std::sqrt(disc);
  if (!(t > 0)) return false;
  on = o + dir * t;
  n_light = normalize(on - sp.center);
  return true;
}

// The exit vertex as the path tracer shades it (trace(): the frame of the shading normal
// where it agrees with the geometric one about wo's side, the smooth dielectric's
// refraction from inside): the refracted direction and the weight (1 − F) η² of the
// transmission sample (dielectric.h: the transmission lobe's share over its probability
// is (n_wo / n_wi)², times its probability 1 − F). False where no light leaves that way.
bool walk_exit_refraction(const SurfaceHit& y, const Vec3& d, Float eta, Vec3& wi_world, Float& weight) {
  const Vec3 wo_world = -d;
  const bool consistent = dot(wo_world, y.ns) * dot(wo_world, y.ng) > 0;
  const Frame frame = Frame::from_normal_tangent(consistent ? y.ns : y.ng, y.tangent);
  const Vec3 wo = normalize(frame.to_local(wo_world));
  if (!(wo.z < 0)) return false;
  const Float cos_o = -wo.z;
  const Float r = fresnel_dielectric_oriented(cos_o, cos_o * cos_o, 1 / eta, eta);
  if (!(r < 1)) return false;
  const Vec3 wi = DielectricBxDF::scattered(wo, eta, false);
  wi_world = normalize(frame.to_world(wi));
  if (!sides_agree(wo_world, wi_world, y.ng, wo, wi)) return false;
  weight = (1 - r) * transmission_scale(1 / eta, TransportMode::Radiance);
  return true;
}

// p_walk of the header comment: the walk's direction density for d after arriving at an
// event along d_in (phase and Dwivedi techniques mixed with the guide's q, the Dwivedi
// density averaged over channels) times the survival to the boundary at s averaged over
// channels.
double walk_exit_pdf(const WalkNeeState& w, const Vec3& d_in, const Vec3& d, Float s) {
  const double phase = hg_sampled_pdf(dot(d_in, d), w.g);
  const double mu = std::clamp(double(dot(d, w.n)), -1.0, 1.0);
  double dw = 0, tr = 0;
  for (int k = 0; k < 3; ++k) {
    dw += w.dnorm[k] / (1 - w.kappa[k] * mu) * double(kInv2Pi);
    tr += std::exp(-double(w.sigma_t[k]) * double(s));
  }
  return ((1 - double(w.q)) * phase + double(w.q) * dw / 3) * (tr / 3);
}

// q_rr of the header comment.
Float walk_nee_probability(const WalkNeeState& w, const Vec3& x) {
  const Float h = std::max(Float(0), dot(w.p0 - x, w.n));
  return std::max(kWalkNeeFloor, std::exp(-w.sigma_min * h));
}

}  // namespace

// The plane of the event x's proposal: the tangent plane at x's nearest surface point q,
// its normal the direction from x to q (for x inside a closed surface, x − q lies along
// the surface's normal at q wherever it is smooth, and it points out of the medium). A walk
// that has wandered to another side of the shape is guided by the surface it is near,
// not by the one it entered through. The entry point's tangent plane near the entry point,
// where no surface is within reach (x deep inside: its estimates are rare), or where x
// lies on the surface.
WalkNeePlane PathTracer::walk_nee_plane(const WalkNeeState& w, const Vec3& x) const {
  const Float reach = Float(kWalkNeePlaneReach) / w.sigma_min;
  const Float near_entry = Float(kWalkNeeEntryRadius) / w.sigma_min;
  if (length_squared(x - w.p0) < near_entry * near_entry) return {x + w.n * dot(w.p0 - x, w.n), w.n};
  Vec3 q;
  const Float dist = accel_.closest_point(x, reach, q);
  if (dist < reach && dist > 0) {
    const Vec3 n = (q - x) / dist;
    if (is_finite(n)) return {q, n};
  }
  return {x + w.n * dot(w.p0 - x, w.n), w.n};
}

bool PathTracer::walk_nee_setup(const Material& material, const SurfaceHit& entry, WalkNeeState& w) const {
  if (!material.subsurface || !material.subsurface->nee || material.inside || light_sampler_.count() == 0) return false;
  const Subsurface& ss = *material.subsurface;
  const auto* boundary = std::get_if<DielectricBxDF>(&ss.boundary.models());
  if (!boundary || boundary->film.active()) return false;
  w.material = entry.material;
  w.p0 = entry.p;
  w.n = normalize(entry.ng);
  w.eta = boundary->eta;
  w.sigma_t = ss.medium.sigma_t();
  w.sigma_min = w.sigma_t.min_component();
  w.g = ss.medium.g;
  w.q = std::clamp(ss.guide, Float(0), Float(1));
  const auto& k = walk_dwivedi_[static_cast<size_t>(entry.material)];
  for (int c = 0; c < 3; ++c) w.kappa[c] = k[size_t(c)], w.dnorm[c] = k[size_t(c) + 3];
  return true;
}

// p_nee(d) for an event whose plane is `plane` (without q_rr): 0 where the plane proposal
// cannot give d.
Float PathTracer::walk_nee_density(const WalkNeeState& w, const WalkNeePlane& plane, const Vec3& d) const {
  Vec3 omega;
  Float jacobian;
  if (!walk_plane_out(d, plane.n, w.eta, omega, jacobian)) return 0;
  const Vec3& y0 = plane.y0;
  double p = 0;
  for (size_t i = 0; i < scene_.area_lights.size(); ++i) {
    Vec3 on, n_light;
    if (!walk_ray_hits_light(scene_.area_lights[i], y0, omega, on, n_light)) continue;
    const Float pmf = light_sampler_.pmf(y0, plane.n, int(i));
    if (pmf > 0) p += double(pmf) * double(area_light_pdf(scene_.area_lights[i], y0, on, n_light));
  }
  if (!scene_.environment.is_black())
    p += double(light_sampler_.pmf(y0, plane.n, light_sampler_.environment_index())) * double(scene_.environment.pdf(omega));
  return Float(p * double(jacobian));
}

// The weight w_walk of the emission found by the walk's exit through its own material's
// boundary: x and d_in the last event and the direction it was reached in, d and s the
// direction and length of the segment that reached the boundary.
Float PathTracer::walk_exit_weight(const WalkNeeState& w, const Vec3& x, const Vec3& d_in, const Vec3& d, Float s) const {
  const double p_nee = double(walk_nee_probability(w, x)) * double(walk_nee_density(w, walk_nee_plane(w, x), d));
  const double p_walk = walk_exit_pdf(w, d_in, d, s);
  return p_nee + p_walk > 0 ? Float(p_walk / (p_nee + p_walk)) : Float(1);
}

// One estimate from the event x (reached along d_in) of the light leaving through the
// boundary towards an emitter, per unit path weight (the caller multiplies by the walk's
// weight at x): phase(d) e^{−σt s} (1 − F) η² Le / (q_rr p_nee + p_walk) when x estimates
// (probability q_rr), 0 otherwise.
Color PathTracer::walk_nee(const WalkNeeState& w, const Vec3& x, const Vec3& d_in, Pcg32& rng, PathStats& stats) const {
  const Float q_rr = walk_nee_probability(w, x);
  if (rng.next_float() >= q_rr) return Color(0);
  const Float u_pick = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
  const WalkNeePlane plane = walk_nee_plane(w, x);
  const LightSampler::Choice choice = light_sampler_.sample(plane.y0, plane.n, u_pick);
  if (choice.light < 0) return Color(0);
  const bool env = choice.light == light_sampler_.environment_index();
  const LightSample ls = env ? scene_.environment.sample(u1, u2)
                             : sample_area_light(scene_.area_lights[static_cast<size_t>(choice.light)], plane.y0, u1, u2);
  Vec3 d;
  if (!(ls.pdf > 0) || !walk_plane_in(ls.wi, plane.n, w.eta, d)) return Color(0);
  const Float p_nee = walk_nee_density(w, plane, d);
  if (!(p_nee > 0)) return Color(0);

  // The true boundary along d, and the light leaving it.
  const SceneBoundary boundary(accel_, stats.rays);
  SceneBoundary::Hit yh;
  if (!boundary.nearest(x, d, yh) || yh.surface.material != w.material) return Color(0);
  Vec3 wi;
  Float transmission;
  if (!walk_exit_refraction(yh.surface, d, w.eta, wi, transmission)) return Color(0);
  ++stats.rays;
  SurfaceHit e;
  Color le(0);
  if (!accel_.intersect(Ray{offset_ray_origin(yh.surface.p, yh.surface.ng, wi), wi}, e)) {
    if (!scene_.environment.is_black()) le = scene_.environment.radiance(wi);
  } else if (e.area_light >= 0) {
    // As trace() takes an emitter's radiance where a path hits it.
    const AreaLight& light = scene_.area_lights[static_cast<size_t>(e.area_light)];
    const auto* quad = std::get_if<QuadLight>(&light);
    const Vec3 nl = quad ? quad->normal() : e.ng;
    const Material& surface = scene_.materials[static_cast<size_t>(e.material)];
    le = surface.emits ? surface_emission(surface, nl, -wi, e.uv) : area_light_radiance(light, nl, -wi);
  }
  if (le.is_black()) return Color(0);
  const double denom = double(q_rr) * double(p_nee) + walk_exit_pdf(w, d_in, d, yh.t);
  const double phase = hg_sampled_pdf(dot(d_in, d), w.g);
  Color tr = map(w.sigma_t, [&](Float st) { return std::exp(-st * yh.t); });
  const Color c = tr * le * Float(phase * double(transmission) / denom);
  return c.is_finite() ? c : Color(0);
}

template <typename Shading, typename Model>
typename Shading::C PathTracer::direct_light(const SurfaceHit& hit, const Frame& frame, const Model& bxdf, const Vec3& wo,
                                             const Vec3& wo_world, int depth, Float u_pick, PixelSampler& sampler,
                                             PathStats& stats, Shading& shading) const {
  using C = typename Shading::C;
  C sum(0);
  // Eq. 2: every point light contributes f · I / r² · |cos θi|.
  // A spot light's intensity is scaled by its falloff; a directional light's irradiance
  // E replaces I / r² (KHR_lights_punctual, SPEC §3).
  for (const PointLight& light : scene_.point_lights) {
    Vec3 wi_world;
    Float dist, scale;
    if (light.directional) {
      wi_world = -light.direction;
      dist = std::numeric_limits<Float>::infinity();
      scale = 1;
    } else {
      const Vec3 d = light.position - hit.p;
      const Float dist2 = length_squared(d);
      if (!(dist2 > 0)) continue;
      dist = std::sqrt(dist2);
      wi_world = d / dist;
      scale = spot_factor(light, -wi_world) / dist2;
      if (!(scale > 0)) continue;
    }
    const Vec3 wi = normalize(frame.to_local(wi_world));
    if (!sides_agree(wo_world, wi_world, hit.ng, wo, wi)) continue;
    const C f = bxdf.f(wo, wi);
    if (f.is_black() || occluded(hit.p, hit.ng, wi_world, dist, stats)) continue;
    sum += f * shading.point(light) * (std::abs(wi.z) * scale);
  }
  // Eq. 1 by sampling one of the other lights, chosen by the light sampler with the
  // probability choice.pmf, which divides out below.
  if (light_sampler_.count() == 0) return sum;
  const LightSampler::Choice choice = light_sampler_.sample(hit.p, frame.n, u_pick);
  if (choice.light < 0) return sum;
  const int pick = choice.light;
  const auto [u1, u2] = sampler.get2d(dims::bounce(depth) + dims::kLightPosition);
  const bool env = pick == light_sampler_.environment_index();
  LightSample ls = env ? scene_.environment.sample(u1, u2)
                       : sample_area_light(scene_.area_lights[static_cast<size_t>(pick)], hit.p, u1, u2);
  // An emitting surface (an openpbr sphere or quad): what leaves it towards hit.p. A point
  // on it sees none of its own (convex) surface.
  // (A scene built in code may leave area_light_material empty: plain lights.)
  const int emitter = env || size_t(pick) >= scene_.area_light_material.size()
                          ? -1
                          : scene_.area_light_material[static_cast<size_t>(pick)];
  if (emitter >= 0) {
    if (pick == hit.area_light || !(ls.pdf > 0)) return sum;
    const AreaLight& light = scene_.area_lights[static_cast<size_t>(pick)];
    const auto* quad = std::get_if<QuadLight>(&light);
    const Vec3 n = quad ? quad->normal() : normalize(hit.p + ls.wi * ls.distance - std::get<SphereLight>(light).center);
    ls.radiance = surface_emission(scene_.materials[static_cast<size_t>(emitter)], n, -ls.wi);
  }
  if (!(ls.pdf > 0) || ls.radiance.is_black()) return sum;
  const Vec3 wi = normalize(frame.to_local(ls.wi));
  if (!sides_agree(wo_world, ls.wi, hit.ng, wo, wi)) return sum;
  const auto e = bxdf.eval(wo, wi);
  if (e.f.is_black() || occluded(hit.p, hit.ng, ls.wi, ls.distance, stats)) return sum;
  const Float light_pdf = choice.pmf * ls.pdf;
  const Float w = power_heuristic(light_pdf, e.pdf);
  const auto Le = env            ? shading.environment(scene_.environment, ls.wi, ls.radiance)
                  : emitter >= 0 ? shading.surface(ls.radiance)
                                 : shading.area(scene_.area_lights[static_cast<size_t>(pick)], ls.radiance);
  sum += e.f * Le * (std::abs(wi.z) * w / light_pdf);
  return sum;
}

Color PathTracer::radiance(Ray ray, PixelSampler& sampler, PathStats& stats) const {
  thread_local std::optional<BxDF> textured;
  RgbShading shading;
  shading.textured = &textured;
  const Color L = trace(ray, sampler, stats, shading);
  textured.reset();  // not to keep a material's model (and its tables) alive past the render
  return L;
}

SampledSpectrum PathTracer::radiance(Ray ray, SampledWavelengths& w, PixelSampler& sampler, PathStats& stats,
                                     SpectralScratch& scratch) const {
  thread_local SpectralSlots slots;
  SpectralShading shading{{}, w, scratch, &slots.textured, &slots.model};
  const SampledSpectrum L = trace(ray, sampler, stats, shading);
  slots.textured.reset();  // as in the RGB radiance()
  return L;
}

std::array<Color, 4> PathTracer::stokes(Ray ray, PixelSampler& sampler, PathStats& stats) const {
  PolarizedShading<RgbShading> shading{{}, scene_.camera.image_x(), scene_.camera.polarizer_deg ? &polarizer_rgb_ : nullptr,
                                       &polarized_models_, {}, {}, scene_.materials.data()};
  shading.base.walks = false;  // media are not carried with Stokes vectors: BSDF forms
  thread_local std::optional<BxDF> textured;
  shading.base.textured = &textured;
  const auto S = trace(ray, sampler, stats, shading);
  textured.reset();  // as in radiance()
  return S;
}

std::array<SampledSpectrum, 4> PathTracer::stokes(Ray ray, SampledWavelengths& w, PixelSampler& sampler, PathStats& stats,
                                                  SpectralScratch& scratch) const {
  thread_local SpectralSlots slots;
  PolarizedShading<SpectralShading> shading{{{}, w, scratch, &slots.textured, &slots.model},
                                            scene_.camera.image_x(),
                                            scene_.camera.polarizer_deg ? &polarizer_spectral_ : nullptr,
                                            nullptr,
                                            {},
                                            {},
                                            scene_.materials.data()};
  const auto S = trace(ray, sampler, stats, shading);
  slots.textured.reset();  // as in the RGB radiance()
  return S;
}

// The distance bound of the random walks' steps (walk_distance_grid.h): over the box of the
// shapes whose material walks, in voxels of four of the longest mean free path among them
// (a step is an exponential flight of that scale: a voxel much larger would leave its
// outer steps near the surface a bound too small, a smaller one costs more queries).
void PathTracer::make_walk_grid() {
  const auto walks = [&](int material) {
    if (material < 0 || size_t(material) >= scene_.materials.size()) return false;
    const Material& m = scene_.materials[size_t(material)];
    return m.subsurface && !m.subsurface_bsdf_fallback && m.subsurface->method == SubsurfaceMethod::RandomWalk;
  };
  Vec3 lo{std::numeric_limits<Float>::max(), std::numeric_limits<Float>::max(), std::numeric_limits<Float>::max()};
  Vec3 hi = -lo;
  Float mfp = 0;
  const auto add = [&](const Vec3& a, const Vec3& b, int material) {
    lo = {std::min(lo.x, a.x), std::min(lo.y, a.y), std::min(lo.z, a.z)};
    hi = {std::max(hi.x, b.x), std::max(hi.y, b.y), std::max(hi.z, b.z)};
    const Color sigma_t = scene_.materials[size_t(material)].subsurface->medium.sigma_t();
    const Float smallest = std::min({sigma_t[0], sigma_t[1], sigma_t[2]});
    if (smallest > 0) mfp = std::max(mfp, 1 / smallest);
  };
  for (const Mesh& m : scene_.meshes)
    if (walks(m.material))
      for (const Vec3& p : m.positions) add(p, p, m.material);
  for (const Sphere& s : scene_.spheres)
    if (walks(s.material)) add(s.center - Vec3{s.radius, s.radius, s.radius}, s.center + Vec3{s.radius, s.radius, s.radius}, s.material);
  if (!(mfp > 0) || !(hi.x >= lo.x)) return;
  walk_grid_ = std::make_unique<WalkDistanceGrid>(accel_, lo, hi, 4 * mfp);
}

template <typename Shading>
typename Shading::Radiance PathTracer::trace(Ray ray, PixelSampler& sampler, PathStats& stats, Shading& shading) const {
  using C = typename Shading::C;
  using Radiance = typename Shading::Radiance;
  Radiance L{};
  C beta = shading.start(ray);
  bool specular = true;  // the previous vertex was a delta lobe (or is the camera)
  Float prev_pdf = 0;    // solid-angle density of the BSDF sample that made `ray`
  Vec3 prev_p = ray.o;
  Vec3 prev_n{0, 0, 0};  // the normal light selection used at prev_p (LightSampler::pmf)
  Float eta_scale = 1;   // undoes the (n_wo/n_wi)² of refraction for Russian roulette
  const int max_depth = scene_.settings.max_depth;
  // The boundary point a random walk reached: the next vertex, found without a ray.
  SceneBoundary::Hit walked;
  bool have_walked = false;
  // Next-event estimation from the walk (walk_nee): the walk's setup and last event, for
  // the MIS weight of the emission its exit finds (`emit_weight`, for the next hit only;
  // taken only where that hit emits, as it needs a closest-point query).
  WalkNeeState walk_nee_state;
  WalkLastEvent walk_last;
  bool walk_nee_pending = false;
  bool exit_mis_next = false;
  // The absorbing interior (an openpbr material's, Material::absorption) the current ray
  // travels through, or null.
  const Material* absorber = nullptr;
  for (int depth = 0;; ++depth) {
    SurfaceHit hit;
    Vec3 wo_world;
    const bool exit_mis = exit_mis_next;
    exit_mis_next = false;
    auto emit_weight = [&] {
      return exit_mis ? walk_exit_weight(walk_nee_state, walk_last.point, walk_last.d_in, walked.d, walked.t) : Float(1);
    };
    if (have_walked) {
      // Inside the medium there is nothing to collect: light enters only through the
      // boundary, whose vertex this is.
      have_walked = false;
      hit = walked.surface;
      wo_world = -walked.d;
    } else {
      ++stats.rays;
      const bool found = accel_.intersect(ray, hit);
      if (absorber) {
        // Beer–Lambert over the segment; a ray leaving an open absorbing shape meets no end
        // of it (an infinite path length).
        if (!found) break;
        shading.attenuate(beta, shading.absorption(*absorber), hit.t);
        absorber = nullptr;
      }
      if (!found) {
        if (!scene_.environment.is_black()) {
          const Color rgb = scene_.environment.radiance(ray.d);
          const Float w = specular ? 1 : power_heuristic(prev_pdf, light_sampler_.pmf(prev_p, prev_n, light_sampler_.environment_index()) *
                                                                            scene_.environment.pdf(ray.d));
          if (!rgb.is_black()) shading.add(L, beta, shading.environment(scene_.environment, ray.d, rgb), w * emit_weight());
        }
        break;
      }
      const Material& surface = scene_.materials[static_cast<size_t>(hit.material)];
      if (hit.area_light >= 0) {
        // A light of the scene's "lights" (a black body apart from its emission: the path
        // ends here) or an emitting openpbr surface, which also reflects.
        const AreaLight& light = scene_.area_lights[static_cast<size_t>(hit.area_light)];
        const auto* quad = std::get_if<QuadLight>(&light);
        const Vec3 n = quad ? quad->normal() : hit.ng;
        const bool own = surface.emits;
        const Color rgb = own ? surface_emission(surface, n, -ray.d, hit.uv) : area_light_radiance(light, n, -ray.d);
        if (!rgb.is_black()) {
          const Float w = specular ? 1 : power_heuristic(prev_pdf, light_sampler_.pmf(prev_p, prev_n, hit.area_light) *
                                                                            area_light_pdf(light, prev_p, hit.p, n));
          shading.add(L, beta, own ? shading.surface(rgb) : shading.area(light, rgb), w * emit_weight());
        }
        if (surface.black_body) break;
      } else if (surface.emits) {
        // An emitting mesh: no light samples it, so what a path finds counts in full.
        const Color rgb = surface_emission(surface, hit.ng, -ray.d, hit.uv);
        if (!rgb.is_black()) shading.add(L, beta, shading.surface(rgb), 1);
      }
      wo_world = -ray.d;
    }
    if (depth >= max_depth) break;

    const Material& material = scene_.materials[static_cast<size_t>(hit.material)];
    const auto& bxdf = shading.bxdf(material, hit.uv, dot(wo_world, hit.ng) < 0);
    // Where the shading and geometric normals disagree about the side of wo, shading
    // with the interpolated normal would give black or leak: fall back to the geometric.
    const bool consistent = dot(wo_world, hit.ns) * dot(wo_world, hit.ng) > 0;
    const Frame frame = Frame::from_normal_tangent(consistent ? hit.ns : hit.ng, hit.tangent);
    const Vec3 wo = normalize(frame.to_local(wo_world));
    shading.at_vertex(beta, frame, wo, wo_world);

    const auto [u_pick, u_lobe] = sampler.get2d(dims::bounce(depth) + dims::kChoiceAndLobe);
    if (!is_delta_only(bxdf.flags())) shading.add(L, beta, direct_light(hit, frame, bxdf, wo, wo_world, depth, u_pick, sampler, stats, shading));

    const auto [u1, u2] = sampler.get2d(dims::bounce(depth) + dims::kDirection);
    const auto s = bxdf.sample(wo, u_lobe, u1, u2);
    if (!s) break;
    Vec3 wi_world = normalize(frame.to_world(s->wi));
    if (!sides_agree(wo_world, wi_world, hit.ng, wo, s->wi)) break;
    // The exit of a walk that estimated its light: what the refracted ray finds emitting
    // shares the weight with those estimates.
    if (walk_nee_pending) {
      walk_nee_pending = false;
      exit_mis_next = s->delta && s->lobe == Lobe::Transmission && hit.material == walk_nee_state.material;
    }
    beta *= s->weight;
    if (!(shading.magnitude(beta) > 0)) break;
    shading.leave(frame, s->wi);
    specular = s->delta;
    prev_pdf = s->pdf;
    prev_p = hit.p;
    prev_n = frame.n;
    if (s->lobe == Lobe::Transmission) eta_scale *= s->eta * s->eta;

    // Russian roulette (Arvo & Kirk 1990): continue with probability ~ the throughput.
    if (depth + 1 >= scene_.settings.rr_depth) {
      const Float q = std::min(Float(0.95), shading.magnitude(beta) * eta_scale);
      if (sampler.get1d(dims::bounce(depth) + dims::kRoulette) >= q) break;
      beta /= q;
    }

    // Into the medium of a subsurface material: the geometric normal points out of the
    // shape (spheres; meshes wound or turned so at load), so wi is inside when it is on
    // the normal's back side — after a refraction from outside or a reflection inside.
    if (material.subsurface && std::is_same_v<C, Color> && dot(wi_world, hit.ng) < 0) {
      if constexpr (std::is_same_v<C, Color>) {
        if (material.subsurface->method == SubsurfaceMethod::RandomWalk) {
          // Start just inside the surface, so that the walk's first query does not find
          // the surface it starts on.
          const Vec3 start = offset_ray_origin(hit.p, hit.ng, wi_world);
          const SceneBoundary boundary(accel_, stats.rays, walk_grid_.get());
          WalkStats ws;
          ++stats.walks;
          // guided_walk.h: the channel chosen once per walk and weighted over the whole
          // path (spectral MIS), the classic walk mixed with Dwivedi sampling towards
          // the entry point's surface with probability `guide` per event.
          // Next-event estimation from the walk's events (walk_nee) where the exit vertex
          // it stands for is within max_depth (its emitter at depth + 2).
          const bool nee = depth + 1 < max_depth && walk_nee_setup(material, hit, walk_nee_state);
          const WalkGuide guide{hit.ng, material.subsurface->guide, walk_dwivedi_[size_t(hit.material)].data()};
          bool reached;
          if (nee) {
            auto estimate = [&](const Vec3& x, const Vec3& d_in, const Color& b) {
              shading.add(L, b, walk_nee(walk_nee_state, x, d_in, sampler.rng(), stats));
            };
            reached = walk_to_boundary_guided(material.subsurface->medium, boundary, guide, start, wi_world, beta,
                                              sampler.rng(), walked, &ws, nullptr, kMaxWalkSteps, estimate, &walk_last);
          } else {
            reached = walk_to_boundary_guided(material.subsurface->medium, boundary, guide, start, wi_world, beta,
                                              sampler.rng(), walked, &ws);
          }
          walk_nee_pending = nee && walk_last.scattered;
          stats.walk_steps += ws.steps;
          if (!reached || !(beta.max_component() > 0)) break;
          have_walked = true;
          continue;
        }
        // Diffusion (pbrt-v3 §15.4.1 and §16.1, SubsurfaceMaterial): the boundary
        // sample's transmission carried the entry factor 1 − Fr(cos θo); the profile
        // gives the exit point and the weight Sp / pdf; the exit is then a vertex of its
        // own, shaded with the exit lobe Sw.
        if (depth + 1 >= max_depth) break;
        ++depth;
        const auto exit = sample_probe_exit(accel_, hit, frame, *material.profile, sampler.rng());
        if (!exit) break;
        ++stats.probe_exits;
        // The radiance of the entry's refraction was scaled by 1/η²; the light leaves
        // again through the boundary, which scales it back (pbrt-v3's
        // SeparableBSSRDFAdapter multiplies Sw by η² for the same reason).
        const Float eta2 = material.subsurface->eta * material.subsurface->eta;
        beta *= exit->weight * eta2;
        eta_scale /= eta2;
        if (!(beta.max_component() > 0)) break;
        const SurfaceHit& xo = exit->hit;
        const Frame exit_frame = Frame::from_normal_tangent(xo.ng, xo.tangent);
        const SwBxDF& sw = material.exit_lobe;
        const Vec3 sw_wo{0, 0, 1};  // Sw does not depend on wo
        const auto [v_pick, v_lobe] = sampler.get2d(dims::bounce(depth) + dims::kChoiceAndLobe);
        shading.add(L, beta, direct_light(xo, exit_frame, sw, sw_wo, xo.ng, depth, v_pick, sampler, stats, shading));
        const auto [v1, v2] = sampler.get2d(dims::bounce(depth) + dims::kDirection);
        const auto so = sw.sample(sw_wo, v_lobe, v1, v2);
        if (!so) break;
        wi_world = normalize(exit_frame.to_world(so->wi));
        beta *= so->weight;
        if (!(beta.max_component() > 0)) break;
        specular = false;
        prev_pdf = so->pdf;
        prev_p = xo.p;
        prev_n = exit_frame.n;
        ray = Ray{offset_ray_origin(xo.p, xo.ng, wi_world), wi_world};
        continue;
      } else {
        break;  // unreachable: the constructor rejects spectral and polarized subsurface scenes
      }
    }
    // Into an absorbing interior: the geometric normal points out of the shape (as for the
    // subsurface media above).
    if (material.absorption && dot(wi_world, hit.ng) < 0) absorber = &material;
    ray = Ray{offset_ray_origin(hit.p, hit.ng, wi_world), wi_world};
  }
  // A path with a NaN anywhere contributes nothing rather than poisoning the pixel.
  return shading.finite(L) ? L : Radiance{};
}

}  // namespace gonio::render
