// Subsurface scattering in the renderer (issue 14): the random walk as a path segment, the
// closed-mesh check, and the diffusion exit. Expected values are closed forms: a white
// furnace, Beer–Lambert through a slab between two Fresnel interfaces.

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "../unit/test_scale.h"
#include "gonio/error.h"
#include "gonio/material.h"
#include "gonio/render/accel.h"
#include "gonio/render/path_tracer.h"
#include "gonio/render/renderer.h"
#include "gonio/render/scene_loader.h"
#include "gonio/render/subsurface_walk.h"
#include "gonio/render/walk_nee_plane.h"
#include "render_test_util.h"
#include "scratch_dir.h"

namespace gonio::render {
namespace {

using gonio::test::ScratchDir;
using gonio::test::scaled;

// An axis-aligned box as an OBJ, wound counter-clockwise seen from outside (or, with
// `inward`, the other way); `drop` faces (of 6, two triangles each) are left out.
std::string box_obj(Vec3 lo, Vec3 hi, bool inward = false, int drop = 0) {
  std::string s;
  for (int i = 0; i < 8; ++i) {
    const Vec3 p{(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z};
    s += "v " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
  }
  // Quads as corner indices (1-based), outward by the right-hand rule.
  const int quads[6][4] = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5}, {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}};
  for (int f = drop; f < 6; ++f) {
    const int* q = quads[f];
    if (inward) s += "f " + std::to_string(q[3]) + " " + std::to_string(q[2]) + " " + std::to_string(q[1]) + " " + std::to_string(q[0]) + "\n";
    else s += "f " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " + std::to_string(q[3]) + "\n";
  }
  return s;
}

// Mean over an image's pixels of one channel, and the standard error of that mean from
// the pixels' own spread (pixels are independent estimates).
struct MeanErr {
  double mean = 0, err = 0;
};
MeanErr image_mean(const Image& img, int c) {
  double s = 0, s2 = 0;
  const int n = img.width() * img.height();
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      const double v = img.at(x, y)[c];
      s += v;
      s2 += v * v;
    }
  const double m = s / n;
  return {m, std::sqrt(std::max(0.0, s2 / n - m * m) / (n - 1))};
}

// A white furnace: a sphere that absorbs nothing, filling the image, inside a uniform
// environment of radiance 1. Every path that is not cut short returns 1: light is only
// moved around, never lost (the boundary's Fresnel split and the medium's scattering
// conserve energy), so the image is 1 within its noise.
std::string furnace_scene(const std::string& material, int spp) {
  return R"({"camera": {"position": [0, 0, 6], "look_at": [0, 0, 0], "fov": 8, "width": 8, "height": 8},
             "render": {"spp": )" + std::to_string(spp) + R"(, "max_depth": 1024},
             "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": )" + material + R"(}],
             "environment": {"radiance": 1}})";
}

void expect_furnace(const Scene& scene, const std::string& what) {
  const Image img = render(scene, {});
  for (int c = 0; c < 3; ++c) {
    const MeanErr m = image_mean(img, c);
    EXPECT_NEAR(m.mean, 1.0, 4 * m.err + 1e-3) << what << " channel " << c << " ± " << m.err;
  }
}

TEST(SubsurfaceRender, FurnaceRandomWalkSmoothBoundary) {
  const std::string material = R"({"type": "subsurface", "eta": 1.33, "sigma_s": [1, 3, 8], "sigma_a": 0, "g": 0.3})";
  expect_furnace(parse_scene(furnace_scene(material, static_cast<int>(scaled(64, 16))), "furnace.json", ""), material);
}

// A rough boundary: next-event estimation through it, from outside and from inside. The
// single-scattering microfacet dielectric loses the energy of its facets' interreflection
// (a rough glass sphere alone renders about 0.85 here at α = 0.3), so the material asks
// for the energy-conserving boundary of Kulla & Conty 2017 (`"multiscatter": true`): the
// loss is the boundary model's, not the walk's, and the furnace must give 1.
TEST(SubsurfaceRender, FurnaceRandomWalkRoughBoundary) {
  const std::string material =
      R"({"type": "subsurface", "eta": 1.5, "alpha": 0.3, "multiscatter": true, "sigma_s": [2, 2, 5], "sigma_a": 0})";
  Scene scene = parse_scene(furnace_scene(material, static_cast<int>(scaled(64, 16))), "furnace.json", "");
  ASSERT_TRUE(scene.materials[0].subsurface);
  expect_furnace(scene, material);
}

