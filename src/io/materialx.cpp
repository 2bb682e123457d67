// MaterialX documents → gonio's `openpbr` JSON (include/gonio/io/materialx.h).
//
// Sources:
// - MaterialX Specification v1.39 (AcademySoftwareFoundation/MaterialX,
//   documents/Specification/MaterialX.v1.39.Spec.md), "Inputs" and "Output Elements": an
//   input carries a `value`, or a `nodename` / `nodegraph` + `output` / `interfacename`
//   connection; a nodegraph's `output` names the node inside it.
// - The OpenPBR 1.1 node definition (MaterialX libraries/bxdf/open_pbr_surface.mtlx,
//   ND_open_pbr_surface_surfaceshader, version 1.1): the input names, types and defaults
//   of kOpenPbr below (also OpenPBR's parametrization table).
// - SPEC §2: a document of version 1.38 uses the OpenPBR draft's names and units.
// - Autodesk Standard Surface 1.0.1 (MaterialX libraries/bxdf/standard_surface.mtlx,
//   ND_standard_surface_surfaceshader; 1.0.0 differs in base = 0.8, base_color = 1) and its
//   translation to OpenPBR, MaterialX libraries/bxdf/translation/
//   standard_surface_to_open_pbr.mtlx (ND/NG_standard_surface_to_open_pbr_surface):
//   standard_surface_to_openpbr() follows that graph node by node, except where noted.
// - ACEScg → linear Rec.709: MaterialX libraries/stdlib/genglsl/lib/mx_transform_color.glsl
//   (M_AP1_TO_REC709), i.e. the AP1 primaries (ACES S-2014-004) with white D60 to the
//   BT.709 primaries with white D65, the white adapted by CAT02.

#include "gonio/io/materialx.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>
#include <pugixml.hpp>

#include "gonio/error.h"
#include "gonio/io/materialx_graph.h"
#include "gonio/json_text.h"
#include "gonio/material_types.h"

namespace gonio {
// Its own namespace: in a unity build, helpers of other files' anonymous namespaces
// (gonio::{anonymous}) would otherwise meet these.
namespace mtlx {
namespace {

using json = nlohmann::json;
using Rgb = std::array<double, 3>;

enum class Kind { Float, Color3, Boolean, Vector3 };

const char* kind_name(Kind k) {
  switch (k) {
    case Kind::Float: return "float";
    case Kind::Color3: return "color3";
    case Kind::Boolean: return "boolean";
    case Kind::Vector3: return "vector3";
  }
  return "";
}

// A constant input's value (Vector3: only accepted unset, so it carries nothing), and
// the input element it came from (none for a default), for messages.
struct Value {
  Kind kind = Kind::Float;
  double f = 0;
  Rgb c{};
  bool b = false;
  pugi::xml_node node{};
};

// What the model takes of a number (or of each channel of a colour). A value above `hi`
// is clamped to it; one below `lo` is refused when negative values mean nothing to the
// model (a weight, a roughness, an Abbe number: `what` names it in the message), else
// clamped (a colour's negative channel, an index below 1). The bounds are the openpbr
// type's parameter ranges (src/material_types.cpp), so that what the reader passes on
// is taken as is.
struct Range {
  double lo = 0, hi = 0;
  const char* refused_below = nullptr;  // e.g. "a weight"; nullptr: clamped
};
constexpr double kLarge = 1e9;  // the openpbr type's bound of unbounded parameters
constexpr Range kWeightRange{0, 1, "a weight"};
constexpr Range kRoughRange{0, 1, "a roughness"};
constexpr Range kUnitRange{0, 1};               // colours, anisotropies
constexpr Range kOpenRange{0, kLarge};          // emission, lengths, radius scales
constexpr Range kIorRange{1, 1e4};              // indices of refraction
constexpr Range kPhaseRange{-1, 1};             // Henyey-Greenstein g
constexpr Range kTurnRange{-1e3, 1e3};          // gonio's tangent rotations, in turns
constexpr Range kAbbeRange{0, 1e4, "an Abbe number"};

struct ParamDef {
  const char* name;
  Kind kind;
  Rgb def;  // a float's default in def[0]; a boolean's as 0 or 1
  Range range{};
  const char* unit = "";  // the unit of the document's value, when it has one
};

// OpenPBR Surface 1.1, in the specification's order (ND_open_pbr_surface_surfaceshader).
constexpr ParamDef kOpenPbr[] = {
    {"base_weight", Kind::Float, {1}, kWeightRange},
    {"base_color", Kind::Color3, {0.8, 0.8, 0.8}, kUnitRange},
    {"base_metalness", Kind::Float, {0}, kWeightRange},
    {"base_diffuse_roughness", Kind::Float, {0}, kRoughRange},
    {"specular_weight", Kind::Float, {1}, Range{0, 1e4, "a weight"}},
    {"specular_color", Kind::Color3, {1, 1, 1}, kUnitRange},
    {"specular_roughness", Kind::Float, {0.3}, kRoughRange},
    {"specular_roughness_anisotropy", Kind::Float, {0}, kUnitRange},
    {"specular_ior", Kind::Float, {1.5}, kIorRange},
    {"transmission_weight", Kind::Float, {0}, kWeightRange},
    {"transmission_color", Kind::Color3, {1, 1, 1}, kUnitRange},
    {"transmission_depth", Kind::Float, {0}, kOpenRange},
    {"transmission_scatter", Kind::Color3, {0, 0, 0}, kUnitRange},
    {"transmission_scatter_anisotropy", Kind::Float, {0}, kPhaseRange},
    {"transmission_dispersion_scale", Kind::Float, {0}, kWeightRange},
    {"transmission_dispersion_abbe_number", Kind::Float, {20}, kAbbeRange},
    {"subsurface_weight", Kind::Float, {0}, kWeightRange},
    {"subsurface_color", Kind::Color3, {0.8, 0.8, 0.8}, kUnitRange},
    {"subsurface_radius", Kind::Float, {1}, kOpenRange},
    {"subsurface_radius_scale", Kind::Color3, {1, 0.5, 0.25}, kOpenRange},
    {"subsurface_scatter_anisotropy", Kind::Float, {0}, kPhaseRange},
    {"coat_weight", Kind::Float, {0}, kWeightRange},
    {"coat_color", Kind::Color3, {1, 1, 1}, kUnitRange},
    {"coat_roughness", Kind::Float, {0}, kRoughRange},
    {"coat_roughness_anisotropy", Kind::Float, {0}, kUnitRange},
    {"coat_ior", Kind::Float, {1.6}, kIorRange},
    {"coat_darkening", Kind::Float, {1}, kWeightRange},
    {"fuzz_weight", Kind::Float, {0}, kWeightRange},
    {"fuzz_color", Kind::Color3, {1, 1, 1}, kUnitRange},
    {"fuzz_roughness", Kind::Float, {0.5}, kRoughRange},
    {"thin_film_weight", Kind::Float, {0}, kWeightRange},
    {"thin_film_thickness", Kind::Float, {0.5}, Range{0, 10}, "um"},  // micrometres
    {"thin_film_ior", Kind::Float, {1.4}, kIorRange},
    {"emission_luminance", Kind::Float, {0}, kOpenRange},
    {"emission_color", Kind::Color3, {1, 1, 1}, kOpenRange},
    {"geometry_opacity", Kind::Float, {1}, kWeightRange},
    {"geometry_thin_walled", Kind::Boolean, {0}},
    // Shading frames: the caller's (a BSDF works in the local frame); accepted unset only.
    {"geometry_normal", Kind::Vector3, {}},
    {"geometry_coat_normal", Kind::Vector3, {}},
    {"geometry_tangent", Kind::Vector3, {}},
    {"geometry_coat_tangent", Kind::Vector3, {}},
};

// SPEC §2: the OpenPBR draft's names in documents of version 1.38 (values copied).
struct Rename {
  const char* old_name;
  const char* new_name;
};
constexpr Rename kRenames138[] = {
    {"specular_anisotropy", "specular_roughness_anisotropy"},
    {"coat_anisotropy", "coat_roughness_anisotropy"},
    {"subsurface_anisotropy", "subsurface_scatter_anisotropy"},
    {"base_roughness", "base_diffuse_roughness"},
};
// SPEC §2: 1.38's tangent rotations (a fraction of a turn) → gonio's extension parameters
// of the same names. Standard Surface has the same two inputs with the same meaning.
constexpr const char* kRotations[] = {"specular_rotation", "coat_rotation"};

// Autodesk Standard Surface 1.0.1 (ND_standard_surface_surfaceshader).
constexpr ParamDef kStandardSurface[] = {
    {"base", Kind::Float, {1}, kWeightRange},
    {"base_color", Kind::Color3, {0.8, 0.8, 0.8}, kUnitRange},
    {"diffuse_roughness", Kind::Float, {0}, kRoughRange},
    {"metalness", Kind::Float, {0}, kWeightRange},
    {"specular", Kind::Float, {1}, Range{0, 1e4, "a weight"}},
    {"specular_color", Kind::Color3, {1, 1, 1}, kUnitRange},
    {"specular_roughness", Kind::Float, {0.2}, kRoughRange},
    {"specular_IOR", Kind::Float, {1.5}, kIorRange},
    {"specular_anisotropy", Kind::Float, {0}, kUnitRange},
    {"specular_rotation", Kind::Float, {0}, kTurnRange},
    {"transmission", Kind::Float, {0}, kWeightRange},
    {"transmission_color", Kind::Color3, {1, 1, 1}, kUnitRange},
    {"transmission_depth", Kind::Float, {0}, kOpenRange},
    {"transmission_scatter", Kind::Color3, {0, 0, 0}, kUnitRange},
    {"transmission_scatter_anisotropy", Kind::Float, {0}, kPhaseRange},
    {"transmission_dispersion", Kind::Float, {0}, kAbbeRange},
    {"transmission_extra_roughness", Kind::Float, {0}, kRoughRange},
    {"subsurface", Kind::Float, {0}, kWeightRange},
    {"subsurface_color", Kind::Color3, {1, 1, 1}, kUnitRange},
    {"subsurface_radius", Kind::Color3, {1, 1, 1}, kOpenRange},
    {"subsurface_scale", Kind::Float, {1}, kOpenRange},
    {"subsurface_anisotropy", Kind::Float, {0}, kPhaseRange},
    {"sheen", Kind::Float, {0}, kWeightRange},
    {"sheen_color", Kind::Color3, {1, 1, 1}, kUnitRange},
    {"sheen_roughness", Kind::Float, {0.3}, kRoughRange},
    {"coat", Kind::Float, {0}, kWeightRange},
    {"coat_color", Kind::Color3, {1, 1, 1}, kUnitRange},
    {"coat_roughness", Kind::Float, {0.1}, kRoughRange},
    {"coat_anisotropy", Kind::Float, {0}, kUnitRange},
    {"coat_rotation", Kind::Float, {0}, kTurnRange},
    {"coat_IOR", Kind::Float, {1.5}, kIorRange},
    {"coat_affect_color", Kind::Float, {0}, kWeightRange},
    {"coat_affect_roughness", Kind::Float, {0}, kWeightRange},
    {"thin_film_thickness", Kind::Float, {0}, Range{0, 1e4}, "nm"},  // nanometres
    {"thin_film_IOR", Kind::Float, {1.5}, kIorRange},
    {"emission", Kind::Float, {0}, kOpenRange},
    {"emission_color", Kind::Color3, {1, 1, 1}, kOpenRange},
    {"opacity", Kind::Color3, {1, 1, 1}, kUnitRange},
    {"thin_walled", Kind::Boolean, {0}},
    {"normal", Kind::Vector3, {}},
    {"tangent", Kind::Vector3, {}},
    {"coat_normal", Kind::Vector3, {}},
};

// ACEScg (linear AP1, D60) → linear Rec.709 (D65), row-major: MaterialX's M_AP1_TO_REC709
// (mx_transform_color.glsl, there column-major), the CAT02-adapted primaries conversion.
constexpr double kAp1ToRec709[3][3] = {
    {1.705079555511475, -0.6242334842681885, -0.0808461606502533},
    {-0.1297005265951157, 1.138468623161316, -0.008768022060394287},
    {-0.02416634373366833, -0.1246141716837883, 1.148780584335327},
};

const ParamDef* find_def(const ParamDef* begin, const ParamDef* end, std::string_view name) {
  for (const ParamDef* p = begin; p != end; ++p)
    if (name == p->name) return p;
  return nullptr;
}

// Appends its parts (GCC 12 warns falsely, -Wrestrict, on "literal" + std::string).
template <class... Parts>
std::string cat(const Parts&... parts) {
  std::string s;
  (s.append(std::string_view(parts)), ...);
  return s;
}

// Document text as messages echo it: at most 60 bytes, cut on a UTF-8 character
// boundary and marked "..." (as json_excerpt cuts a JSON value), so that a name of
// millions of characters does not become a line of millions.
std::string excerpt(std::string_view s) {
  constexpr size_t kMax = 60;
  if (s.size() <= kMax) return std::string(s);
  size_t cut = kMax - 3;
  while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;  // a continuation byte
  return cat(s.substr(0, cut), "...");
}

std::string in_quotes(std::string_view s) { return cat("\"", excerpt(s), "\""); }

// XInclude's namespace (W3C XInclude 1.0, §4): an element `include` in it, whatever its
// prefix, is an inclusion.
constexpr std::string_view kXIncludeNamespace = "http://www.w3.org/2001/XInclude";

// One loaded document (the one read, an xi:include'd one, or a data library file).
struct Loaded {
  std::string path;  // as messages name it
  std::string text;
  pugi::xml_document doc;
  bool library = false;  // MaterialX's data library: definitions only, no surfaces
};

// A surface by SPEC §2's naming rule: a surfacematerial, a nodegraph's surfaceshader
// output ("NODEGRAPH/OUTPUT"), or a top-level surface shader node.
struct Surface {
  std::string name;
  pugi::xml_node node;
};

// Where interfacename resolves while a graph is compiled: a nodegraph's own inputs, or,
// for a node whose definition a nodegraph implements, that node instance's inputs (read
// in `parent`) and its definition's defaults. The top level has no graph.
struct Frame {
  pugi::xml_node graph;
  pugi::xml_node instance;
  pugi::xml_node nodedef;
  const Frame* parent = nullptr;
};

// A compiled value: its register and width (1 float/integer/boolean, 2, 3 or 4 lanes).
struct Val {
  std::uint16_t reg = 0;
  int width = 1;
};

// Bounds of what a document may ask (docs/materialx.md): xi:include nesting, the nesting
// of graph evaluation (nodes within nodes, definitions within definitions).
constexpr int kMaxIncludeDepth = 8;
constexpr int kMaxGraphDepth = 128;

int width_of(std::string_view type) {
  if (type == "float" || type == "integer" || type == "boolean") return 1;
  if (type == "vector2") return 2;
  if (type == "color3" || type == "vector3") return 3;
  if (type == "color4" || type == "vector4") return 4;
  return 0;  // not a value (a closure, a string, a filename, a multioutput)
}

bool is_closure_type(std::string_view type) {
  return type == "BSDF" || type == "EDF" || type == "VDF" || type == "surfaceshader" || type == "displacementshader" ||
         type == "volumeshader" || type == "material" || type == "lightshader";
}

// Elements of a document that are not nodes.
bool is_structural(std::string_view element) {
  static constexpr std::string_view kNames[] = {"nodedef", "nodegraph", "output", "input", "implementation", "typedef",
                                                "look", "collection", "geominfo", "propertyset", "materialassign",
                                                "variantset", "backdrop", "token", "unittypedef", "unitdef",
                                                "targetdef", "attributedef", "member", "lookgroup", "comment"};
  for (const std::string_view n : kNames)
    if (element == n) return true;
  return false;
}

// The document being read: its text's source for messages, and what scopes need.
class Reader {
 public:
  Reader(std::string source, const mtlxgraph::ShadingPoint& at) : source_(std::move(source)), at_(at) {}

