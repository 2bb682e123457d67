#pragma once
// A sample for the virtual gonioreflectometer (SPEC §3 `gonio measure --surface`): a
// height field and the material its facets carry. Parsed from JSON of the form
// {"type": "flat" | "gaussian" | "vgroove" | "image", "material": {...}, ...}; every bad
// field throws gonio::InputError with one line naming it.

#include <string>
#include <string_view>

#include "gonio/bxdf.h"
#include "gonio/measure/heightfield.h"

namespace gonio::measure {

struct Surface {
  std::string type;   // "flat", "gaussian", "vgroove" or "image"
  HeightField field;  // the microsurface (a flat sample is one cell of height 0)
  BxDF material;      // evaluated in each facet's own frame (normal = the facet's normal)
};

// `source` prefixes syntax errors ("--surface" or the file's path); relative paths in the
// description (an "image" file) are resolved in `base_dir` (empty: the working directory).
Surface parse_surface(std::string_view json_text, std::string_view source = "--surface",
                      const std::string& base_dir = "");

}  // namespace gonio::measure