// A slab 1 unit thick that only absorbs (σs = 0), lit from below by a uniform area light
// and seen straight down at normal incidence. With the Fresnel reflectance at normal
// incidence R = ((η − 1)/(η + 1))² (Born & Wolf §1.5.3) and τ = σa d, the light that
// reaches the eye went through both interfaces and bounced 2k times inside between them:
//   T = (1 − R)² e^{−τ} Σ_k (R² e^{−2τ})^k = (1 − R)² e^{−τ} / (1 − R² e^{−2τ}).
// (The radiance factor η² of entering cancels that of leaving.)
TEST(SubsurfaceRender, AbsorbingSlabIsBeerLambertBetweenTwoFresnelInterfaces) {
  ScratchDir dir("gonio_subsurface");
  dir.file("slab.obj", box_obj({-100, 0, -100}, {100, 1, 100}));
  const double eta = 2.0, sigma_a[3] = {0.1, 0.3, 0.6};
  const std::string scene_path = dir.file("slab.json", R"({
    "shapes": [{"type": "mesh", "file": "slab.obj",
                "material": {"type": "subsurface", "eta": 2.0, "sigma_s": 0, "sigma_a": [0.1, 0.3, 0.6]}}],
    "lights": [{"type": "quad", "corner": [-300, -1, -300], "edge1": [0, 0, 600], "edge2": [600, 0, 0], "radiance": 1}],
    "render": {"max_depth": 64}})");
  const Scene scene = load_scene_file(scene_path);
  const Accel accel(scene);
  const PathTracer tracer(scene, accel);
  // Independent samples: the standard error below assumes them.
  PixelSampler sampler(SamplerType::Independent, 1, 7);
  PathStats stats;
  const std::uint64_t n = scaled(100000, 20000);
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  for (std::uint64_t i = 0; i < n; ++i) {
    sampler.start(0, 0, i);
    const Color L = tracer.radiance(Ray{{0.3f, 5, -0.2f}, {0, -1, 0}}, sampler, stats);
    for (int c = 0; c < 3; ++c) sum[c] += L[c], sum2[c] += double(L[c]) * L[c];
  }
  EXPECT_GT(stats.walks, 0u);
  const double R = std::pow((eta - 1) / (eta + 1), 2);
  for (int c = 0; c < 3; ++c) {
    const double a = std::exp(-sigma_a[c]);
    const double expected = (1 - R) * (1 - R) * a / (1 - R * R * a * a);
    const double mean = sum[c] / double(n);
    const double err = std::sqrt(std::max(0.0, sum2[c] / double(n) - mean * mean) / double(n - 1));
    EXPECT_NEAR(mean, expected, 4 * err + 1e-4) << "channel " << c << " ± " << err;
  }
}

// The diffusion method on a thick flat slab under a uniform white sky, seen straight down.
// The separable BSSRDF S = (1 − Fr(cos θo)) Sp(r) Sw(ωi) (pbrt-v3 eq. 11.6) with
// ∫ Sw cos θ dω = 1 (Sw's normalisation, pbrt-v3 eq. 11.7) gives, for light arriving
// from everywhere with radiance 1, L(θo) = Fr(θo) + (1 − Fr(θo)) ∫ Sp dA: the specular
// reflection plus what enters and leaves anywhere on the plane. ∫ Sp dA = 2π ∫ Sp r dr is
// the profile's own Rd, which the profile's tests check against its integral; here the
// renderer's part is checked — the entry's 1 − Fr and 1/η², the exit's η², the probe
// weight, Sw at the exit with next-event estimation and its sampled direction.
TEST(SubsurfaceRender, DiffusionOnAFlatSlabUnderAWhiteSky) {
  ScratchDir dir("gonio_subsurface");
  dir.file("slab.obj", box_obj({-60, -30, -60}, {60, 0, 60}));
  const Scene scene = load_scene_file(dir.file("slab.json", R"({
    "shapes": [{"type": "mesh", "file": "slab.obj",
                "material": {"type": "subsurface", "method": "diffusion", "eta": 1.33, "sigma_s": 10, "sigma_a": [0.2, 1, 4]}}],
    "environment": {"radiance": 1}})"));
  const Material& m = scene.materials[0];
  ASSERT_TRUE(m.profile);
  const Accel accel(scene);
  const PathTracer tracer(scene, accel);
  PixelSampler sampler(SamplerType::Independent, 1, 11);
  PathStats stats;
  const std::uint64_t n = scaled(40000, 8000);
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  for (std::uint64_t i = 0; i < n; ++i) {
    sampler.start(0, 0, i);
    const Color L = tracer.radiance(Ray{{0.3f, 5, -0.2f}, {0, -1, 0}}, sampler, stats);
    for (int c = 0; c < 3; ++c) sum[c] += L[c], sum2[c] += double(L[c]) * L[c];
  }
  EXPECT_GT(stats.probe_exits, 0u);
  const double eta = 1.33, F0 = std::pow((eta - 1) / (eta + 1), 2);  // Fresnel at normal incidence
  for (int c = 0; c < 3; ++c) {
    const double expected = F0 + (1 - F0) * m.profile->Rd()[c];
    const double mean = sum[c] / double(n);
    const double err = std::sqrt(std::max(0.0, sum2[c] / double(n) - mean * mean) / double(n - 1));
    EXPECT_NEAR(mean, expected, 4 * err + 1e-3) << "channel " << c << " ± " << err << ", Rd " << m.profile->Rd()[c];
  }
}

