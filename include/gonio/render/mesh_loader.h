#pragma once
// Triangle meshes from Wavefront OBJ files (read by tinyobjloader), placed in the scene by
// scale, then rotation about an axis, then translation.

#include <string>

#include "gonio/render/scene.h"

namespace gonio::render {

struct MeshTransform {
  Vec3 scale{1, 1, 1};
  Vec3 rotate_axis{0, 1, 0};
  Float rotate_degrees = 0;
  Vec3 translate{0, 0, 0};
};

// Loads `path`; errors name `where` (the scene file and JSON path) and the file.
// Per-vertex tangents are derived from the UVs (dP/du, Lengyel's method) when the file
// has texture coordinates, so that anisotropic materials follow the surface's u.
Mesh load_obj_mesh(const std::string& path, const MeshTransform& transform, const std::string& where);

}  // namespace gonio::render
