#pragma once
// Scenes from JSON (docs/scene-format.md). Every error is an InputError whose one-line
// message names the file, the JSON path and the problem, e.g.
//   "room.json: /shapes/2/radius: must be > 0, got -1".

#include <string>
#include <string_view>

#include "gonio/render/scene.h"

namespace gonio::render {

// Reads a scene file; relative paths inside it (OBJ meshes, images) are relative to the
// file's directory.
Scene load_scene_file(const std::string& path);

// Parses scene text. `source` names it in messages; `base_dir` resolves relative paths.
Scene parse_scene(std::string_view json_text, const std::string& source, const std::string& base_dir);

// The built-in default scene (what `gonio render` draws with no arguments), as JSON text:
// it doubles as an example of the format.
std::string_view default_scene_json();

}  // namespace gonio::render