// The closed-mesh check: a walk in an open mesh leaves through the hole.
TEST(SubsurfaceRender, OpenMeshIsRejectedWithItsCountOfOpenEdges) {
  ScratchDir dir("gonio_subsurface");
  dir.file("open.obj", box_obj({0, 0, 0}, {1, 1, 1}, false, 1));  // one face missing: 4 open edges
  const std::string path = dir.file("open.json", R"({"shapes": [
    {"type": "sphere", "center": [0, 5, 0], "radius": 1, "material": {"type": "diffuse"}},
    {"type": "mesh", "file": "open.obj", "material": {"type": "subsurface", "sigma_s": 1, "sigma_a": 0.1}}]})");
  try {
    load_scene_file(path);
    FAIL() << "an open mesh was accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find("/shapes/1"), std::string::npos) << msg;
    EXPECT_NE(msg.find("open.obj"), std::string::npos) << msg;
    EXPECT_NE(msg.find("4 open edges"), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
  // A quad is never closed; the diffusion method does not need a closed mesh.
  EXPECT_THROW(parse_scene(R"({"shapes": [{"type": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0],
                                 "material": {"type": "subsurface", "sigma_s": 1, "sigma_a": 0.1}}]})",
                           "q.json", ""),
               InputError);
}

TEST(SubsurfaceRender, ClosedMeshesAreAcceptedAndTurnedOutward) {
  ScratchDir dir("gonio_subsurface");
  dir.file("in.obj", box_obj({0, 0, 0}, {1, 2, 3}, true));
  const Scene scene = load_scene_file(dir.file("in.json", R"({"shapes": [
    {"type": "mesh", "file": "in.obj", "material": {"type": "subsurface", "sigma_s": 1, "sigma_a": 0.1}}]})"));
  ASSERT_EQ(scene.meshes.size(), 1u);
  const MeshClosure c = mesh_closure(scene.meshes[0]);
  EXPECT_EQ(c.edges, 18u);  // 12 box edges and 6 face diagonals
  EXPECT_EQ(c.open_edges, 0u);
  EXPECT_EQ(c.inconsistent_edges, 0u);
  EXPECT_NEAR(c.volume, 6.0, 1e-5);  // wound inward in the file, outward after loading
  // The same for the diffusion method, whose exits and entries need outward normals too.
  const Scene diffusion = load_scene_file(dir.file("in-diffusion.json", R"({"shapes": [
    {"type": "mesh", "file": "in.obj", "material": {"type": "subsurface", "method": "diffusion", "sigma_s": 1, "sigma_a": 0.1}}]})"));
  EXPECT_NEAR(mesh_closure(diffusion.meshes[0]).volume, 6.0, 1e-5);

  // The lecture's bunny (data/meshes/bunny.obj) is closed and wound outward as shipped.
  const Scene bunny = parse_scene(R"({"shapes": [{"type": "mesh", "file": "data/meshes/bunny.obj",
    "material": {"type": "diffuse"}}]})", "bunny.json", GONIO_SOURCE_DIR);
  const MeshClosure b = mesh_closure(bunny.meshes[0]);
  EXPECT_EQ(b.open_edges, 0u);
  EXPECT_EQ(b.inconsistent_edges, 0u);
  EXPECT_EQ(b.edges, 5511u);  // Euler: V − E + F = 2 with V = 1839, F = 3674
  EXPECT_GT(b.volume, 0);
}

