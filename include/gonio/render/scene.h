#pragma once
// A scene in memory: camera, materials, shapes and lights, as scene_loader.h reads them
// from JSON (docs/scene-format.md). Shapes are spheres and triangle meshes (quads and
// OBJ files become meshes); area lights are shapes too, so that rays can hit them.

#include <cstdint>
#include <string>
#include <vector>

#include "gonio/bxdf.h"
#include "gonio/math/warp.h"
#include "gonio/render/camera.h"
#include "gonio/render/lights.h"

namespace gonio::render {

struct Material {
  std::string name;
  BxDF bxdf;
};

// Indexed triangles with optional per-vertex normals, UVs and tangents (each either empty
// or one per position).
struct Mesh {
  std::vector<Vec3> positions, normals, tangents;
  std::vector<Vec2> uvs;
  std::vector<std::uint32_t> indices;  // 3 per triangle
  int material = -1;
  int area_light = -1;  // index into Scene::area_lights when the mesh emits
};

struct Sphere {
  Vec3 center;
  Float radius = 1;
  int material = -1;
  int area_light = -1;
};

struct RenderSettings {
  int spp = 16;
  int max_depth = 16;   // bounces
  int rr_depth = 3;     // Russian roulette from this bounce on
  std::uint64_t seed = 0;
  Float exposure = 0;   // stops, for PNG output
  bool filmic = true;   // tone map for PNG output (else clamp)
};

struct Scene {
  Camera camera;
  RenderSettings settings;
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  std::vector<Sphere> spheres;
  std::vector<PointLight> point_lights;
  std::vector<AreaLight> area_lights;
  Environment environment;
};

}  // namespace gonio::render
