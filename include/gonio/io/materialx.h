#pragma once
// MaterialX documents (.mtlx, versions 1.38 and 1.39) → gonio's `openpbr` material JSON
// (SPEC §2, "A material may also come from a MaterialX document"; SPEC §3 `gonio
// materials --from-mtlx`). One `surfacematerial` is chosen (by name, or the document's
// only one); its `surfaceshader` input leads, directly or through a nodegraph's
// `output`, to an `open_pbr_surface` or a `standard_surface` node, whose constant inputs
// become the JSON object {"type": "openpbr", every OpenPBR 1.1 parameter: its value}.
//
// Only constant values are read. A connected input (an image or any other node, a
// nodegraph, an interfacename), an unknown node or input, a value that does not parse or
// is not finite, a negative weight, roughness or Abbe number, an unsupported colour space,
// several materials and no name: each is one InputError line naming the file, the line,
// the node and the input, in the document's names and units. Any other finite value
// outside what the model takes is clamped into it, as renderers do (a colour a hair above
// 1, an ACEScg colour whose Rec.709 red is negative, an index below 1), and `note` (when
// given) receives one line naming each clamped input, its value and the value used (empty
// when nothing was clamped). The mapping rules (1.38 names and units, Standard Surface →
// OpenPBR, colour spaces, ranges) are in src/io/materialx.cpp and docs/materialx.md.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gonio/io/materialx_graph.h"

#include <nlohmann/json_fwd.hpp>

namespace gonio {

// Largest .mtlx file read (a hand-written material is a few KB).
inline constexpr std::size_t kMaxMaterialxFileBytes = std::size_t(16) << 20;  // 16 MiB

// Where a document's node graphs are evaluated (SPEC §2: `--uv U V`, default 0.5 0.5;
// `--position X Y Z`, default 0 0 0).
using MaterialxPoint = mtlxgraph::ShadingPoint;

// The surface `name` (nullopt: the document's only surface) of the document text `xml`,
// by SPEC §2's naming rule (a surfacematerial; in a document without materials a
// nodegraph's surfaceshader output "NODEGRAPH/OUTPUT" or a top-level surface shader
// node); `source` names the document in messages (its path; xi:includes resolve from its
// folder). Connected inputs are evaluated by the node graph compiler at `at`. `note`
// receives the clamped values and what was ignored (displacement, volumes, normal maps),
// one line each.
nlohmann::json materialx_to_json(std::string_view xml, const std::string& source,
                                 const std::optional<std::string>& name = std::nullopt, std::string* note = nullptr,
                                 const MaterialxPoint& at = {});

// The same, read from the file `path` (bounded: kMaxMaterialxFileBytes; read whatever it
// is, a FIFO included, as a scene file is: docs/materialx.md).
nlohmann::json materialx_file_to_json(const std::string& path, const std::optional<std::string>& name = std::nullopt,
                                      std::string* note = nullptr, const MaterialxPoint& at = {});

// The names of the surfaces of the document `path`, in document order (SPEC §3
// `gonio materials --from-mtlx FILE --list`).
std::vector<std::string> materialx_surface_names(const std::string& path);
// The same of the document text `xml` named `source` (read once: a FIFO cannot be read twice).
std::vector<std::string> materialx_surface_names(std::string_view xml, const std::string& source);

}  // namespace gonio