TEST(SubsurfaceRender, InconsistentWindingIsRejected) {
  ScratchDir dir("gonio_subsurface");
  std::string obj = box_obj({0, 0, 0}, {1, 1, 1});
  obj += "f 1 2 3\n";  // an extra triangle: its edges are now used three times
  dir.file("bad.obj", obj);
  EXPECT_THROW(load_scene_file(dir.file("bad.json", R"({"shapes": [
    {"type": "mesh", "file": "bad.obj", "material": {"type": "subsurface", "sigma_s": 1, "sigma_a": 0.1}}]})")),
               InputError);
  // One face turned around: closed, but its four edges run the same way twice.
  std::string flipped = box_obj({0, 0, 0}, {1, 1, 1});
  flipped.replace(flipped.find("f 1 3 4 2"), 9, "f 2 4 3 1");
  dir.file("flip.obj", flipped);
  try {
    load_scene_file(dir.file("flip.json", R"({"shapes": [
      {"type": "mesh", "file": "flip.obj", "material": {"type": "subsurface", "sigma_s": 1, "sigma_a": 0.1}}]})"));
    FAIL() << "an inconsistently wound mesh was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("wound inconsistently (4 edges"), std::string::npos) << e.what();
  }
}

// The medium is RGB: a spectral render says so rather than render it wrong.
TEST(SubsurfaceRender, SpectralRenderIsRejected) {
  Scene scene = parse_scene(furnace_scene(R"({"type": "subsurface", "sigma_s": 1, "sigma_a": 0})", 1), "s.json", "");
  scene.settings.spectral = true;
  try {
    render(scene, {});
    FAIL() << "a spectral subsurface render was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("RGB only"), std::string::npos) << e.what();
  }
}