  [[noreturn]] void fail(const std::string& what) const { throw InputError(escape_control(source_ + ": " + what)); }

  // "FILE: line L: what", L the line where `node` starts in the document FILE holding it.
  [[noreturn]] void fail_at(const pugi::xml_node node, const std::string& what) const {
    const Loaded* d = doc_of(node);
    const size_t line = line_of(node);
    const std::string& file = d ? d->path : source_;
    if (line == 0) throw InputError(escape_control(file + ": " + what));
    throw InputError(escape_control(cat(file, ": line ", std::to_string(line), ": ", what)));
  }

  // Reads the document text `xml` (named source_), its xi:includes and, when
  // GONIO_MTLX_LIBRARIES names MaterialX's data library, its definitions.
  void load(std::string_view xml) {
    const pugi::xml_node root = load_doc(std::string(xml), source_, 0, false);
    read_version(root);
    if (const char* lib = std::getenv("GONIO_MTLX_LIBRARIES"); lib && *lib) load_library(lib);
  }

  std::vector<Surface> surfaces() const {
    std::vector<Surface> out;
    for (const pugi::xml_node n : top_)
      if (std::string_view(n.name()) == "surfacematerial") out.push_back({n.attribute("name").value(), n});
    if (!out.empty()) return out;
    for (const pugi::xml_node n : top_) {
      const std::string_view element = n.name();
      if (element == "nodegraph") {
        if (n.attribute("nodedef")) continue;  // a definition's implementation
        for (const pugi::xml_node o : n.children("output"))
          if (std::string_view(o.attribute("type").value()) == "surfaceshader")
            out.push_back({cat(n.attribute("name").value(), "/", o.attribute("name").value()), o});
      } else if (!is_structural(element) && std::string_view(n.attribute("type").value()) == "surfaceshader") {
        out.push_back({n.attribute("name").value(), n});
      }
    }
    return out;
  }

  json read(const std::optional<std::string>& name, std::string* note) {
    const std::vector<Surface> all = surfaces();
    std::map<std::string_view, const Surface*> by_name;
    for (const Surface& s : all) {
      const auto [it, fresh] = by_name.emplace(s.name, &s);
      if (!fresh)
        fail_at(s.node, cat("two surfaces are named ", in_quotes(s.name), " (", line_text(it->second->node), " and ",
                            line_text(s.node), ")"));
    }
    std::string names;  // for messages: the first ten
    for (size_t i = 0; i < all.size() && i < 10; ++i) names += cat(i ? ", " : "", in_quotes(all[i].name));
    if (all.size() > 10) names += cat(" and ", std::to_string(all.size() - 10), " more");
    const Surface* chosen = nullptr;
    if (name) {
      const auto it = by_name.find(*name);
      if (it == by_name.end())
        fail(cat("no surface named ", in_quotes(*name),
                 all.empty() ? std::string(" (the document has none)") : cat(" (its surfaces: ", names, ")")));
      chosen = it->second;
    } else {
      if (all.empty()) fail("the document has no surface (no surfacematerial, nodegraph surfaceshader output or surface shader node)");
      if (all.size() > 1) fail(cat("the document has several surfaces (", names, "): name the one to read"));
      chosen = &all[0];
    }
    json j = from_surface(*chosen);
    if (note) {
      note->clear();
      std::string list;
      for (const std::string& c : clamped_) list += cat(list.empty() ? "" : "; ", c);
      if (!list.empty()) *note = cat(source_, ": ", shader_text_, ": clamped to what the model takes: ", list);
      for (const std::string& n : notes_) *note += cat(note->empty() ? "" : "\n", source_, ": ", n);
      *note = escape_control(*note);
    }
    return j;
  }

 private:
  std::string source_;
  mtlxgraph::ShadingPoint at_;
  std::deque<Loaded> docs_;           // stable addresses: nodes point into them
  std::vector<pugi::xml_node> top_;   // the top-level elements, includes expanded in place
  std::vector<pugi::xml_node> lib_;   // the data library's top-level elements
  std::vector<std::string> include_stack_;  // canonical paths of the documents being included
  bool v138_ = false;                 // a version 1.38 document: the OpenPBR draft's names and units
  std::string shader_text_;           // the shader node read, for the note
  mutable std::vector<std::string> clamped_;  // "input V -> W (line L)" per clamped input
  std::vector<std::string> notes_;    // what was ignored (displacement, volume, shading normals)
  // The graph compiler's state.
  mtlxgraph::Program program_;
  std::deque<Frame> frames_;
  std::map<std::tuple<const void*, const Frame*, std::string>, Val> compiled_;
  std::set<std::tuple<const void*, const Frame*, std::string>> compiling_;
  std::optional<Val> texcoord_, position_, normal_;
  pugi::xml_node current_;  // the node being compiled, for "too large"
  mutable std::map<const void*, std::map<std::string_view, pugi::xml_node>> index_;  // named_in's
  // Values of generic material JSON waiting for the program's run: the JSON holds the
  // string kMarker + index until finish() writes the value.
  static constexpr char kMarker = '\x01';
  struct Pending {
    Val val;
    pugi::xml_node input;
    std::string what;
    std::string type;  // the input's MaterialX type
  };
  std::vector<Pending> pending_;

  const Loaded* doc_of(const pugi::xml_node node) const {
    const pugi::xml_node r = node.root();
    for (const Loaded& d : docs_)
      if (r == d.doc) return &d;
    return nullptr;
  }

  static size_t line_in(std::string_view text, size_t offset) {
    offset = std::min(offset, text.size());
    return 1 + size_t(std::count(text.begin(), text.begin() + std::ptrdiff_t(offset), '\n'));
  }
  // The line where `node` starts; 0 when pugixml cannot tell.
  size_t line_of(const pugi::xml_node node) const {
    const std::ptrdiff_t offset = node.offset_debug();
    const Loaded* d = doc_of(node);
    return offset < 0 || !d ? 0 : line_in(d->text, size_t(offset));
  }
  std::string line_text(const pugi::xml_node node) const { return cat("line ", std::to_string(line_of(node))); }
  // "FILE:LINE" of a node, for messages that name a place in another document.
  std::string file_line(const pugi::xml_node node) const {
    const Loaded* d = doc_of(node);
    return cat(d ? d->path : source_, ":", std::to_string(line_of(node)));
  }

