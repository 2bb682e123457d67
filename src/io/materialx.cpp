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
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <pugixml.hpp>

#include "gonio/error.h"
#include "gonio/json_text.h"

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

// The document being read: its text's source for messages, and what scopes need.
class Reader {
 public:
  Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& what) const { throw InputError(escape_control(source_ + ": " + what)); }

  // "SOURCE: line L: what", L the line where `node` starts in the document.
  [[noreturn]] void fail_at(const pugi::xml_node node, const std::string& what) const {
    const size_t line = line_of(node);
    if (line == 0) fail(what);
    fail(cat("line ", std::to_string(line), ": ", what));
  }

  json read(std::string_view xml, const std::optional<std::string>& name, std::string* note) {
    xml_ = xml;
    // pugixml stops at a NUL byte, so whatever followed one would go unread; XML text
    // cannot hold one (XML 1.0 §2.2, Char).
    if (const size_t nul = xml.find('\0'); nul != std::string_view::npos)
      fail(cat("line ", std::to_string(line_at(nul)), ": a NUL byte (at byte offset ", std::to_string(nul),
               "): XML text cannot hold one"));
    const pugi::xml_parse_result parsed =
        doc_.load_buffer(xml.data(), xml.size(), pugi::parse_default, pugi::encoding_utf8);
    if (!parsed) {
      const size_t at = std::min(size_t(parsed.offset), xml.size());
      fail(cat("malformed MaterialX document: ", parsed.description(), " at line ", std::to_string(line_at(at))));
    }
    // pugixml reads a fragment; a document has one root element (XML 1.0 §2.1).
    pugi::xml_node root;
    for (const pugi::xml_node top : doc_.children()) {
      if (top.type() != pugi::node_element) continue;
      if (root)
        fail_at(top, cat("malformed MaterialX document: a second root element <", excerpt(top.name()), "> after <",
                         excerpt(root.name()), "> (a document has one)"));
      root = top;
    }
    if (std::string_view(root.name()) != "materialx")
      fail_at(root, cat("not a MaterialX document: the root element is <", excerpt(root.name()), ">, not <materialx>"));
    read_version(root);
    refuse_xinclude(root);
    const pugi::xml_node material = find_material(root, name);
    json j = from_material(root, material);
    if (note) {
      note->clear();
      if (!clamped_.empty()) {
        std::string list;
        for (const std::string& c : clamped_) list += cat(list.empty() ? "" : "; ", c);
        *note = escape_control(cat(source_, ": ", shader_text_, ": clamped to what the model takes: ", list));
      }
    }
    return j;
  }

 private:
  std::string source_;
  std::string_view xml_;
  pugi::xml_document doc_;
  bool v138_ = false;                 // a version 1.38 document: the OpenPBR draft's names and units
  std::string shader_text_;           // the shader node read, for the note
  mutable std::vector<std::string> clamped_;  // "input V -> W (line L)" per clamped input

  // The 1-based line of byte `offset` of the document.
  size_t line_at(size_t offset) const {
    offset = std::min(offset, xml_.size());
    return 1 + size_t(std::count(xml_.begin(), xml_.begin() + std::ptrdiff_t(offset), '\n'));
  }
  // The line where `node` starts; 0 when pugixml cannot tell.
  size_t line_of(const pugi::xml_node node) const {
    const std::ptrdiff_t offset = node.offset_debug();
    return offset < 0 ? 0 : line_at(size_t(offset));
  }
  std::string line_text(const pugi::xml_node node) const { return cat("line ", std::to_string(line_of(node))); }

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
  // element or an ancestor binds to XInclude's namespace. Anywhere in the document: an
  // inclusion inside a nodegraph would be dropped as surely as a top-level one.
  void refuse_xinclude(const pugi::xml_node root) const {
    struct Walker : pugi::xml_tree_walker {
      pugi::xml_node found;
      bool for_each(pugi::xml_node& n) override {
        if (n.type() != pugi::node_element) return true;
        const std::string_view name = n.name();
        const size_t colon = name.find(':');
        const std::string_view prefix = colon == std::string_view::npos ? "" : name.substr(0, colon);
        const std::string_view local = colon == std::string_view::npos ? name : name.substr(colon + 1);
        if (local != "include") return true;
        bool bound = prefix == "xi";
        const std::string declaration = prefix.empty() ? std::string("xmlns") : cat("xmlns:", prefix);
        for (pugi::xml_node up = n; up && !bound; up = up.parent())
          if (const pugi::xml_attribute a = up.attribute(declaration.c_str())) {
            bound = std::string_view(a.value()) == kXIncludeNamespace;
            break;  // the nearest declaration binds the prefix
          }
        if (!bound) return true;
        found = n;
        return false;
      }
    } walker;
    pugi::xml_node scope = root;
    scope.traverse(walker);
    if (walker.found)
      fail_at(walker.found, cat("<", excerpt(walker.found.name()),
                                "> (an XInclude) is not supported (give the included document's material directly)"));
  }

  static std::string element_text(const pugi::xml_node n) {
    return cat("<", excerpt(n.name()), "> ", in_quotes(n.attribute("name").value()));
  }

  pugi::xml_node find_material(const pugi::xml_node root, const std::optional<std::string>& name) const {
    std::vector<pugi::xml_node> materials;
    std::map<std::string_view, pugi::xml_node> by_name;
    for (const pugi::xml_node child : root.children("surfacematerial")) {
      const auto [it, fresh] = by_name.emplace(child.attribute("name").value(), child);
      if (!fresh)
        fail_at(child, cat("two surfacematerials are named ", in_quotes(it->first), " (", line_text(it->second), " and ",
                           line_text(child), ")"));
      materials.push_back(child);
    }
    std::string names;  // for messages: the first ten
    for (size_t i = 0; i < materials.size() && i < 10; ++i)
      names += cat(i ? ", " : "", in_quotes(materials[i].attribute("name").value()));
    if (materials.size() > 10) names += cat(" and ", std::to_string(materials.size() - 10), " more");
    if (name) {
      for (const auto& m : materials)
        if (*name == m.attribute("name").value()) return m;
      fail(cat("no surfacematerial named ", in_quotes(*name),
               materials.empty() ? std::string(" (the document has none)") : cat(" (its materials: ", names, ")")));
    }
    if (materials.empty()) fail("the document has no surfacematerial");
    if (materials.size() > 1) fail(cat("the document has several materials (", names, "): name the one to read"));
    return materials[0];
  }

  // The element called `name` among `scope`'s children (one at most).
  pugi::xml_node named_child(const pugi::xml_node scope, std::string_view name) const {
    pugi::xml_node found;
    for (const pugi::xml_node child : scope.children()) {
      if (child.type() != pugi::node_element || name != child.attribute("name").value()) continue;
      if (found)
        fail_at(child, cat("two elements are named ", in_quotes(name), " (", line_text(found), " and ", line_text(child), ")"));
      found = child;
    }
    return found;
  }

  json from_material(const pugi::xml_node root, const pugi::xml_node material) {
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
      } else if (input == "backsurfaceshader" || input == "displacementshader" || input == "volumeshader") {
        // Unset (no connection, empty value) is what the examples write; anything else
        // would be dropped.
        if (child.attribute("nodename") || child.attribute("nodegraph") || child.attribute("value").value()[0] != '\0')
          fail_at(child, where + ": input " + std::string(input) + " is not supported (only surfaceshader may be connected)");
      } else {
        fail_at(child, where + ": unknown input " + in_quotes(input) + " (surfaceshader expected)");
      }
    }
    if (!shader_input) fail_at(material, where + ": no surfaceshader input");
    const pugi::xml_node shader = shader_node(root, shader_input, where + ": input surfaceshader");
    return from_shader(shader);
  }

  // The node a surfacematerial's surfaceshader input leads to: a node named by
  // `nodename`, or the node a nodegraph's output names.
  pugi::xml_node shader_node(const pugi::xml_node root, const pugi::xml_node input, const std::string& where) const {
    const pugi::xml_attribute nodename = input.attribute("nodename"), graph = input.attribute("nodegraph");
    if (nodename && graph) fail_at(input, where + ": both nodename and nodegraph are given");
    if (nodename) {
      if (const pugi::xml_attribute out = input.attribute("output"); out && std::string_view(out.value()) != "out")
        fail_at(input, where + ": output " + in_quotes(out.value()) + " of a shader node (only \"out\")");
      const pugi::xml_node node = named_child(root, nodename.value());
      if (!node) fail_at(input, where + ": no node named " + in_quotes(nodename.value()));
      return node;
    }
    if (!graph) fail_at(input, where + ": not connected (a nodename or nodegraph attribute expected)");
    const pugi::xml_node g = named_child(root, graph.value());
    if (!g || std::string_view(g.name()) != "nodegraph") fail_at(input, where + ": no nodegraph named " + in_quotes(graph.value()));
    const std::string gwhere = element_text(g);
    if (g.attribute("nodedef")) fail_at(g, gwhere + ": a nodegraph implementing a node definition is not supported");
    std::vector<pugi::xml_node> outputs;
    for (const pugi::xml_node o : g.children("output")) outputs.push_back(o);
    pugi::xml_node output;
    if (const pugi::xml_attribute want = input.attribute("output")) {
      for (const auto& o : outputs)
        if (std::string_view(o.attribute("name").value()) == want.value()) output = o;
      if (!output) fail_at(g, gwhere + ": no output named " + in_quotes(want.value()));
    } else {
      if (outputs.size() != 1) fail_at(g, gwhere + ": " + std::to_string(outputs.size()) + " outputs, and the input names none");
      output = outputs[0];
    }
    const std::string owhere = gwhere + ": output " + in_quotes(output.attribute("name").value());
    if (output.attribute("interfacename") || output.attribute("nodegraph") || !output.attribute("nodename"))
      fail_at(output, owhere + ": only an output naming a node of the graph (nodename) is supported");
    const pugi::xml_node node = named_child(g, output.attribute("nodename").value());
    if (!node) fail_at(output, owhere + ": no node named " + in_quotes(output.attribute("nodename").value()) + " in the graph");
    return node;
  }

  // The colour space of an input: its own attribute, else the nearest enclosing
  // element's (MaterialX scoping), else the default lin_rec709.
  static std::string colorspace_of(pugi::xml_node n) {
    for (; n; n = n.parent())
      if (const pugi::xml_attribute cs = n.attribute("colorspace")) return cs.value();
    return "lin_rec709";
  }

  json from_shader(const pugi::xml_node shader) {
    const std::string_view category = shader.name();
    const std::string where = element_text(shader);
    shader_text_ = where;
    if (category != "open_pbr_surface" && category != "standard_surface")
      fail_at(shader, where + ": unsupported shader node (open_pbr_surface or standard_surface expected)");
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
    for (const pugi::xml_node input : shader.children()) {
      if (input.type() != pugi::node_element) continue;
      if (std::string_view(input.name()) != "input")
        fail_at(input, where + ": unsupported element <" + excerpt(input.name()) + "> (only constant inputs)");
      read_input(shader, input, openpbr, where, given);
    }
    return openpbr ? openpbr_json(given) : standard_surface_to_openpbr(given, where, ss100);
  }

  // ", output O: <category> "N"": the node a nodegraph's output names (for messages; empty
  // when there is none to name).
  std::string linked_node(const pugi::xml_node scope, std::string_view graph, std::string_view output) const {
    pugi::xml_node g;
    for (const pugi::xml_node child : scope.children("nodegraph"))
      if (graph == child.attribute("name").value()) g = child;
    for (const pugi::xml_node o : g.children("output")) {
      if (!output.empty() && output != o.attribute("name").value()) continue;
      for (const pugi::xml_node n : g.children())
        if (n.type() == pugi::node_element && std::string_view(n.name()) != "output" &&
            std::string_view(o.attribute("nodename").value()) == n.attribute("name").value())
          return cat(", output ", in_quotes(o.attribute("name").value()), ": ", element_text(n));
      break;
    }
    return "";
  }

  void read_input(const pugi::xml_node shader, const pugi::xml_node input, bool openpbr, const std::string& where,
                  std::map<std::string, Value, std::less<>>& given) const {
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
    // Connections: textures, other nodes and graphs are not read.
    for (const char* attr : {"nodename", "nodegraph", "interfacename", "output", "channels", "defaultgeomprop"}) {
      const pugi::xml_attribute a = input.attribute(attr);
      if (!a) continue;
      std::string what = cat(attr, "=", in_quotes(a.value()));
      if (std::string_view(attr) == "nodename") {
        if (const pugi::xml_node n = named_child(shader.parent(), a.value())) what = cat("node ", element_text(n));
      } else if (std::string_view(attr) == "nodegraph") {
        what = cat("nodegraph ", in_quotes(a.value()), linked_node(shader.parent(), a.value(), input.attribute("output").value()));
      }
      fail_at(input, iwhere + ": connected (" + what + "); only constant values are supported (no textures or node graphs)");
    }
    const pugi::xml_attribute type = input.attribute("type");
    if (!type) fail_at(input, iwhere + ": no type attribute (" + std::string(kind_name(def->kind)) + " expected)");
    if (std::string_view(type.value()) != kind_name(def->kind))
      fail_at(input, iwhere + ": type " + in_quotes(type.value()) + ", expected " + kind_name(def->kind));
    if (const pugi::xml_attribute u = input.attribute("unit"))
      fail_at(input, iwhere + ": unit " + in_quotes(u.value()) + " is not supported (values in the node definition's units)");
    const pugi::xml_attribute value = input.attribute("value");
    if (def->kind == Kind::Vector3) {
      if (value) fail_at(input, iwhere + ": a constant " + excerpt(name) + " is not supported (the caller's shading frame is used)");
      given[key] = Value{Kind::Vector3, 0, {}, false, input};  // unset: the shading frame (kept for "given twice")
      return;
    }
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
                                 std::string* note) {
  mtlx::Reader reader(source);
  return reader.read(xml, name, note);
}

// Read as a scene file is (read_text_file): whatever the path is, a FIFO included, so that
// `--from-mtlx <(generator)` works; a FIFO that no process writes waits for one, as
// `cat` does, until a signal ends the command (docs/materialx.md).
nlohmann::json materialx_file_to_json(const std::string& path, const std::optional<std::string>& name, std::string* note) {
  const std::string text = read_text_file(path, kMaxMaterialxFileBytes, "a MaterialX document");
  return materialx_to_json(text, path, name, note);
}

}  // namespace gonio