// The walk's next-event proposal maps a direction d inside through a plane to the ω it
// leaves in, and turns the light's density of ω into one of d with |dω/dd| (issue 56: the
// factor cos θ_d left out passed the unbiasedness tests below, which see it only
// diluted in both strategies' MIS weights). Here the map is held to Snell's law and the
// Jacobian to the finite-difference Jacobian of the map: the ratio of the solid angles of
// the small parallelograms spanned by central differences of ω and of d, in double.
TEST(SubsurfaceRender, WalkPlaneJacobianIsTheMapsFiniteDifferenceJacobian) {
  const auto to_vec = [](double x, double y, double z) { return Vec3{Float(x), Float(y), Float(z)}; };
  struct D3 {
    double x, y, z;
  };
  const auto d3 = [](const Vec3& v) { return D3{v.x, v.y, v.z}; };
  const auto cross3 = [](D3 a, D3 b) { return D3{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; };
  const auto len3 = [](D3 a) { return std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z); };
  const auto sub3 = [](D3 a, D3 b) { return D3{a.x - b.x, a.y - b.y, a.z - b.z}; };
  const auto dot3 = [](D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; };
  const auto unit3 = [&](D3 a) { const double l = len3(a); return D3{a.x / l, a.y / l, a.z / l}; };
  int checked = 0;
  for (const double eta : {0.8, 1.2, 1.5, 2.0}) {
    for (const D3 n_raw : {D3{0, 0, 1}, D3{0.3, -0.5, 0.8}}) {
      const D3 n = unit3(n_raw);
      // A tangent frame (t, b, n).
      const D3 t = unit3(cross3(std::abs(n.x) < 0.9 ? D3{1, 0, 0} : D3{0, 1, 0}, n)), b = cross3(n, t);
      // θ_d up to where sin θ_ω = η sin θ_d reaches 0.95 (near total internal reflection the
      // Jacobian grows without bound and differences lose their meaning), and for η < 1 to
      // 75° (a grazing d leaves grazing).
      const double theta_max = std::min(std::asin(std::min(1.0, 0.95 / eta)), 75 * kPiD / 180);
      for (int i = 0; i <= 6; ++i)
        for (const double phi : {0.3, 2.0, 4.4}) {
          const double th = theta_max * i / 6;
          const auto dir = [&](double th_, double ph_) {
            const double st = std::sin(th_), ct = std::cos(th_);
            return D3{st * std::cos(ph_) * t.x + st * std::sin(ph_) * b.x + ct * n.x,
                      st * std::cos(ph_) * t.y + st * std::sin(ph_) * b.y + ct * n.y,
                      st * std::cos(ph_) * t.z + st * std::sin(ph_) * b.z + ct * n.z};
          };
          const D3 d = dir(th, phi);
          const Vec3 nf = to_vec(n.x, n.y, n.z);
          Vec3 omega;
          Float jacobian = 0;
          ASSERT_TRUE(walk_plane_out(to_vec(d.x, d.y, d.z), nf, Float(eta), omega, jacobian)) << eta << " " << th;
          // Snell's law: ω outside, in the plane of n and d, η sin θ_d = sin θ_ω.
          const D3 w = d3(omega);
          EXPECT_GT(dot3(w, n), 0);
          EXPECT_NEAR(len3(cross3(w, n)), eta * len3(cross3(d, n)), 2e-6);
          EXPECT_NEAR(dot3(w, cross3(n, d)), 0, 2e-6);
          // And walk_plane_in undoes it.
          Vec3 back;
          ASSERT_TRUE(walk_plane_in(omega, nf, Float(eta), back)) << "eta " << eta << ", theta_d " << th << ", phi " << phi;
          EXPECT_NEAR(len3(sub3(d3(back), d)), 0, 1e-5);
          // The finite-difference Jacobian of the map, from two perpendicular pairs of
          // directions about d (a step of 1e-3 rad: truncation ~1e-6, float rounding ~1e-4).
          const double h = 1e-3;
          const D3 du = sub3(dir(th + h, phi), dir(th - h, phi));
          const double dphi = th > 0 ? h / std::sin(th) : h;
          const D3 dv = th > 0 ? sub3(dir(th, phi + dphi), dir(th, phi - dphi))
                               : sub3(dir(h, phi + kPiD / 2), dir(h, phi - kPiD / 2));
          const auto out = [&](const D3& e) {
            Vec3 o;
            Float j;
            EXPECT_TRUE(walk_plane_out(to_vec(e.x, e.y, e.z), nf, Float(eta), o, j));
            return d3(o);
          };
          const D3 wu = sub3(out(dir(th + h, phi)), out(dir(th - h, phi)));
          const D3 wv = th > 0 ? sub3(out(dir(th, phi + dphi)), out(dir(th, phi - dphi)))
                               : sub3(out(dir(h, phi + kPiD / 2)), out(dir(h, phi - kPiD / 2)));
          const double numeric = len3(cross3(wu, wv)) / len3(cross3(du, dv));
          EXPECT_NEAR(jacobian / numeric, 1, 2e-3) << "eta " << eta << ", theta_d " << th << ", phi " << phi
                                                   << ": |dω/dd| " << jacobian << ", finite differences " << numeric;
          ++checked;
        }
    }
  }
  EXPECT_EQ(checked, 4 * 2 * 7 * 3);
}