  // Parses `text` (named `path`) and appends its top-level elements, its xi:includes
  // expanded where they stand. Returns its <materialx> root.
  pugi::xml_node load_doc(std::string text, const std::string& path, int depth, bool library) {
    Loaded& d = docs_.emplace_back();
    d.path = path;
    d.text = std::move(text);
    d.library = library;
    const std::string_view xml = d.text;
    const auto fail_in = [&](const std::string& what) { throw InputError(escape_control(path + ": " + what)); };
    // pugixml stops at a NUL byte, so whatever followed one would go unread; XML text
    // cannot hold one (XML 1.0 §2.2, Char).
    if (const size_t nul = xml.find('\0'); nul != std::string_view::npos)
      fail_in(cat("line ", std::to_string(line_in(xml, nul)), ": a NUL byte (at byte offset ", std::to_string(nul),
                  "): XML text cannot hold one"));
    const pugi::xml_parse_result parsed = d.doc.load_buffer(xml.data(), xml.size(), pugi::parse_default, pugi::encoding_utf8);
    if (!parsed) {
      const size_t at = std::min(size_t(parsed.offset), xml.size());
      fail_in(cat("malformed MaterialX document: ", parsed.description(), " at line ", std::to_string(line_in(xml, at))));
    }
    // pugixml reads a fragment; a document has one root element (XML 1.0 §2.1).
    pugi::xml_node root;
    for (const pugi::xml_node top : d.doc.children()) {
      if (top.type() != pugi::node_element) continue;
      if (root)
        fail_at(top, cat("malformed MaterialX document: a second root element <", excerpt(top.name()), "> after <",
                         excerpt(root.name()), "> (a document has one)"));
      root = top;
    }
    if (std::string_view(root.name()) != "materialx")
      fail_at(root, cat("not a MaterialX document: the root element is <", excerpt(root.name()), ">, not <materialx>"));
    refuse_nested_xinclude(root);
    std::vector<pugi::xml_node>& into = library ? lib_ : top_;
    for (const pugi::xml_node n : root.children()) {
      if (n.type() != pugi::node_element) continue;
      if (is_xinclude(n)) {
        include(n, path, depth);
        continue;
      }
      into.push_back(n);
    }
    return root;
  }

  // XInclude 1.0 (W3C, §3.1): the element's href names the document, relative to the
  // including one; its top-level elements take the element's place (MaterialX
  // Specification v1.39, "XInclude"). Nested at most kMaxIncludeDepth deep; a document
  // that includes itself, directly or not, is refused.
  void include(const pugi::xml_node n, const std::string& from, int depth) {
    const std::string where = cat("<", excerpt(n.name()), ">");
    const std::string href = n.attribute("href").value();
    if (href.empty()) fail_at(n, where + ": no href");
    if (const pugi::xml_attribute parse = n.attribute("parse"); parse && std::string_view(parse.value()) != "xml")
      fail_at(n, where + ": parse=" + in_quotes(parse.value()) + " is not supported (xml)");
    if (depth + 1 > kMaxIncludeDepth)
      fail_at(n, cat(where, " ", in_quotes(href), ": includes nested more than ", std::to_string(kMaxIncludeDepth), " deep"));
    std::filesystem::path p(href);
    if (p.is_relative()) p = std::filesystem::path(from).parent_path() / p;
    std::error_code ec;
    if (!std::filesystem::exists(p, ec))
      fail_at(n, cat(where, " ", in_quotes(href), ": no such document (", excerpt(p.string()), ")"));
    const std::string canonical = std::filesystem::weakly_canonical(p, ec).string();
    const std::string self = std::filesystem::weakly_canonical(std::filesystem::path(from), ec).string();
    if (include_stack_.empty()) include_stack_.push_back(self);
    for (const std::string& s : include_stack_)
      if (s == canonical) fail_at(n, cat(where, " ", in_quotes(href), ": an include cycle (the document includes itself)"));
    include_stack_.push_back(canonical);
    load_doc(read_text_file(p.string(), kMaxMaterialxFileBytes, "a MaterialX document"), p.string(), depth + 1, false);
    include_stack_.pop_back();
  }

  // MaterialX's data library (libraries/ of MaterialX 1.39, e.g. from the npm package
  // @needle-tools/materialx: docs/materialx.md): the definitions of stdlib, pbrlib and
  // bxdf, read for nodes gonio does not evaluate itself.
  void load_library(const std::string& dir) {
    for (const char* sub : {"stdlib", "pbrlib", "bxdf", "bxdf/lama"}) {
      std::error_code ec;
      std::vector<std::filesystem::path> files;
      for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(dir) / sub, ec))
        if (e.path().extension() == ".mtlx") files.push_back(e.path());
      std::sort(files.begin(), files.end());
      for (const auto& f : files)
        load_doc(read_text_file(f.string(), kMaxMaterialxFileBytes, "a MaterialX library document"), f.string(), 0, true);
    }
  }

  void read_version(const pugi::xml_node root) {
    const pugi::xml_attribute v = root.attribute("version");
    if (!v) fail_at(root, "<materialx> has no version attribute (1.38 or 1.39 expected)");
    const std::string_view text = v.value();
    const auto is = [&](std::string_view major_minor) {
      return text == major_minor ||
             (text.size() > major_minor.size() && text.substr(0, major_minor.size()) == major_minor &&
              text[major_minor.size()] == '.');
    };
    if (is("1.38")) {
      v138_ = true;
    } else if (!is("1.39")) {
      fail_at(root, cat("MaterialX version ", in_quotes(text), " is not supported (1.38 or 1.39)"));
    }
  }

  // An element is an XInclude when its name is xi:include (the prefix MaterialX writes,
  // declared or not), or `include` under a prefix (or the default namespace) that the
  // element or an ancestor binds to XInclude's namespace.
  static bool is_xinclude(const pugi::xml_node n) {
    if (n.type() != pugi::node_element) return false;
    const std::string_view name = n.name();
    const size_t colon = name.find(':');
    const std::string_view prefix = colon == std::string_view::npos ? "" : name.substr(0, colon);
    const std::string_view local = colon == std::string_view::npos ? name : name.substr(colon + 1);
    if (local != "include") return false;
    if (prefix == "xi") return true;
    const std::string declaration = prefix.empty() ? std::string("xmlns") : cat("xmlns:", prefix);
    for (pugi::xml_node up = n; up; up = up.parent())
      if (const pugi::xml_attribute a = up.attribute(declaration.c_str()))
        return std::string_view(a.value()) == kXIncludeNamespace;  // the nearest declaration binds the prefix
    return false;
  }

  // An XInclude below the top level (inside a nodegraph) is refused: MaterialX includes
  // whole documents at the top.
  void refuse_nested_xinclude(const pugi::xml_node root) const {
    struct Walker : pugi::xml_tree_walker {
      pugi::xml_node found;
      bool for_each(pugi::xml_node& n) override {
        if (depth() == 0 || !is_xinclude(n)) return true;
        found = n;
        return false;
      }
    } walker;
    pugi::xml_node scope = root;
    scope.traverse(walker);
    if (walker.found)
      fail_at(walker.found, cat("<", excerpt(walker.found.name()),
                                "> (an XInclude) inside an element is not supported (only at the top level)"));
  }

  static std::string element_text(const pugi::xml_node n) {
    return cat("<", excerpt(n.name()), "> ", in_quotes(n.attribute("name").value()));
  }

  // The element called `name` in a frame's scope: the graph's children, or the top level
  // (an index per scope, built on first use: graphs of thousands of nodes stay linear).
  pugi::xml_node named_in(const Frame& f, std::string_view name) const {
    const void* key = f.graph ? f.graph.internal_object() : nullptr;
    auto it = index_.find(key);
    if (it == index_.end()) {
      std::map<std::string_view, pugi::xml_node> idx;
      const auto consider = [&](const pugi::xml_node child) {
        if (child.type() != pugi::node_element || is_xinclude(child)) return;
        const std::string_view n = child.attribute("name").value();
        if (n.empty()) return;
        const auto [at, fresh] = idx.emplace(n, child);
        // A nodedef and its nodegraph, or an output and a node, may not share a name either.
        if (!fresh)
          fail_at(child, cat("two elements are named ", in_quotes(n), " (", file_line(at->second), " and ", file_line(child), ")"));
      };
      if (f.graph) {
        for (const pugi::xml_node child : f.graph.children()) consider(child);
      } else {
        for (const pugi::xml_node child : top_) consider(child);
      }
      it = index_.emplace(key, std::move(idx)).first;
    }
    const auto found = it->second.find(name);
    return found == it->second.end() ? pugi::xml_node() : found->second;
  }

  const Frame& top_frame() {
    if (frames_.empty()) frames_.emplace_back();
    return frames_.front();
  }

  json from_surface(const Surface& s) {
    const Frame& top = top_frame();
    json j;
    if (std::string_view(s.node.name()) == "surfacematerial") {
      j = from_material(s.node);
    } else if (std::string_view(s.node.name()) == "output") {
      Frame& g = frames_.emplace_back();
      g.graph = s.node.parent();
      g.parent = &top;
      j = closure_from_connection(s.node, g, element_text(s.node), 0);
    } else {
      j = closure_json(s.node, top, 0);
    }
    finish(j);
    return j;
  }

  // Runs the program at the shading point: the registers.
  std::vector<mtlxgraph::Reg> evaluate() const {
    std::vector<mtlxgraph::Reg> regs(program_.register_count());
    program_.run(at_, regs);
    return regs;
  }

  // A pending value's lanes, checked finite.
  std::array<double, 4> pending_value(const Pending& p, const std::vector<mtlxgraph::Reg>& regs) const {
    const mtlxgraph::Reg& r = regs[p.val.reg];
    for (int i = 0; i < p.val.width; ++i)
      if (!std::isfinite(r[size_t(i)]))
        fail_at(p.input, cat(p.what, ": the graph's value at uv (", format_number(at_.u), ", ", format_number(at_.v),
                             ") is not finite"));
    return r;
  }

  // Runs the program once and replaces each pending marker of `j` by its value.
  void finish(json& j) {
    if (pending_.empty()) return;
    const std::vector<mtlxgraph::Reg> regs = evaluate();
    const auto walk = [&](auto&& self, json& x) -> void {
      if (x.is_structured()) {
        for (auto& e : x) self(self, e);
        return;
      }
      if (!x.is_string()) return;
      const std::string& s = x.get_ref<const std::string&>();
      if (s.empty() || s[0] != kMarker) return;
      const Pending& p = pending_[std::stoul(s.substr(1))];
      const auto r = pending_value(p, regs);
      if (p.type == "boolean") {
        x = r[0] != 0;
      } else if (p.type == "integer") {
        x = std::llround(r[0]);
      } else if (p.val.width == 1) {
        x = r[0];
      } else {
        x = json::array();
        for (int i = 0; i < p.val.width; ++i) x.push_back(r[size_t(i)]);
      }
    };
    walk(walk, j);
  }

