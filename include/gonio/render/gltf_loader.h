#pragma once
// glTF 2.0 scenes (.gltf, .glb), read with tinygltf; docs/gltf.md says what is supported
// and how each glTF concept maps onto gonio's (SPEC §3, `gonio render SCENE.gltf`).
// glTF's frame (right-handed, +y up, metres) is gonio's scene frame unchanged. Every
// error is an InputError of one line naming the file and the glTF object.

#include <string>
#include <vector>

#include "gonio/render/mesh_loader.h"
#include "gonio/render/scene.h"

namespace gonio::render {

struct GltfCamera {
  std::string name;  // "" when the file gives none
  Camera camera;     // placed by its node; width/height from its aspect ratio when given
  bool has_aspect = false;
};

// Adds the default scene of the glTF file `path` to `scene` (its materials, meshes with
// their textures, KHR_lights_punctual lights; emissive materials emit), every node's
// world transform followed by `transform` (a scene JSON's "gltf" shape). Returns the
// cameras of the scene's nodes, in node order. `where` prefixes errors (the scene file
// and JSON path, or "" for a glTF given on its own).
std::vector<GltfCamera> append_gltf(Scene& scene, const std::string& path, const MeshTransform& transform,
                                    const std::string& where);

struct GltfSceneOptions {
  std::string camera;  // a camera's name; "" for the first camera
};

// A glTF file as a whole scene: append_gltf's contents seen through its named (or first)
// camera, or, with no camera, a default view framing the geometry from +z.
Scene load_gltf_scene(const std::string& path, const GltfSceneOptions& options = {});

// Whether `path` names a glTF file (extension .gltf or .glb, case-insensitive).
bool is_gltf_path(const std::string& path);

}  // namespace gonio::render