// Next-event estimation from the walk's events through a smooth boundary (issue 38,
// path_tracer.cpp "Next-event estimation from inside a medium") adds a strategy; it must
// not change what is estimated. The same sphere of a coloured, anisotropic medium under a
// quad light above it and a dim environment (two lights whose directions overlap, so the
// proposal's density is a mixture), with `nee` on and off: the mean radiance over rays
// spread across the sphere must agree within the two estimates' standard errors. The
// medium is thin (mean free paths 0.7–2.5 radii) and η = 2, so that walks leave far from
// their entry, where the boundary's normal is not the entry plane's (the Fresnel factor
// and refraction taken at the plane instead are 3–6 % too bright here).
struct WalkNeeMean {
  double mean[3] = {}, err[3] = {};
  std::uint64_t walks = 0;
};
// The quad light above the sphere, or (`behind`) facing the sphere's back, which the
// camera does not see.
WalkNeeMean walk_nee_mean(bool nee, std::uint64_t n, Float alpha = 0, Float density = 1, bool behind = false,
                          Float eta = 2) {
  const auto coefficients = [density](double a, double b, double c) {
    return "[" + std::to_string(a * density) + ", " + std::to_string(b * density) + ", " + std::to_string(c * density) + "]";
  };
  const std::string material = std::string(R"({"type": "subsurface", "eta": )") + std::to_string(eta) + R"(, "sigma_s": )" + coefficients(0.3, 0.6, 1.2) +
                               R"(, "sigma_a": )" + coefficients(0.1, 0.05, 0.02) + R"(, "g": 0.3, "nee": )" + (nee ? "true" : "false") +
                               (alpha > 0 ? R"(, "alpha": )" + std::to_string(alpha) : std::string()) + "}";
  const Scene scene = parse_scene(R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
      "render": {"max_depth": 64},
      "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": )" + material + R"(}],
      "lights": [)" + std::string(behind ? R"({"type": "quad", "corner": [-1, -1, -2.5], "edge1": [2, 0, 0], "edge2": [0, 2, 0], "radiance": 2})"
                                         : R"({"type": "quad", "corner": [-1, 2.5, -1], "edge1": [2, 0, 0], "edge2": [0, 0, 2], "radiance": 2})") +
                           R"(], "environment": {"radiance": 0.2}})", "nee.json", "");
  const Accel accel(scene);
  const PathTracer tracer(scene, accel);
  PixelSampler sampler(SamplerType::Independent, 1, nee ? 11 : 12);
  Pcg32 aim(5);
  PathStats stats;
  double sum[3] = {}, sum2[3] = {};
  for (std::uint64_t i = 0; i < n; ++i) {
    sampler.start(0, 0, i);
    // A ray from the camera to a uniform point of the disc the sphere covers (z = 0).
    const Float r = 0.98f * std::sqrt(aim.next_float()), phi = 2 * kPi * aim.next_float();
    const Vec3 o{0, 0, 5};
    const Color L = tracer.radiance(Ray{o, normalize(Vec3{r * std::cos(phi), r * std::sin(phi), 0} - o)}, sampler, stats);
    for (int c = 0; c < 3; ++c) sum[c] += L[c], sum2[c] += double(L[c]) * L[c];
  }
  WalkNeeMean m;
  for (int c = 0; c < 3; ++c) {
    m.mean[c] = sum[c] / double(n);
    m.err[c] = std::sqrt(std::max(0.0, sum2[c] / double(n) - m.mean[c] * m.mean[c]) / double(n - 1));
  }
  m.walks = stats.walks;
  return m;
}

void expect_walk_nee_unbiased(std::uint64_t n, Float density, bool behind, Float eta = 2) {
  const WalkNeeMean on = walk_nee_mean(true, n, 0, density, behind, eta),
                    off = walk_nee_mean(false, n, 0, density, behind, eta);
  EXPECT_GT(on.walks, n / 2);
  for (int c = 0; c < 3; ++c) {
    const double err = std::hypot(on.err[c], off.err[c]);
    EXPECT_NEAR(on.mean[c], off.mean[c], 4 * err) << "channel " << c << ": with " << on.mean[c] << " ± " << on.err[c]
                                                  << ", without " << off.mean[c] << " ± " << off.err[c];
  }
}

TEST(SubsurfaceRender, WalkNextEventEstimationIsUnbiased) { expect_walk_nee_unbiased(scaled(600000, 20000), 1, false); }

// The same medium six times denser (mean free paths 0.14–0.42 radii) and the light behind
// the sphere: the light the camera sees crosses the sphere, and events farther than two
// mean free paths from the entry point propose through the tangent plane at their nearest
// surface point (walk_nee_plane), so the walk's exit and the events' estimates must weigh
// each other with that plane.
TEST(SubsurfaceRender, WalkNextEventEstimationIsUnbiasedThroughNearestSurfacePlanes) {
  expect_walk_nee_unbiased(scaled(1600000, 8000), 6, true);
}

// The same at η = 1.2. At η = 2 a direction d that leaves lies within 30° of the normal,
// where the Jacobian's cos θ_d is at least 0.87; and a wrong proposal density enters both
// strategies' MIS weights, which hides most of its error: the estimate without cos θ_d
// (issue 56) was 1–2 % low there, within 4 σ. At η = 1.2 d reaches 56° (cos θ_d 0.55):
// the same error is 5–7 % low, at 10 σ in a third of the samples; so is an exit weight
// taken with the entry plane instead of the event's nearest-surface plane (4 % high, 6 σ).
TEST(SubsurfaceRender, WalkNextEventEstimationIsUnbiasedThroughNearestSurfacePlanesAtALowIndex) {
  expect_walk_nee_unbiased(scaled(500000, 8000), 6, true, 1.2f);
}

}  // namespace
}  // namespace gonio::render