  json from_material(const pugi::xml_node material) {
    const std::string where = element_text(material);
    if (const pugi::xml_attribute t = material.attribute("type"); t && std::string_view(t.value()) != "material")
      fail_at(material, where + ": type must be \"material\", got " + in_quotes(t.value()));
    pugi::xml_node shader_input;
    for (const pugi::xml_node child : material.children()) {
      if (child.type() != pugi::node_element) continue;
      const std::string_view input = child.attribute("name").value();
      if (std::string_view(child.name()) != "input") fail_at(child, where + ": unsupported element <" + excerpt(child.name()) + ">");
      if (input == "surfaceshader") {
        if (shader_input) fail_at(child, where + ": input surfaceshader is given twice");
        shader_input = child;
      } else if (input == "displacementshader" || input == "volumeshader") {
        // SPEC §2: displacement and volumes are ignored, with one note.
        if (child.attribute("nodename") || child.attribute("nodegraph"))
          notes_.push_back(cat(where, ": input ", input, " ignored (", line_text(child), ")"));
      } else if (input == "backsurfaceshader") {
        if (child.attribute("nodename") || child.attribute("nodegraph") || child.attribute("value").value()[0] != '\0')
          fail_at(child, where + ": input backsurfaceshader is not supported (one surface shader for both sides)");
      } else {
        fail_at(child, where + ": unknown input " + in_quotes(input) + " (surfaceshader expected)");
      }
    }
    if (!shader_input) fail_at(material, where + ": no surfaceshader input");
    return closure_from_connection(shader_input, top_frame(), where + ": input surfaceshader", 0);
  }

  // The graph's output element that a `nodegraph` (+ `output`) connection names.
  pugi::xml_node graph_output(const pugi::xml_node at, const pugi::xml_node g, const pugi::xml_attribute want,
                              const std::string& where) const {
    const std::string gwhere = element_text(g);
    std::vector<pugi::xml_node> outputs;
    for (const pugi::xml_node o : g.children("output")) outputs.push_back(o);
    if (want) {
      for (const auto& o : outputs)
        if (std::string_view(o.attribute("name").value()) == want.value()) return o;
      fail_at(at, cat(where, ": ", gwhere, " has no output named ", in_quotes(want.value())));
    }
    if (outputs.size() != 1) fail_at(at, cat(where, ": ", gwhere, " has ", std::to_string(outputs.size()), " outputs, and the input names none"));
    return outputs[0];
  }

  // The element a connection names, with the frame it is read in: `in` is an input or
  // output element read in frame `f`. Returns a null node when nothing is connected.
  // `output` receives the output name of a multi-output node.
  std::pair<pugi::xml_node, const Frame*> connected(const pugi::xml_node in, const Frame& f, const std::string& where,
                                                    std::string* output, int depth) {
    if (depth > kMaxGraphDepth)
      fail_at(in, cat(where, ": the graph is nested more than ", std::to_string(kMaxGraphDepth), " deep"));
    const pugi::xml_attribute nodename = in.attribute("nodename"), graph = in.attribute("nodegraph"),
                              iface = in.attribute("interfacename");
    if (int(bool(nodename)) + int(bool(graph)) + int(bool(iface)) > 1)
      fail_at(in, where + ": more than one of nodename, nodegraph and interfacename");
    if (nodename) {
      const pugi::xml_node node = named_in(f, nodename.value());
      if (!node || is_structural(node.name())) fail_at(in, cat(where, ": no node named ", in_quotes(nodename.value())));
      if (output) *output = in.attribute("output").value();
      return {node, &f};
    }
    if (graph) {
      const pugi::xml_node g = named_in(top_frame(), graph.value());
      if (!g || std::string_view(g.name()) != "nodegraph") fail_at(in, where + ": no nodegraph named " + in_quotes(graph.value()));
      const pugi::xml_node o = graph_output(in, g, in.attribute("output"), where);
      Frame& gf = frames_.emplace_back();
      gf.graph = g;
      gf.parent = &top_frame();
      return connected(o, gf, cat(element_text(g), ": output ", in_quotes(o.attribute("name").value())), output, depth + 1);
    }
    if (iface) {
      if (!f.graph) fail_at(in, where + ": interfacename " + in_quotes(iface.value()) + " outside a nodegraph");
      if (f.instance) {
        // The node instance's own input of that name, read where the instance is.
        for (const pugi::xml_node i : f.instance.children("input"))
          if (std::string_view(i.attribute("name").value()) == iface.value())
            return {i, f.parent};
        for (const pugi::xml_node i : f.nodedef.children("input"))
          if (std::string_view(i.attribute("name").value()) == iface.value()) return {i, &f};
        fail_at(in, cat(where, ": interfacename ", in_quotes(iface.value()), " is not an input of ", element_text(f.nodedef)));
      }
      for (const pugi::xml_node i : f.graph.children("input"))
        if (std::string_view(i.attribute("name").value()) == iface.value()) return {i, f.parent ? f.parent : &top_frame()};
      fail_at(in, cat(where, ": interfacename ", in_quotes(iface.value()), " is not an input of ", element_text(f.graph)));
    }
    if (std::string_view(in.name()) == "output") fail_at(in, where + ": an output that names no node");
    return {pugi::xml_node(), &f};
  }

  // ---- Closures: surface shaders and BSDFs become gonio material JSON ----------------

  // The closure an input or output leads to, as material JSON.
  json closure_from_connection(const pugi::xml_node in, const Frame& f, const std::string& where, int depth) {
    pugi::xml_node at = in;
    const Frame* frame = &f;
    std::string w = where;
    // Follow interface inputs until an element that is a node or holds no connection.
    for (int guard = 0;; ++guard) {
      const auto [target, tf] = connected(at, *frame, w, nullptr, depth + guard);
      if (!target) fail_at(at, w + ": not connected (a nodename or nodegraph attribute expected)");
      if (std::string_view(target.name()) == "input") {
        at = target;
        frame = tf;
        w = cat(w, " -> input ", in_quotes(target.attribute("name").value()));
        continue;
      }
      return closure_json(target, *tf, depth + 1);
    }
  }

  json closure_json(const pugi::xml_node node, const Frame& f, int depth) {
    if (depth > kMaxGraphDepth) fail_at(node, cat(element_text(node), ": the graph is nested more than ", std::to_string(kMaxGraphDepth), " deep"));
    const std::string category = node.name();
    const std::string where = element_text(node);
    if (category == "open_pbr_surface" || category == "standard_surface") return from_shader(node, f);
    if (category == "dot") {
      for (const pugi::xml_node i : node.children("input"))
        if (std::string_view(i.attribute("name").value()) == "in") return closure_from_connection(i, f, where + ": input in", depth);
      fail_at(node, where + ": no input in");
    }
    if (category == "surface") return surface_json(node, f, depth);
    if (find_material_type(category)) return generic_json(node, f, depth);
    // A node that a definition's nodegraph implements (the document's own, or the data
    // library's).
    if (const auto [nodedef, graph] = implementation(node); graph) {
      Frame& g = frames_.emplace_back();
      g.graph = graph;
      g.instance = node;
      g.nodedef = nodedef;
      g.parent = &f;
      const pugi::xml_node o = graph_output(node, graph, node.attribute("output"), where);
      return closure_from_connection(o, g, cat(element_text(graph), ": output ", in_quotes(o.attribute("name").value())), depth + 1);
    }
    fail_at(node, cat(where, ": unsupported node (category ", in_quotes(category), ", type ", in_quotes(node.attribute("type").value()), ")"));
  }

  // pbrlib's `surface`: the BSDF its `bsdf` input names, as it is when nothing else is
  // given; else {"type": "surface", "bsdf", "edf", "opacity"}.
  json surface_json(const pugi::xml_node node, const Frame& f, int depth) {
    json j = json::object();
    j["type"] = "surface";
    for (const pugi::xml_node i : node.children("input")) {
      const std::string name = i.attribute("name").value();
      const std::string iwhere = cat(element_text(node), ": input ", excerpt(name));
      if (name == "bsdf" || name == "edf") {
        if (i.attribute("nodename") || i.attribute("nodegraph") || i.attribute("interfacename"))
          j[name] = closure_from_connection(i, f, iwhere, depth);
      } else if (name == "opacity") {
        value_into(i, f, iwhere, 1, j[name], depth);
      } else if (name == "thin_walled") {
        value_into(i, f, iwhere, 1, j[name], depth);
      } else {
        fail_at(i, iwhere + ": not an input of surface (bsdf, edf, opacity, thin_walled)");
      }
    }
    bool opaque = true;  // no opacity input, or the constant 1
    for (const pugi::xml_node i : node.children("input"))
      if (std::string_view(i.attribute("name").value()) == "opacity")
        opaque = !i.attribute("nodename") && !i.attribute("nodegraph") && !i.attribute("interfacename") &&
                 std::strtod(i.attribute("value").value(), nullptr) == 1.0;
    const bool plain = j.contains("bsdf") && !j.contains("edf") && opaque && !j.contains("thin_walled");
    return plain ? json(j["bsdf"]) : j;
  }

  // A node of a gonio material type of the same name (SPEC §2, wave 4): its inputs under
  // their MaterialX names; closure inputs as nested materials, values (constant or
  // computed by the graph at the shading point) as numbers, arrays, booleans, strings.
  json generic_json(const pugi::xml_node node, const Frame& f, int depth) {
    json j = json::object();
    j["type"] = node.name();
    for (const pugi::xml_node i : node.children()) {
      if (i.type() != pugi::node_element) continue;
      const std::string iwhere = cat(element_text(node), ": input ", excerpt(i.attribute("name").value()));
      if (std::string_view(i.name()) != "input") fail_at(i, cat(element_text(node), ": unsupported element <", excerpt(i.name()), ">"));
      const std::string name = i.attribute("name").value();
      const std::string_view type = i.attribute("type").value();
      const bool linked = i.attribute("nodename") || i.attribute("nodegraph") || i.attribute("interfacename");
      if (is_closure_type(type)) {
        if (linked) j[name] = closure_from_connection(i, f, iwhere, depth);
        continue;
      }
      if ((name == "normal" || name == "tangent" || name == "coat_normal") && type == "vector3") {
        // The shading frame is the caller's (a BSDF works in its local frame).
        if (linked) notes_.push_back(cat(iwhere, " ignored: the shading frame is the caller's (", line_text(i), ")"));
        continue;
      }
      if (type == "string" || type == "filename") {
        if (linked) fail_at(i, iwhere + ": a connected string is not supported");
        j[name] = i.attribute("value").value();
        continue;
      }
      const int w = width_of(type);
      if (w == 0) fail_at(i, cat(iwhere, ": type ", in_quotes(type), " is not supported"));
      value_into(i, f, iwhere, w, j[name], depth);
    }
    return j;
  }

  // Writes an input's value into `out`: its constant now, or its graph's value after
  // the program runs (finish()).
  void value_into(const pugi::xml_node i, const Frame& f, const std::string& iwhere, int width, json& out, int depth) {
    const Val v = compile_input(i, f, iwhere, width, depth);
    out = cat(std::string(1, kMarker), std::to_string(pending_.size()));
    pending_.push_back(Pending{v, i, iwhere, i.attribute("type").value()});
  }

  // ---- The graph compiler: values of stdlib nodes, into program_ -----------------------

  using Reg = mtlxgraph::Reg;
  using Op = mtlxgraph::Op;

  // Refuses a program grown past its bounds (an enormous graph), naming where it grew.
  void room(const pugi::xml_node at) const {
    if (program_.size() >= mtlxgraph::kMaxInstructions || program_.register_count() >= mtlxgraph::kMaxRegisters)
      fail_at(at, cat("the graph is too large (more than ", std::to_string(mtlxgraph::kMaxInstructions), " operations or ",
                      std::to_string(mtlxgraph::kMaxRegisters), " values)"));
  }

  Val constant(const Reg& r, int width) {
    room(current_);
    return Val{program_.constant(r), width};
  }
  Val splat(double x) { return constant(Reg{x, x, x, x}, 1); }

  Val emit(Op op, std::initializer_list<Val> in, int width, std::uint32_t aux = 0) {
    room(current_);
    mtlxgraph::Instr I;
    I.op = op;
    I.aux = aux;
    size_t k = 0;
    for (const Val& v : in) I.in[k++] = v.reg;
    return Val{program_.emit(I), width};
  }

  // A lane selection: out lane i = in lane sel[i] (width lanes), as MaterialX's
  // swizzle/extract/channels do; one lane is splatted, as floats are held.
  Val swizzle(const Val v, const std::array<int, 4>& sel, int width) {
    std::uint32_t aux = 0;
    for (size_t i = 0; i < 4; ++i) aux |= std::uint32_t(sel[width == 1 ? 0 : std::min<size_t>(i, 3)] & 3) << (2 * i);
    return emit(Op::Swizzle, {v}, width, aux);
  }

  Val texcoord() { return texcoord_ ? *texcoord_ : *(texcoord_ = emit(Op::Texcoord, {}, 2)); }

  // A geometric property's value (MaterialX's defaultgeomprop names).
  Val geomprop(std::string_view name, const pugi::xml_node at, const std::string& where) {
    if (name == "UV0") return texcoord();
    if (name == "Pobject" || name == "Pworld") return position_ ? *position_ : *(position_ = emit(Op::Position, {}, 3));
    if (name == "Nobject" || name == "Nworld") return normal_ ? *normal_ : *(normal_ = emit(Op::Normal, {}, 3));
    if (name == "Tobject" || name == "Tworld") return constant(Reg{1, 0, 0, 0}, 3);
    if (name == "Bobject" || name == "Bworld") return constant(Reg{0, 1, 0, 0}, 3);
    fail_at(at, cat(where, ": geometric property ", in_quotes(name), " is not supported"));
  }

  // A value written in the document: `type`'s lanes, colours converted to linear Rec.709.
  Val parse_value(const pugi::xml_node at, std::string_view type, std::string_view text, const std::string& where) {
    const int w = width_of(type);
    if (type == "boolean") {
      if (text == "true") return splat(1);
      if (text == "false") return splat(0);
      fail_at(at, where + ": value " + in_quotes(text) + " is not a boolean (true or false)");
    }
    std::vector<double> parts;
    size_t start = 0;
    while (true) {
      const size_t comma = text.find(',', start);
      parts.push_back(parse_number(text.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start), at, where));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    if (int(parts.size()) != w)
      fail_at(at, cat(where, ": value ", in_quotes(text), " is not a ", type, " (", std::to_string(w), " number", w > 1 ? "s" : "", ")"));
    Reg r{};
    for (size_t i = 0; i < 4; ++i) r[i] = parts[std::min(i, parts.size() - 1)];
    if (w == 1) return constant(r, 1);
    if (type == "color3" || type == "color4") {
      const Rgb c = to_lin_rec709(Rgb{r[0], r[1], r[2]}, colorspace_of(at), at, where);
      r = {c[0], c[1], c[2], w == 4 ? r[3] : 0};
    } else if (w < 4) {
      for (size_t i = size_t(w); i < 4; ++i) r[i] = 0;
    }
    return constant(r, w);
  }

  // The colour space of an input: its own attribute, else the nearest enclosing
  // element's (MaterialX scoping), else the default lin_rec709.
  static std::string colorspace_of(pugi::xml_node n) {
    for (; n; n = n.parent())
      if (const pugi::xml_attribute cs = n.attribute("colorspace")) return cs.value();
    return "lin_rec709";
  }

  // An input's value: connected (a node, a graph's output, an interface input), or its
  // value, or its definition's geometric default. `width` is what the reader wants
  // (0: the input's own); a float widens (held splatted), nothing narrows.
  Val compile_input(const pugi::xml_node in, const Frame& f, const std::string& where, int width, int depth) {
    std::string output;
    const auto [target, tf] = connected(in, f, where, &output, depth);
    Val v;
    if (target && std::string_view(target.name()) == "input") {
      v = compile_input(target, *tf, cat(where, " -> input ", in_quotes(target.attribute("name").value())), width, depth + 1);
    } else if (target) {
      v = compile_node(target, output, *tf, depth + 1);
    } else if (const pugi::xml_attribute value = in.attribute("value")) {
      v = parse_value(in, in.attribute("type").value(), value.value(), where);
    } else if (const pugi::xml_attribute g = in.attribute("defaultgeomprop")) {
      v = geomprop(g.value(), in, where);
    } else {
      fail_at(in, where + ": no value and no connection");
    }
    if (const pugi::xml_attribute ch = in.attribute("channels"); ch && *ch.value()) v = channels(v, ch.value(), in, where);
    if (width != 0 && v.width != width && v.width != 1)
      fail_at(in, cat(where, ": a value of ", std::to_string(v.width), " channels where ", std::to_string(width), " are expected"));
    return v;
  }

  // MaterialX 1.38's `channels` (and the swizzle node's): letters rgba / xyzw, 0, 1.
  Val channels(const Val v, std::string_view spec, const pugi::xml_node at, const std::string& where) {
    if (spec.empty() || spec.size() > 4) fail_at(at, cat(where, ": channels ", in_quotes(spec), " (1 to 4 of rgba or xyzw)"));
    std::array<int, 4> sel{};
    for (size_t i = 0; i < spec.size(); ++i) {
      const size_t k = std::string_view("rgbaxyzw").find(spec[i]);
      if (k == std::string_view::npos || int(k % 4) >= std::max(v.width, 1) + (v.width == 1 ? 3 : 0))
        fail_at(at, cat(where, ": channels ", in_quotes(spec), " (letters of rgba or xyzw within the value's ", std::to_string(v.width), ")"));
      sel[i] = int(k % 4);
    }
    for (size_t i = spec.size(); i < 4; ++i) sel[i] = sel[spec.size() - 1];
    return swizzle(v, sel, int(spec.size()));
  }

  // The nodedef of `node` and the nodegraph implementing it, searched in the document and
  // its includes, then the data library; matched by category and output type.
  std::pair<pugi::xml_node, pugi::xml_node> implementation(const pugi::xml_node node) const {
    const std::string_view category = node.name(), type = node.attribute("type").value();
    const std::string_view wanted = node.attribute("nodedef").value();
    for (const std::vector<pugi::xml_node>* scope : {&top_, &lib_}) {
      for (const pugi::xml_node d : *scope) {
        if (std::string_view(d.name()) != "nodedef" || std::string_view(d.attribute("node").value()) != category) continue;
        const std::string_view dname = d.attribute("name").value();
        if (!wanted.empty() && dname != wanted) continue;
        bool type_ok = wanted.empty() ? false : true;
        for (const pugi::xml_node o : d.children("output"))
          if (std::string_view(o.attribute("type").value()) == type) type_ok = true;
        if (std::string_view(d.attribute("type").value()) == type) type_ok = true;  // 1.37-style
        if (!type_ok) continue;
        if (!inputs_match(node, d)) continue;
        for (const std::vector<pugi::xml_node>* s2 : {&top_, &lib_})
          for (const pugi::xml_node g : *s2)
            if (std::string_view(g.name()) == "nodegraph" && dname == g.attribute("nodedef").value()) return {d, g};
      }
    }
    return {};
  }

  // Every typed input of the node is an input of the definition with the same type.
  static bool inputs_match(const pugi::xml_node node, const pugi::xml_node def) {
    for (const pugi::xml_node i : node.children("input")) {
      bool found = false;
      for (const pugi::xml_node d : def.children("input"))
        if (std::string_view(d.attribute("name").value()) == i.attribute("name").value()) {
          const std::string_view t = i.attribute("type").value();
          found = t.empty() || t == d.attribute("type").value();
        }
      if (!found) return false;
    }
    return true;
  }

  // A node's value (its output `output` for multi-output nodes), compiled once per frame.
  Val compile_node(const pugi::xml_node node, const std::string& output, const Frame& f, int depth) {
    const std::string where = element_text(node);
    if (depth > kMaxGraphDepth) fail_at(node, cat(where, ": the graph is nested more than ", std::to_string(kMaxGraphDepth), " deep"));
    const auto key = std::make_tuple(static_cast<const void*>(node.internal_object()), &f, output);
    if (const auto it = compiled_.find(key); it != compiled_.end()) return it->second;
    if (!compiling_.insert(key).second) fail_at(node, where + ": a cycle (the node's value depends on itself)");
    const Val v = compile_node_once(node, output, f, where, depth);
    compiling_.erase(key);
    compiled_[key] = v;
    return v;
  }

  Val compile_node_once(const pugi::xml_node node, const std::string& output, const Frame& f, const std::string& where,
                        int depth) {
    current_ = node;
    const std::string category = node.name();
    const std::string_view type = node.attribute("type").value();
    const int w = type == "multioutput" ? 0 : width_of(type);
    if (w == 0 && type != "multioutput")
      fail_at(node, cat(where, ": type ", in_quotes(type), " where a value is expected (category ", in_quotes(category), ")"));
    // An input of this node, or its default (a float default splats into any width).
    const auto in = [&](std::string_view name, std::optional<Reg> def, int width = 0) -> Val {
      for (const pugi::xml_node i : node.children("input"))
        if (std::string_view(i.attribute("name").value()) == name)
          return compile_input(i, f, cat(where, ": input ", excerpt(name)), width, depth);
      if (!def) fail_at(node, cat(where, ": input ", name, " is required"));
      return constant(*def, 1);
    };
    const auto num = [](double x) { return std::optional<Reg>(Reg{x, x, x, x}); };
    const auto uv = [&](std::string_view name) -> Val {
      for (const pugi::xml_node i : node.children("input"))
        if (std::string_view(i.attribute("name").value()) == name) return compile_input(i, f, cat(where, ": input ", name), 2, depth);
      return texcoord();
    };
    const auto unary = [&](Op op) { return emit(op, {in("in", num(0))}, w); };
    const auto binary = [&](Op op, double d1, double d2) { return emit(op, {in("in1", num(d1)), in("in2", num(d2))}, w); };
    // A constant integer input (extract's index, separate's outputs).
    const auto uniform_int = [&](std::string_view name, int def) -> int {
      for (const pugi::xml_node i : node.children("input"))
        if (std::string_view(i.attribute("name").value()) == name) {
          if (i.attribute("nodename") || i.attribute("nodegraph") || i.attribute("interfacename"))
            fail_at(i, cat(where, ": input ", name, " must be a constant"));
          return int(parse_number(i.attribute("value").value(), i, cat(where, ": input ", name)));
        }
      return def;
    };

    // Standard Nodes (MaterialX Specification v1.39): defaults of each nodedef
    // (libraries/stdlib/stdlib_defs.mtlx).
    if (category == "constant") return in("value", num(0), w);
    if (category == "dot") return in("in", num(0), w);
    if (category == "add") return binary(Op::Add, 0, 0);
    if (category == "subtract") return binary(Op::Subtract, 0, 0);
    if (category == "multiply") return binary(Op::Multiply, 0, 1);
    if (category == "divide") return binary(Op::Divide, 0, 1);
    if (category == "modulo") return binary(Op::Modulo, 0, 1);
    if (category == "power") return binary(Op::Power, 0, 1);
    if (category == "min") return binary(Op::Min, 0, 0);
    if (category == "max") return binary(Op::Max, 0, 0);
    if (category == "clamp") return emit(Op::Clamp, {in("in", num(0)), in("low", num(0)), in("high", num(1))}, w);
    if (category == "mix") return emit(Op::Mix, {in("bg", num(0)), in("fg", num(0)), in("mix", num(0))}, w);
    if (category == "absval") return unary(Op::Absval);
    if (category == "sign") return unary(Op::Sign);
    if (category == "floor") return unary(Op::Floor);
    if (category == "ceil") return unary(Op::Ceil);
    if (category == "round") return unary(Op::Round);
    if (category == "sqrt") return unary(Op::Sqrt);
    if (category == "sin") return unary(Op::Sin);
    if (category == "cos") return unary(Op::Cos);
    if (category == "tan") return unary(Op::Tan);
    if (category == "asin") return unary(Op::Asin);
    if (category == "acos") return unary(Op::Acos);
    if (category == "exp") return unary(Op::Exp);
    if (category == "ln") return unary(Op::Ln);
    if (category == "atan2") return emit(Op::Atan2, {in("iny", num(0)), in("inx", num(1))}, w);
    if (category == "invert") return emit(Op::Invert, {in("in", num(0)), in("amount", num(1))}, w);
    if (category == "smoothstep") return emit(Op::Smoothstep, {in("in", num(0)), in("low", num(0)), in("high", num(1))}, w);
    if (category == "dotproduct") {
      const Val a = in("in1", num(0)), b = in("in2", num(0));
      return emit(Op::Dot, {a, b}, 1, std::uint32_t(std::max(a.width, b.width)));
    }
    if (category == "magnitude" || category == "normalize") {
      const Val a = in("in", num(0));
      return emit(category == "magnitude" ? Op::Magnitude : Op::Normalize, {a}, category == "magnitude" ? 1 : a.width,
                  std::uint32_t(a.width));
    }
    if (category == "extract") {
      const Val a = in("in", num(0));
      const int k = uniform_int("index", 0);
      if (k < 0 || k >= std::max(a.width, 1)) fail_at(node, cat(where, ": index ", std::to_string(k), " outside the input's ", std::to_string(a.width), " channels"));
      return swizzle(a, {k, k, k, k}, 1);
    }
    if (category == "separate2" || category == "separate3" || category == "separate4") {
      const Val a = in("in", num(0));
      const size_t k = std::string_view("rgbaxyzw").find(output.size() == 4 && output.substr(0, 3) == "out" ? output[3] : '?');
      if (k == std::string_view::npos || int(k % 4) >= category.back() - '0')
        fail_at(node, cat(where, ": output ", in_quotes(output), " (outr/outg/outb/outa or outx/outy/outz/outw)"));
      const int c = int(k % 4);
      return swizzle(a, {c, c, c, c}, 1);
    }
    if (category == "combine2" || category == "combine3" || category == "combine4") {
      const Val zero = splat(0);
      const int n = category.back() - '0';
      const Val a = in("in1", num(0)), b = in("in2", num(0)), c = n > 2 ? in("in3", num(0)) : zero, d = n > 3 ? in("in4", num(0)) : zero;
      // combine2 of a vector2 pair into a vector4 (combine2_vector4VA) is not read.
      if (a.width > 1 || b.width > 1) fail_at(node, where + ": combining non-float inputs is not supported");
      return emit(Op::Combine, {a, b, c, d}, w);
    }
    if (category == "convert") {
      const Val a = in("in", num(0));
      if (a.width == 1 || a.width == w) return a;
      if (a.width == 3 && w == 4) {  // convert_color3_color4: alpha 1
        const Val one = splat(1);
        return emit(Op::Combine, {swizzle(a, {0, 0, 0, 0}, 1), swizzle(a, {1, 1, 1, 1}, 1), swizzle(a, {2, 2, 2, 2}, 1), one}, 4);
      }
      return swizzle(a, {0, 1, 2, 3}, w);  // dropping channels (color4 → color3, vector3 → vector2)
    }
    if (category == "swizzle") {
      std::string spec;
      for (const pugi::xml_node i : node.children("input"))
        if (std::string_view(i.attribute("name").value()) == "channels") spec = i.attribute("value").value();
      return channels(in("in", num(0)), spec, node, where);
    }
    if (category == "texcoord") return texcoord();
    if (category == "position") return geomprop("Pobject", node, where);
    if (category == "normal") return geomprop("Nobject", node, where);
    if (category == "rotate2d") return emit(Op::Rotate2d, {in("in", num(0), 2), in("amount", num(0))}, 2);
    if (category == "place2d") {
      // NG_place2d_vector2: operationorder 0: ((tc − pivot)/scale, rotated) − offset + pivot;
      // 1: ((tc − pivot − offset) rotated)/scale + pivot.
      const Val tc = uv("texcoord"), pivot = in("pivot", num(0), 2), scale = in("scale", num(1), 2),
                rot = in("rotate", num(0)), offset = in("offset", num(0), 2);
      const int order = uniform_int("operationorder", 0);
      const Val centred = emit(Op::Subtract, {tc, pivot}, 2);
      if (order == 0) {
        const Val r = emit(Op::Rotate2d, {emit(Op::Divide, {centred, scale}, 2), rot}, 2);
        return emit(Op::Add, {emit(Op::Subtract, {r, offset}, 2), pivot}, 2);
      }
      const Val r = emit(Op::Rotate2d, {emit(Op::Subtract, {centred, offset}, 2), rot}, 2);
      return emit(Op::Add, {emit(Op::Divide, {r, scale}, 2), pivot}, 2);
    }
    if (category == "ramplr") return emit(Op::Ramplr, {in("valuel", num(0)), in("valuer", num(0)), uv("texcoord")}, w);
    if (category == "ramptb") return emit(Op::Ramptb, {in("valuet", num(0)), in("valueb", num(0)), uv("texcoord")}, w);
    if (category == "ramp4")
      return emit(Op::Ramp4, {in("valuetl", num(0)), in("valuetr", num(0)), in("valuebl", num(0)), in("valuebr", num(0)), uv("texcoord")}, w);
    if (category == "splitlr")
      return emit(Op::Splitlr, {in("valuel", num(0)), in("valuer", num(0)), in("center", num(0.5)), uv("texcoord")}, w);
    if (category == "splittb")
      return emit(Op::Splittb, {in("valuet", num(0)), in("valueb", num(0)), in("center", num(0.5)), uv("texcoord")}, w);
    if (category == "ifgreater" || category == "ifgreatereq" || category == "ifequal") {
      const Op op = category == "ifgreater" ? Op::IfGreater : category == "ifgreatereq" ? Op::IfGreaterEq : Op::IfEqual;
      const double v1 = category == "ifequal" ? 0 : 1;
      return emit(op, {in("value1", num(v1)), in("value2", num(0)), in("in1", num(0)), in("in2", num(0))}, w);
    }
    if (category == "switch") {
      // switch: which (default 0) picks in1..in5 (MaterialX 1.39: five inputs).
      const Val which = in("which", num(0));
      mtlxgraph::Instr I;
      I.op = Op::Switch;
      I.aux = 5;
      I.in[0] = which.reg;
      for (size_t k = 0; k < 5; ++k) I.in[1 + k] = in(cat("in", std::to_string(k + 1)), num(0)).reg;
      room(node);
      return Val{program_.emit(I), w};
    }
    if (category == "luminance")
      return emit(Op::Luminance, {in("in", num(0)), in("lumacoeffs", Reg{0.2722287, 0.6740818, 0.0536895, 0})}, w);
    if (category == "image" || category == "tiledimage" || category == "hextiledimage" || category == "UsdUVTexture" ||
        category == "gltf_image" || category == "gltf_colorimage" || category == "gltf_normalmap") {
      for (const pugi::xml_node i : node.children("input")) {
        const std::string_view t = i.attribute("type").value();
        if (t == "filename") {
          std::string file;
          if (i.attribute("interfacename")) {
            const auto [target, tf] = connected(i, f, where, nullptr, depth);
            file = target.attribute("value").value();
            resolve_image(file, target, node);
          } else {
            resolve_image(i.attribute("value").value(), i, node);
          }
        }
      }
      fail_at(node, cat(where, ": image lookups are not in this build yet (category ", in_quotes(category), ")"));
    }
    // A node that a definition's nodegraph implements (the document's, or the library's).
    if (const auto [nodedef, graph] = implementation(node); graph) {
      Frame& g = frames_.emplace_back();
      g.graph = graph;
      g.instance = node;
      g.nodedef = nodedef;
      g.parent = &f;
      pugi::xml_attribute want;
      pugi::xml_node o;
      if (!output.empty()) {
        for (const pugi::xml_node x : graph.children("output"))
          if (output == x.attribute("name").value()) o = x;
        if (!o) fail_at(node, cat(where, ": ", element_text(graph), " has no output ", in_quotes(output)));
      } else {
        o = graph_output(node, graph, want, where);
      }
      std::string out2;
      const auto [target, tf] = connected(o, g, cat(element_text(graph), ": output"), &out2, depth + 1);
      if (!target) fail_at(o, cat(element_text(graph), ": output ", in_quotes(o.attribute("name").value()), " names no node"));
      if (std::string_view(target.name()) == "input")
        return compile_input(target, *tf, cat(element_text(graph), ": output"), w, depth + 1);
      return compile_node(target, out2, *tf, depth + 1);
    }
    fail_at(node, cat(where, ": unsupported node (category ", in_quotes(category), ", type ", in_quotes(type), ")"));
  }

  // SPEC §2: an image's path is its fileprefix (inherited) + its value, found relative to
  // the document's folder, then each ancestor folder, then each folder of
  // GONIO_MTLX_SEARCH_PATH. Missing: "image not found: PATH (node NODE, FILE:LINE)".
  std::string resolve_image(const std::string& value, const pugi::xml_node input, const pugi::xml_node node) const {
    std::string prefix;
    for (pugi::xml_node n = input; n; n = n.parent())
      if (const pugi::xml_attribute p = n.attribute("fileprefix")) {
        prefix = p.value();
        break;
      }
    const std::filesystem::path rel(prefix + value);
    std::error_code ec;
    const auto found = [&](const std::filesystem::path& p) { return std::filesystem::is_regular_file(p, ec); };
    if (value.empty()) fail_at(input, cat(element_text(node), ": input ", in_quotes(input.attribute("name").value()), ": no file"));
    if (rel.is_absolute()) {
      if (found(rel)) return rel.string();
    } else {
      const Loaded* d = doc_of(input);
      std::filesystem::path dir = std::filesystem::absolute(std::filesystem::path(d ? d->path : source_), ec).parent_path();
      for (std::filesystem::path up = dir;; up = up.parent_path()) {
        if (found(up / rel)) return (up / rel).string();
        if (up == up.parent_path() || up.empty()) break;
      }
      if (const char* sp = std::getenv("GONIO_MTLX_SEARCH_PATH")) {
        std::string_view list = sp;
        while (!list.empty()) {
          const size_t colon = list.find(':');
          const std::string_view one = list.substr(0, colon);
          if (!one.empty() && found(std::filesystem::path(std::string(one)) / rel)) return (std::filesystem::path(std::string(one)) / rel).string();
          if (colon == std::string_view::npos) break;
          list.remove_prefix(colon + 1);
        }
      }
    }
    throw InputError(escape_control(cat("image not found: ", rel.string(), " (node ", excerpt(node.attribute("name").value()), ", ",
                                        file_line(input), ")")));
  }

  // ---- open_pbr_surface and standard_surface: the openpbr JSON --------------------------

  json from_shader(const pugi::xml_node shader, const Frame& f) {
    const std::string_view category = shader.name();
    const std::string where = element_text(shader);
    shader_text_ = where;
    if (const pugi::xml_attribute t = shader.attribute("type"); t && std::string_view(t.value()) != "surfaceshader")
      fail_at(shader, where + ": type must be \"surfaceshader\", got " + in_quotes(t.value()));
    const bool openpbr = category == "open_pbr_surface";
    const std::string_view version = shader.attribute("version").value();
    bool ss100 = false;  // Standard Surface 1.0.0's defaults
    if (openpbr) {
      if (!version.empty() && version != "1.1") fail_at(shader, where + ": OpenPBR version " + in_quotes(version) + " (1.1 supported)");
      if (const std::string_view nd = shader.attribute("nodedef").value(); !nd.empty() && nd != "ND_open_pbr_surface_surfaceshader")
        fail_at(shader, where + ": node definition " + in_quotes(nd) + " is not supported");
    } else {
      if (!version.empty() && version != "1.0.1" && version != "1.0.0" && version != "1.0")
        fail_at(shader, where + ": Standard Surface version " + in_quotes(version) + " (1.0.0 or 1.0.1 supported)");
      ss100 = version == "1.0.0" || version == "1.0";
      if (const std::string_view nd = shader.attribute("nodedef").value();
          !nd.empty() && nd != "ND_standard_surface_surfaceshader" && nd != "ND_standard_surface_surfaceshader_100")
        fail_at(shader, where + ": node definition " + in_quotes(nd) + " is not supported");
      if (shader.attribute("nodedef").value() == std::string_view("ND_standard_surface_surfaceshader_100")) ss100 = true;
    }
    std::map<std::string, Value, std::less<>> given;
    std::vector<std::tuple<std::string, Val, const ParamDef*, std::string>> linked;  // key, value, definition, where
    for (const pugi::xml_node input : shader.children()) {
      if (input.type() != pugi::node_element) continue;
      if (std::string_view(input.name()) != "input")
        fail_at(input, where + ": unsupported element <" + excerpt(input.name()) + "> (only inputs)");
      read_input(shader, f, input, openpbr, where, given, linked);
    }
    if (!linked.empty()) {
      const std::vector<mtlxgraph::Reg> regs = evaluate();
      for (auto& [key, val, def, iwhere] : linked) {
        Value& v = given[key];
        const Pending p{val, v.node, iwhere, kind_name(def->kind)};
        const auto r = pending_value(p, regs);
        v.kind = def->kind;
        switch (def->kind) {
          case Kind::Float: v.f = r[0]; break;
          case Kind::Color3: v.c = {r[0], r[1], r[2]}; break;
          case Kind::Boolean: v.b = r[0] != 0; break;
          case Kind::Vector3: break;
        }
        if (def->kind == Kind::Float || def->kind == Kind::Color3)
          limit(*def, v.node.attribute("name").value(), "(graph)", "", iwhere, v);
      }
    }
    return openpbr ? openpbr_json(given) : standard_surface_to_openpbr(given, where, ss100);
  }

  void read_input(const pugi::xml_node shader, const Frame& f, const pugi::xml_node input, bool openpbr,
                  const std::string& where, std::map<std::string, Value, std::less<>>& given,
                  std::vector<std::tuple<std::string, Val, const ParamDef*, std::string>>& linked) {
    const std::string name = input.attribute("name").value();
    if (name.empty()) fail_at(input, where + ": an input without a name");
    const std::string iwhere = where + ": input " + excerpt(name);
    std::string key = name;  // the name in the tables
    const ParamDef* def = nullptr;
    if (openpbr) {
      def = find_def(std::begin(kOpenPbr), std::end(kOpenPbr), name);
      if (!def && v138_) {
        for (const Rename& r : kRenames138)
          if (name == r.old_name) def = find_def(std::begin(kOpenPbr), std::end(kOpenPbr), key = r.new_name);
        static constexpr ParamDef kRotationDefs[] = {{"specular_rotation", Kind::Float, {0}, kTurnRange},
                                                     {"coat_rotation", Kind::Float, {0}, kTurnRange}};
        if (!def) def = find_def(std::begin(kRotationDefs), std::end(kRotationDefs), name);
      }
      if (!def) {
        bool draft = false;  // a name SPEC §2 maps in 1.38 documents only
        for (const Rename& r : kRenames138) draft = draft || name == r.old_name;
        for (const char* r : kRotations) draft = draft || name == r;
        fail_at(input, iwhere + ": not an OpenPBR 1.1 input" +
                           (draft ? std::string(" (an OpenPBR draft name, read in documents of version 1.38 only)") : std::string()));
      }
    } else {
      def = find_def(std::begin(kStandardSurface), std::end(kStandardSurface), name);
      if (!def) fail_at(input, iwhere + ": not a Standard Surface input");
    }
    if (const auto twice = given.find(key); twice != given.end())
      fail_at(input, iwhere + ": given twice (" + line_text(twice->second.node) + " and " + line_text(input) + ")" +
                         (key != name ? " (as " + key + " too)" : std::string()));
    const pugi::xml_attribute type = input.attribute("type");
    if (!type) fail_at(input, iwhere + ": no type attribute (" + std::string(kind_name(def->kind)) + " expected)");
    if (std::string_view(type.value()) != kind_name(def->kind))
      fail_at(input, iwhere + ": type " + in_quotes(type.value()) + ", expected " + kind_name(def->kind));
    if (const pugi::xml_attribute u = input.attribute("unit"))
      fail_at(input, iwhere + ": unit " + in_quotes(u.value()) + " is not supported (values in the node definition's units)");
    const bool is_linked = input.attribute("nodename") || input.attribute("nodegraph") || input.attribute("interfacename") ||
                           input.attribute("output");
    if (def->kind == Kind::Vector3) {
      // The shading frame is the caller's (a BSDF works in its local frame): a normal map
      // or tangent is ignored with a note; a constant is refused.
      if (input.attribute("value"))
        fail_at(input, iwhere + ": a constant " + excerpt(name) + " is not supported (the caller's shading frame is used)");
      if (is_linked) notes_.push_back(cat(iwhere, " ignored: the shading frame is the caller's (", line_text(input), ")"));
      given[key] = Value{Kind::Vector3, 0, {}, false, input};  // kept for "given twice"
      return;
    }
    (void)shader;
    if (is_linked || input.attribute("channels")) {
      const Val v = compile_input(input, f, iwhere, def->kind == Kind::Color3 ? 3 : 1, 0);
      given[key] = Value{def->kind, 0, {}, false, input};
      linked.emplace_back(key, v, def, iwhere);
      return;
    }
    const pugi::xml_attribute value = input.attribute("value");
    if (!value) fail_at(input, iwhere + ": no value");
    Value v;
    v.kind = def->kind;
    v.node = input;
    const std::string_view text = value.value();
    std::string space;  // a colour's space, when it is converted
    switch (def->kind) {
      case Kind::Float: v.f = parse_number(text, input, iwhere); break;
      case Kind::Color3: {
        space = colorspace_of(input);
        v.c = to_lin_rec709(parse_color(text, input, iwhere), space, input, iwhere);
        break;
      }
      case Kind::Boolean:
        if (text == "true") {
          v.b = true;
        } else if (text != "false") {
          fail_at(input, iwhere + ": value " + in_quotes(text) + " is not a boolean (true or false)");
        }
        break;
      case Kind::Vector3: break;
    }
    if (def->kind == Kind::Float || def->kind == Kind::Color3) limit(*def, name, text, space, iwhere, v);
    given[key] = v;
  }

  // Refuses or clamps `v` (the input `name`, written `text`) into its parameter's range.
  // A 1.38 OpenPBR document's thin_film_thickness is in nm (SPEC §2): its range in nm.
  void limit(const ParamDef& def, const std::string& name, std::string_view text, const std::string& space,
             const std::string& iwhere, Value& v) const {
    Range r = def.range;
    std::string unit = def.unit;
    if (v138_ && unit == "um") {
      r.lo *= 1000;
      r.hi *= 1000;
      unit = "nm";
    }
    const std::string unit_text = unit.empty() ? "" : cat(" ", unit == "um" ? "\u00b5m" : unit);
    const size_t channels = def.kind == Kind::Color3 ? 3 : 1;
    double* x = def.kind == Kind::Color3 ? v.c.data() : &v.f;
    std::string before, after;
    bool changed = false;
    for (size_t i = 0; i < channels; ++i) {
      if (x[i] < r.lo && r.refused_below)
        fail_at(v.node, cat(iwhere, ": ", format_number(x[i]), unit_text, " is negative (", r.refused_below, ", in [",
                            format_number(r.lo), ", ", format_number(r.hi), "])"));
      before += cat(i ? ", " : "", format_number(x[i]));
      const double used = std::clamp(x[i], r.lo, r.hi);
      changed = changed || used != x[i];
      x[i] = used;
      after += cat(i ? ", " : "", format_number(used));
    }
    if (!changed) return;
    // The document's value as written; a converted colour's linear Rec.709 value too.
    std::string shown = excerpt(trim(text));
    if (!space.empty() && space != "lin_rec709") shown += cat(" (", excerpt(space), "; ", before, " in lin_rec709)");
    clamped_.push_back(cat(excerpt(name), " ", shown, unit_text, " -> ", after, unit_text, " (", line_text(v.node), ")"));
  }

  static std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\n' || s.front() == '\r')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\n' || s.back() == '\r')) s.remove_suffix(1);
    return s;
  }

  double parse_number(std::string_view text, const pugi::xml_node at, const std::string& where) const {
    std::string_view t = trim(text);
    if (!t.empty() && t.front() == '+') t.remove_prefix(1);
    double v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty() || ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v))
      fail_at(at, where + ": value " + in_quotes(text) + " is not a finite number");
    return v;
  }

  Rgb parse_color(std::string_view text, const pugi::xml_node at, const std::string& where) const {
    Rgb c{};
    size_t start = 0;
    for (int i = 0; i < 3; ++i) {
      const size_t comma = text.find(',', start);
      const bool last = i == 2;
      if (last != (comma == std::string_view::npos))
        fail_at(at, where + ": value " + in_quotes(text) + " is not a color3 (three numbers separated by commas)");
      const std::string_view part = text.substr(start, last ? std::string_view::npos : comma - start);
      c[size_t(i)] = parse_number(part, at, where);
      start = comma + 1;
    }
    return c;
  }

  Rgb to_lin_rec709(const Rgb& c, const std::string& space, const pugi::xml_node at, const std::string& where) const {
    if (space == "lin_rec709") return c;
    if (space == "acescg" || space == "lin_ap1") {
      Rgb out{};
      for (size_t r = 0; r < 3; ++r)
        out[r] = kAp1ToRec709[r][0] * c[0] + kAp1ToRec709[r][1] * c[1] + kAp1ToRec709[r][2] * c[2];
      return out;
    }
    fail_at(at, where + ": colorspace " + in_quotes(space) + " is not supported (lin_rec709 or acescg)");
  }

  // {"type": "openpbr", every OpenPBR 1.1 parameter}, the document's value or the default.
  json openpbr_json(std::map<std::string, Value, std::less<>>& given) const {
    json j = json::object();
    j["type"] = "openpbr";
    if (v138_) {
      // SPEC §2: 1.38's thin_film_thickness is in nanometres; a film given a thickness
      // and no weight is on (the draft had no weight).
      if (const auto t = given.find("thin_film_thickness"); t != given.end()) {
        t->second.f /= 1000;
        if (t->second.f > 0 && !given.count("thin_film_weight")) given["thin_film_weight"] = Value{Kind::Float, 1, {}, false, {}};
      }
      for (const char* r : kRotations)
        if (const auto it = given.find(r); it != given.end()) j[r] = it->second.f;
    }
    for (const ParamDef& p : kOpenPbr) {
      if (p.kind == Kind::Vector3) continue;
      const auto it = given.find(p.name);
      const Value v = it != given.end() ? it->second : Value{p.kind, p.def[0], p.def, p.def[0] != 0, {}};
      switch (p.kind) {
        case Kind::Float: j[p.name] = v.f; break;
        case Kind::Color3: j[p.name] = json::array({v.c[0], v.c[1], v.c[2]}); break;
        case Kind::Boolean: j[p.name] = v.b; break;
        case Kind::Vector3: break;
      }
    }
    return j;
  }

  // Standard Surface → OpenPBR as MaterialX's translation graph
  // (NG_standard_surface_to_open_pbr_surface) maps it; the node each line follows is
  // named. Approximations are the graph's own (docs/materialx.md lists them).
  json standard_surface_to_openpbr(const std::map<std::string, Value, std::less<>>& given, const std::string& where,
                                   bool ss100) const {
    const auto value = [&](const char* name) -> Value {
      if (const auto it = given.find(name); it != given.end()) return it->second;
      const ParamDef* p = find_def(std::begin(kStandardSurface), std::end(kStandardSurface), name);
      Value v{p->kind, p->def[0], p->def, p->def[0] != 0, {}};
      if (ss100 && std::string_view(name) == "base") v.f = 0.8;  // Standard Surface 1.0.0
      if (ss100 && std::string_view(name) == "base_color") v.c = {1, 1, 1};
      return v;
    };
    const auto f = [&](const char* name) { return value(name).f; };
    const auto c = [&](const char* name) { return value(name).c; };
    const auto arr = [](const Rgb& x) { return json::array({x[0], x[1], x[2]}); };
    // No OpenPBR counterpart, and the graph drops them: refused unless at their defaults,
    // so that nothing a document says is lost silently.
    for (const char* dropped : {"transmission_extra_roughness", "coat_affect_color"})
      if (f(dropped) != 0)
        fail_at(value(dropped).node, where + ": input " + std::string(dropped) + " = " + format_number(f(dropped)) +
                                         " has no OpenPBR counterpart (only its default 0 is accepted)");

    json j = json::object();
    j["type"] = "openpbr";
    const double metalness = f("metalness"), coat = f("coat");
    // Base: baseWeight, baseColor = base_color · mix(1, coat_color, coat) (coatAttenuation:
    // Standard Surface tints everything under the coat by its colour).
    j["base_weight"] = f("base");
    const Rgb base_color = c("base_color"), coat_color = c("coat_color");
    Rgb tinted{};
    for (size_t i = 0; i < 3; ++i) tinted[i] = base_color[i] * (1 + coat * (coat_color[i] - 1));
    j["base_color"] = arr(tinted);
    j["base_diffuse_roughness"] = f("diffuse_roughness");
    j["base_metalness"] = metalness;
    // Specular: specWeight = 1 where metalness > 0 (in OpenPBR the weight scales the metal
    // too, in Standard Surface it does not); specColor = white when specular_color is
    // black (ifequal on its channel sum), else as given.
    j["specular_weight"] = metalness > 0 ? 1.0 : f("specular");
    const Rgb sc = c("specular_color");
    j["specular_color"] = sc[0] + sc[1] + sc[2] == 0 ? arr({1, 1, 1}) : arr(sc);
    j["specular_roughness"] = f("specular_roughness");
    j["specular_ior"] = f("specular_IOR");
    j["specular_roughness_anisotropy"] = f("specular_anisotropy");
    // Transmission, copied.
    j["transmission_weight"] = f("transmission");
    j["transmission_color"] = arr(c("transmission_color"));
    j["transmission_depth"] = f("transmission_depth");
    j["transmission_scatter"] = arr(c("transmission_scatter"));
    j["transmission_scatter_anisotropy"] = f("transmission_scatter_anisotropy");
    // transmission_dispersion is Standard Surface's Abbe number (0: none). The graph copies
    // it into transmission_dispersion_scale (range [0, 1]); here it is the Abbe number
    // at scale 1 instead, which means what it says (a deviation, docs/materialx.md).
    const double abbe = f("transmission_dispersion");
    j["transmission_dispersion_scale"] = abbe > 0 ? 1.0 : 0.0;
    j["transmission_dispersion_abbe_number"] = abbe > 0 ? abbe : 20.0;
    // Subsurface: subsurface_scale → radius, subsurface_radius (colour) → radius_scale.
    j["subsurface_weight"] = f("subsurface");
    j["subsurface_color"] = arr(c("subsurface_color"));
    j["subsurface_radius"] = f("subsurface_scale");
    j["subsurface_radius_scale"] = arr(c("subsurface_radius"));
    j["subsurface_scatter_anisotropy"] = f("subsurface_anisotropy");
    // Fuzz: fuzzRoughness = sheen_roughness^0.4 (the graph's fit "by eye").
    j["fuzz_weight"] = f("sheen");
    j["fuzz_color"] = arr(c("sheen_color"));
    j["fuzz_roughness"] = std::pow(f("sheen_roughness"), 0.4);
    // Coat: coatWeight = 0 where coat · metalness > 0 (the coat's colour already tints
    // the base above); coatDarkening = coat_affect_roughness, as the graph wires it.
    j["coat_weight"] = coat * metalness > 0 ? 0.0 : coat;
    j["coat_color"] = arr(coat_color);
    j["coat_roughness"] = f("coat_roughness");
    j["coat_roughness_anisotropy"] = f("coat_anisotropy");
    j["coat_ior"] = f("coat_IOR");
    j["coat_darkening"] = f("coat_affect_roughness");
    // Thin film: nm → µm, weight 1 where the thickness is > 0.
    const double film_um = f("thin_film_thickness") * 0.001;
    j["thin_film_weight"] = film_um > 0 ? 1.0 : 0.0;
    j["thin_film_thickness"] = film_um;
    j["thin_film_ior"] = f("thin_film_IOR");
    j["emission_luminance"] = f("emission");
    j["emission_color"] = arr(c("emission_color"));
    // geometryOpacity: the red channel of the opacity colour (extract, index 0).
    j["geometry_opacity"] = c("opacity")[0];
    j["geometry_thin_walled"] = value("thin_walled").b;
    // Tangent rotations: gonio's extension parameters (SPEC §2), when given.
    for (const char* r : kRotations)
      if (given.count(r)) j[r] = f(r);
    return j;
  }
};

}  // namespace
}  // namespace mtlx

nlohmann::json materialx_to_json(std::string_view xml, const std::string& source, const std::optional<std::string>& name,
                                 std::string* note, const MaterialxPoint& at) {
  mtlx::Reader reader(source, at);
  reader.load(xml);
  return reader.read(name, note);
}

// Read as a scene file is (read_text_file): whatever the path is, a FIFO included, so that
// `--from-mtlx <(generator)` works; a FIFO that no process writes waits for one, as
// `cat` does, until a signal ends the command (docs/materialx.md).
nlohmann::json materialx_file_to_json(const std::string& path, const std::optional<std::string>& name, std::string* note,
                                      const MaterialxPoint& at) {
  const std::string text = read_text_file(path, kMaxMaterialxFileBytes, "a MaterialX document");
  return materialx_to_json(text, path, name, note, at);
}

std::vector<std::string> materialx_surface_names(const std::string& path) {
  return materialx_surface_names(read_text_file(path, kMaxMaterialxFileBytes, "a MaterialX document"), path);
}

std::vector<std::string> materialx_surface_names(std::string_view xml, const std::string& source) {
  mtlx::Reader reader(source, {});
  reader.load(xml);
  std::vector<std::string> names;
  for (const auto& s : reader.surfaces()) names.push_back(s.name);
  return names;
}

}  // namespace gonio
