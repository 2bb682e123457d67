// Scene JSON → Scene. Each reader checks types, ranges and unknown keys, and names the
// JSON path of the offending value.

#include "gonio/render/scene_loader.h"
#include "gonio/render/gltf_loader.h"
#include "gonio/render/texture/texture_load.h"

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "gonio/error.h"
#include "gonio/json_text.h"
#include "gonio/material.h"
#include "gonio/spectral_material.h"
#include "gonio/spectrum/rgb_to_spectrum.h"
#include "gonio/render/mesh_loader.h"
#include "gonio/render/subsurface_walk.h"
#include "gonio/subsurface/diffusion.h"
#include "gonio/subsurface/openpbr_interior.h"
#include "gonio/render/texture.h"
#include "gonio/spectrum/spectrum_json.h"
#include "gonio/spectrum/spectrum_to_rgb.h"

namespace gonio::render {
namespace {

using nlohmann::json;

// Error messages show values as json_excerpt does (json_text.h).
std::string show(const json& v) { return json_excerpt(v); }

// A JSON value together with where it is, for messages.
class Node {
 public:
  Node(const json& value, const std::string* source, std::string path)
      : v_(&value), source_(source), path_(std::move(path)) {}

  const json& value() const { return *v_; }
  const std::string& path() const { return path_; }
  std::string where() const { return *source_ + ": " + (path_.empty() ? "/" : path_); }
  [[noreturn]] void fail(const std::string& msg) const { throw InputError(where() + ": " + msg); }

  Node at(const std::string& key) const { return {(*v_)[key], source_, path_ + "/" + key}; }
  Node at(size_t i) const { return {(*v_)[i], source_, path_ + "/" + std::to_string(i)}; }
  bool has(const char* key) const { return v_->contains(key); }
  size_t size() const { return v_->size(); }

  const Node& object(std::initializer_list<const char*> allowed) const {
    if (!v_->is_object()) fail("must be a JSON object, got " + show(*v_));
    for (auto it = v_->begin(); it != v_->end(); ++it) {
      bool ok = it.key() == "comment";
      for (const char* a : allowed) ok |= it.key() == a;
      if (!ok) {
        std::string names;
        for (const char* a : allowed) names += (names.empty() ? "" : ", ") + std::string(a);
        fail("unknown field \"" + it.key() + "\" (known: " + names + ")");
      }
    }
    return *this;
  }
  Node required(const char* key) const {
    if (!has(key)) fail(std::string("missing field \"") + key + "\"");
    return at(key);
  }
  const Node& array() const {
    if (!v_->is_array()) fail("must be an array, got " + show(*v_));
    return *this;
  }

  // Every number of a scene is stored as a Float: it must fit one.
  double number() const {
    if (!v_->is_number()) fail("must be a number, got " + show(*v_));
    const double d = v_->get<double>();
    if (!std::isfinite(d)) fail("must be finite, got " + show(*v_));
    if (std::abs(d) > FLT_MAX) fail("does not fit in a float (at most " + format_number(FLT_MAX) + "), got " + show(*v_));
    return d;
  }
  // With open_lo and lo = 0 (a positive quantity), the value must also stay a normal
  // float: 1e-320 passes "> 0" as a double but is 0 as a Float.
  double number(double lo, double hi, bool open_lo = false) const {
    const double d = number();
    if (open_lo ? !(d > lo) : !(d >= lo)) fail("must be " + std::string(open_lo ? "> " : ">= ") + format_number(lo) + ", got " + show(*v_));
    if (!(d <= hi)) fail("must be <= " + format_number(hi) + ", got " + show(*v_));
    if (open_lo && lo == 0 && !(static_cast<Float>(d) >= FLT_MIN))
      fail("must be > 0, got " + show(*v_) + " (too small for a float: it would round to 0 or a denormal)");
    return d;
  }
  int integer(int lo, int hi) const {
    if (!v_->is_number_integer() && !v_->is_number_unsigned()) fail("must be an integer, got " + show(*v_));
    const double d = v_->get<double>();
    if (d < lo || d > hi) fail("must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + show(*v_));
    return static_cast<int>(d);
  }
  bool boolean() const {
    if (!v_->is_boolean()) fail("must be true or false, got " + show(*v_));
    return v_->get<bool>();
  }
  std::string string() const {
    if (!v_->is_string()) fail("must be a string, got " + show(*v_));
    return v_->get<std::string>();
  }
  Vec3 vec3() const {
    if (!v_->is_array() || v_->size() != 3) fail("must be [x, y, z], got " + show(*v_));
    return {static_cast<Float>(at(0).number()), static_cast<Float>(at(1).number()), static_cast<Float>(at(2).number())};
  }
  Vec3 direction() const {
    const Vec3 v = vec3();
    if (!(length_squared(v) > 0)) fail("must be a non-zero vector, got " + show(*v_));
    return v;
  }
  // A light's colour: a number (grey) or [r, g, b], each >= 0, or (SPEC §2) an emission
  // spectrum — {"spectrum": ...} (a CSV relative to the scene file), {"blackbody": K} or
  // {"illuminant": "D65"}, the last two of luminance 1 — reduced to linear sRGB.
  // `spectrum` receives what spectral mode uses: the spectrum given, or the RGB value
  // upsampled as an illuminant (Jakob & Hanika 2019; m S(rgb/m) D65, rgb_to_spectrum.h).
  Color color(const std::string& base_dir, std::optional<Spectrum>* spectrum = nullptr) const {
    Color c;
    if (v_->is_number() || v_->is_array()) {
      if (v_->is_number()) {
        c = Color(static_cast<Float>(number(0, 1e30)));
      } else if (v_->size() == static_cast<size_t>(Color::size())) {
        for (int i = 0; i < Color::size(); ++i)
          c[i] = static_cast<Float>(at(static_cast<size_t>(i)).number(0, 1e30));
      } else {
        fail("must be a number, [r, g, b] or an emission spectrum, got " + show(*v_));
      }
      // Beyond RgbIlluminantSpectrum's range (10⁹) the spectrum is left unset, and
      // rgb_illuminant() clamps the components to it.
      if (spectrum && c.max_component() <= RgbIlluminantSpectrum::kMaxComponent)
        *spectrum = Spectrum(RgbIlluminantSpectrum(c[0], c[1], c[2]));
    } else if (v_->is_object()) {
      try {
        Spectrum sp = parse_spectrum(*v_, "emission", SpectrumUse::kEmission, base_dir);
        c = spectrum_to_rgb(sp, SpectrumUse::kEmission);
        if (spectrum) *spectrum = std::move(sp);
      } catch (const InputError& e) {
        fail(e.what());
      }
    } else {
      fail("must be a number, [r, g, b] or an emission spectrum, got " + show(*v_));
    }
    return c;
  }

 private:
  const json* v_;
  const std::string* source_;
  std::string path_;
};

struct Loader {
  std::string source, base_dir;
  Scene scene;
  std::map<std::string, int> named_materials;

  std::string resolve(const std::string& file) const {
    const std::filesystem::path p(file);
    return p.is_absolute() || base_dir.empty() ? file : (std::filesystem::path(base_dir) / p).string();
  }

  static bool is_subsurface(const json& desc) {
    return desc.is_object() && desc.contains("type") && desc["type"] == "subsurface";
  }

  int add_material(const std::string& name, const Node& desc) {
    if (is_subsurface(desc.value())) {
      // The boundary is the BSDF; the medium stays beside it for the path tracer.
      if (const auto t = find_texture(desc)) t->fail("a subsurface material cannot have textures");
      Material m;
      m.name = name;
      m.subsurface = subsurface_from_json(desc.value(), desc.where(), base_dir);
      m.bxdf = m.subsurface->boundary;
      if (m.subsurface->method == SubsurfaceMethod::Diffusion) {
        m.profile = std::make_shared<const DiffusionProfile>(m.subsurface->medium, m.subsurface->eta);
        m.exit_lobe = SwBxDF(m.subsurface->eta);
      }
      scene.materials.push_back(std::move(m));
    } else if (has_texture(desc.value())) {
      Material m = textured_material(desc);
      m.name = name;
      scene.materials.push_back(std::move(m));
    } else {
      MaterialWithSpectra parsed = material_with_spectra_from_json(desc.value(), desc.where(), base_dir);
      Material m;
      m.name = name;
      m.bxdf = std::move(parsed.bxdf);
      m.spectra = std::move(parsed.spectra);
      scene.materials.push_back(std::move(m));
    }
    openpbr_surface(scene.materials.back(), desc);
    return static_cast<int>(scene.materials.size()) - 1;
  }

  // What an `openpbr` material adds to the scene beyond its BSDF (docs/openpbr.md,
  // "Rendering"): its emission, and the medium inside its shape when it transmits with a
  // transmission_depth — absorbing only (Beer–Lambert along each segment, in every colour
  // mode), or scattering (the random walk of a `subsurface` medium, with its limits: RGB,
  // closed shapes).
  void openpbr_surface(Material& m, const Node& desc) {
    if (const auto* g = std::get_if<GltfPbrBxDF>(&m.bxdf.models())) {
      gltf_pbr_surface(m, *g, desc);
      return;
    }
    const auto* model = std::get_if<OpenPbrBxDF>(&m.bxdf.models());
    if (!model) return;
    const OpenPbrParams<Color>& p = model->params;
    m.emits = p.emission_luminance > 0 && !p.emission_color.is_black() && p.geometry_opacity > 0;
    m.emits_both_sides = p.geometry_thin_walled;
    // (No volume where no light can enter it: an all-metal base, or a surface that is all hole.)
    if (p.subsurface_weight > 0 && !p.geometry_thin_walled && m.textures.empty() && p.base_metalness < 1 &&
        p.geometry_opacity > 0) {
      subsurface_volume(m, *model, desc);
      return;
    }
    const auto medium = openpbr::transmission_medium(p);
    if (!medium) return;
    m.inside = inside_model(*model);
    if (medium->sigma_s.is_black()) {
      m.absorption = medium->sigma_a;
      m.absorption_depth = p.transmission_depth;
      try {
        m.absorption_colour.emplace(std::clamp(p.transmission_color[0], Float(0), Float(1)),
                                    std::clamp(p.transmission_color[1], Float(0), Float(1)),
                                    std::clamp(p.transmission_color[2], Float(0), Float(1)));
      } catch (const InputError& e) {
        desc.fail(std::string("openpbr: transmission_color: ") + e.what());
      }
      return;
    }
    Subsurface s;
    s.eta = model->relative_eta();
    s.boundary = m.bxdf;
    s.medium = *medium;
    s.method = SubsurfaceMethod::RandomWalk;
    m.subsurface = s;
  }

  // --- Textures (docs/scene-format.md, "Textures") ---------------------------------

  static bool is_texture(const json& v) { return v.is_object() && (v.contains("texture") || v.contains("checker")); }

  // The first texture object among a material's parameters (alpha's entries and a
  // blend's parts included).
  static std::optional<Node> find_texture(const Node& desc) {
    if (!desc.value().is_object()) return std::nullopt;
    for (auto it = desc.value().begin(); it != desc.value().end(); ++it) {
      const Node v = desc.at(it.key());
      if (is_texture(v.value())) return v;
      if ((it.key() == "alpha" || it.key() == "bsdfs") && v.value().is_array()) {
        for (size_t i = 0; i < v.size(); ++i) {
          if (is_texture(v.value()[i])) return v.at(i);
          if (auto t = find_texture(v.at(i))) return t;
        }
      }
    }
    return std::nullopt;
  }
  static bool has_texture(const json& desc) {
    const std::string none;
    return find_texture(Node(desc, &none, "")).has_value();
  }

  // A textured parameter while the material is checked: where it is, its texture, and
  // where (texel index, or checker entry) its smallest and largest values occur.
  struct Slot {
    Node node;        // the parameter's value: the texture object
    std::string key;  // JSON key
    int entry;        // index into "alpha": [alpha_x, alpha_y], else -1
    MaterialParam param;
    bool scalar;
    std::string file;  // image file as written; empty for a checker
    Texture texture;
    std::array<size_t, kColorChannels> lo_at{}, hi_at{};

    int channels() const { return scalar ? 1 : Color::size(); }
    Color value(size_t i) const {
      if (texture.image) return texture.image->pixels()[i];
      return i == 0 ? texture.a : texture.b;
    }
    json to_json(const Color& c) const {
      if (scalar) return double(c[0]);
      json a = json::array();
      for (int i = 0; i < Color::size(); ++i) a.push_back(double(c[i]));
      return a;
    }
    // Float digits: a texel 0.7 shows as 0.7. A grey colour shows as one number.
    std::string show_value(const Color& c) const {
      auto one = [](Float v) {
        std::ostringstream os;
        os.precision(7);
        os << v;
        return os.str();
      };
      if (scalar || c == Color(c[0])) return one(c[0]);
      std::string s = "[";
      for (int i = 0; i < Color::size(); ++i) s += (i ? ", " : "") + one(c[i]);
      return s + "]";
    }
    void put(json& desc, const json& v) const {
      if (entry < 0) desc[key] = v;
      else desc[key][static_cast<size_t>(entry)] = v;
    }
    // Texel or checker entry i, with its value, is outside what the parser accepts.
    [[noreturn]] void out_of_range(size_t i, const std::string& why) const {
      const std::string v = "value " + show_value(value(i)) + " is out of range (" + why + ")";
      if (!texture.image) node.at("checker").at(i).fail(v);
      const size_t w = static_cast<size_t>(texture.image->width());
      node.fail("texture " + file + ": texel (" + std::to_string(i % w) + ", " + std::to_string(i / w) + ") " + v);
    }
  };

  // A colour (number or [r, g, b]) or, for a scalar parameter, a number; finite as a Float.
  static Color texture_value(const Node& n, bool scalar) {
    auto one = [](const Node& e) {
      const double d = e.number();
      if (!std::isfinite(static_cast<Float>(d))) e.fail("is too large, got " + show(e.value()));
      return static_cast<Float>(d);
    };
    if (n.value().is_number()) return Color(one(n));
    if (!scalar && n.value().is_array() && n.size() == static_cast<size_t>(Color::size())) {
      Color c;
      for (int i = 0; i < Color::size(); ++i) c[i] = one(n.at(static_cast<size_t>(i)));
      return c;
    }
    n.fail(scalar ? "must be a number, got " + show(n.value()) : "must be a number or [r, g, b], got " + show(n.value()));
  }

  std::map<std::pair<std::string, bool>, std::shared_ptr<const Image>> images;

  Slot texture_slot(const Node& n, const std::string& key, int entry, MaterialParam param) {
    Slot s{n, key, entry, param, material_param_info(param).scalar, {}, {}, {}, {}};
    n.object({"texture", "checker", "uv_scale", "srgb"});
    if (n.has("texture") == n.has("checker")) n.fail("give exactly one of \"texture\" (an image file) or \"checker\"");
    Texture& t = s.texture;
    if (n.has("uv_scale")) {
      const Node u = n.at("uv_scale");
      if (u.value().is_number()) {
        t.su = t.sv = static_cast<Float>(u.number(0, 1e6, true));
      } else if (u.value().is_array() && u.size() == 2) {
        t.su = static_cast<Float>(u.at(0).number(0, 1e6, true));
        t.sv = static_cast<Float>(u.at(1).number(0, 1e6, true));
      } else {
        u.fail("must be a number or [su, sv], got " + show(u.value()));
      }
    }
    size_t count = 2;
    if (n.has("checker")) {
      if (n.has("srgb")) n.at("srgb").fail("applies to an image \"texture\", not to a checker");
      const Node c = n.at("checker");
      if (!c.value().is_array() || c.size() != 2)
        c.fail(std::string("must be [a, b], two ") + (s.scalar ? "numbers" : "colours (numbers or [r, g, b])") + ", got " + show(c.value()));
      t.a = texture_value(c.at(0), s.scalar);
      t.b = texture_value(c.at(1), s.scalar);
    } else {
      const Node f = n.at("texture");
      s.file = f.string();
      // Colours are stored sRGB-encoded in 8-bit images; roughness-like numbers are data.
      const bool srgb = n.has("srgb") ? n.at("srgb").boolean() : !s.scalar;
      const std::string path = resolve(s.file);
      auto& image = images[{path, srgb}];
      if (!image) {
        try {
          image = std::make_shared<const Image>(read_image(path, srgb));
        } catch (const InputError& e) {
          images.erase({path, srgb});
          f.fail(e.what());
        }
      }
      if (image->pixels().empty()) f.fail(s.file + ": the image is empty");
      t.image = image;
      count = image->pixels().size();
    }
    // Smallest and largest value per channel, and the first texel (entry) holding each.
    t.lo = t.hi = s.value(0);
    for (size_t i = 0; i < count; ++i) {
      const Color c = s.value(i);
      if (!c.is_finite()) s.out_of_range(i, "not finite");
      for (int ch = 0; ch < Color::size(); ++ch) {
        if (c[ch] < t.lo[ch]) t.lo[ch] = c[ch], s.lo_at[static_cast<size_t>(ch)] = i;
        if (c[ch] > t.hi[ch]) t.hi[ch] = c[ch], s.hi_at[static_cast<size_t>(ch)] = i;
      }
    }
    return s;
  }

  // A material some of whose parameters are textures. Its values are checked by the one
  // parser of materials: first with every texture replaced by a value valid on its own
  // (errors that are not the textures'), then with all textures at their smallest and
  // at their largest values per channel. Every range is an interval and the combined
  // constraints (kd + ks <= 1) grow with each value, so these two corners bound every
  // value a lookup can return (bilinear weights are convex). When a corner fails, the
  // texel responsible is the first one holding an extreme of some channel.
  Material textured_material(const Node& desc) {
    const json& d = desc.value();
    const auto type_it = d.find("type");
    const auto& types = material_type_names();
    if (type_it == d.end() || !type_it->is_string() ||
        std::find(types.begin(), types.end(), type_it->get<std::string>()) == types.end()) {
      material_from_json(d, desc.where(), base_dir);  // throws the parser's message about the type
      desc.fail("material: bad type");
    }
    const std::string type = type_it->get<std::string>();
    if (type == "blend")
      find_texture(desc)->fail("textures inside a blend are not supported (texture a whole material instead)");

    std::vector<Slot> slots;
    for (auto it = d.begin(); it != d.end(); ++it) {
      const Node v = desc.at(it.key());
      const bool whole = is_texture(v.value());
      const bool entries = it.key() == "alpha" && v.value().is_array() && v.size() == 2 &&
                           (is_texture(v.value()[0]) || is_texture(v.value()[1]));
      if (!whole && !entries) continue;
      const auto param = varying_param(type, it.key());
      if (!param) {
        const std::string keys = varying_param_keys(type);
        v.fail("cannot be a texture" + (keys.empty() ? " (" + type + " has no parameter that can)"
                                                      : " (" + type + "'s parameters that can: " + keys + ")"));
      }
      if (const auto why = varying_param_refused(d, it.key())) v.fail("cannot be a texture here: " + *why);
      if (whole) {
        slots.push_back(texture_slot(v, it.key(), -1, *param));
      } else {
        for (int i = 0; i < 2; ++i)
          if (is_texture(v.value()[static_cast<size_t>(i)]))
            slots.push_back(texture_slot(v.at(static_cast<size_t>(i)), it.key(), i, i == 0 ? MaterialParam::AlphaX : MaterialParam::AlphaY));
      }
    }
    json probe = d;
    for (const Slot& s : slots) s.put(probe, material_param_info(s.param).probe);
    material_from_json(probe, desc.where(), base_dir);

    auto why_invalid = [this](const json& description) -> std::optional<std::string> {
      try {
        material_from_json(description, "", base_dir);
      } catch (const InputError& e) {
        return std::string(e.what());
      }
      return std::nullopt;
    };
    json corner[2] = {d, d};
    for (int high = 0; high < 2; ++high) {
      for (const Slot& s : slots) s.put(corner[high], s.to_json(high ? s.texture.hi : s.texture.lo));
      const auto why = why_invalid(corner[high]);
      if (!why) continue;
      // Each candidate texel alone, the other textures at their probes; then with one other
      // texture at the same extreme, for the combined constraints (kd + ks <= 1).
      auto candidate = [&](const Slot& s, int ch) { return (high ? s.hi_at : s.lo_at)[static_cast<size_t>(ch)]; };
      for (const Slot& s : slots) {
        for (int ch = 0; ch < s.channels(); ++ch) {
          json one = probe;
          s.put(one, s.to_json(s.value(candidate(s, ch))));
          if (const auto w = why_invalid(one)) s.out_of_range(candidate(s, ch), *w);
        }
      }
      for (const Slot& s : slots) {
        for (int ch = 0; ch < s.channels(); ++ch) {
          for (const Slot& other : slots) {
            if (&other == &s) continue;
            const Color extreme = high ? other.texture.hi : other.texture.lo;
            json two = probe;
            s.put(two, s.to_json(s.value(candidate(s, ch))));
            other.put(two, other.to_json(extreme));
            if (const auto w = why_invalid(two))
              s.out_of_range(candidate(s, ch), *w + ", with " + other.node.path().substr(desc.path().size() + 1) + " at its " +
                                                   (high ? "largest" : "smallest") + " value " + other.show_value(extreme));
          }
        }
      }
      desc.fail("the textures' " + std::string(high ? "largest" : "smallest") + " values are out of range (" + *why + ")");
    }
    // The largest values: a rough conductor then keeps its multiple-scattering lobe
    // unless every roughness is smooth (with_params).
    MaterialWithSpectra parsed = material_with_spectra_from_json(corner[1], desc.where(), base_dir);
    Material m;
    m.bxdf = std::move(parsed.bxdf);
    m.spectra = std::move(parsed.spectra);
    for (const Slot& s : slots) {
      m.textures.push_back({s.param, s.texture});
      if (int(s.param) < kColourParams) m.textured_colours |= TexturedColours(1) << unsigned(s.param);
    }
    return m;
  }

  // A shape's material: the name of an entry of "materials", or a material object.
  int material_of(const Node& shape) {
    const Node m = shape.required("material");
    if (m.value().is_string()) {
      const auto it = named_materials.find(m.string());
      if (it == named_materials.end()) m.fail("no material named \"" + m.string() + "\" in /materials");
      return it->second;
    }
    return add_material("", m);
  }

  void camera(const Node& n) {
    n.object({"position", "look_at", "up", "fov", "width", "height", "polarizer"});
    Camera& c = scene.camera;
    if (n.has("position")) c.position = n.at("position").vec3();
    if (n.has("look_at")) c.look_at = n.at("look_at").vec3();
    if (n.has("up")) c.up = n.at("up").direction();
    if (n.has("fov")) c.fov_deg = static_cast<Float>(n.at("fov").number(0, 179, true));
    if (n.has("width")) c.width = n.at("width").integer(1, 16384);
    if (n.has("height")) c.height = n.at("height").integer(1, 16384);
    // The film and its per-pixel buffers take some 100 bytes a pixel: bounded so that a
    // render that cannot have its memory is refused before it starts.
    if (std::int64_t(c.width) * c.height > kMaxFilmPixels)
      n.fail("width x height = " + std::to_string(std::int64_t(c.width) * c.height) + " pixels, more than the " +
             std::to_string(kMaxFilmPixels) + " (2^25, e.g. 8192 x 4096) a film may have");
    if (n.has("polarizer")) c.polarizer_deg = static_cast<Float>(n.at("polarizer").number(-360, 360));
    const Vec3 forward = c.look_at - c.position;
    if (!(length_squared(forward) > 0)) n.fail("position and look_at must differ");
    if (!(length_squared(cross(normalize(forward), normalize(c.up))) > 1e-8f)) n.fail("up must not be parallel to the viewing direction");
  }

  void render_settings(const Node& n) {
    n.object({"spp", "max_depth", "rr_depth", "seed", "exposure", "tonemap", "spectral", "polarized", "sampler", "light_sampler"});
    RenderSettings& s = scene.settings;
    if (n.has("spp")) s.spp = n.at("spp").integer(1, 1 << 20);
    if (n.has("max_depth")) s.max_depth = n.at("max_depth").integer(0, 1024);
    if (n.has("rr_depth")) s.rr_depth = n.at("rr_depth").integer(1, 1024);
    if (n.has("seed")) s.seed = static_cast<std::uint64_t>(n.at("seed").integer(0, 2147483647));
    if (n.has("spectral")) s.spectral = n.at("spectral").boolean();
    if (n.has("polarized")) s.polarized = n.at("polarized").boolean();
    if (n.has("exposure")) s.exposure = static_cast<Float>(n.at("exposure").number(-64, 64));
    if (n.has("tonemap")) {
      const std::string t = n.at("tonemap").string();
      if (t != "filmic" && t != "clamp") n.at("tonemap").fail("must be \"filmic\" or \"clamp\", got \"" + t + "\"");
      s.filmic = t == "filmic";
    }
    if (n.has("sampler")) {
      const std::string t = n.at("sampler").string();
      const auto type = sampler_type_from_name(t);
      if (!type) n.at("sampler").fail("must be \"zsobol\", \"sobol\" or \"independent\", got \"" + t + "\"");
      s.sampler = *type;
    }
    if (n.has("light_sampler")) {
      const std::string t = n.at("light_sampler").string();
      const auto type = light_sampler_type_from_name(t);
      if (!type) n.at("light_sampler").fail("must be \"bvh\", \"power\" or \"uniform\", got \"" + t + "\"");
      s.light_sampler = *type;
    }
  }

  // The three corners of a parallelogram; its edges must span an area.
  void quad_geometry(const Node& n, Vec3& corner, Vec3& e1, Vec3& e2) {
    corner = n.required("corner").vec3();
    e1 = n.required("edge1").vec3();
    e2 = n.required("edge2").vec3();
    if (!(length(cross(e1, e2)) > 1e-12f * std::max(Float(1), length_squared(e1) + length_squared(e2))))
      n.fail("edge1 and edge2 must span a parallelogram (non-zero, not parallel)");
  }

  void add_quad_mesh(const Vec3& corner, const Vec3& e1, const Vec3& e2, int material, int light) {
    Mesh m;
    m.positions = {corner, corner + e1, corner + e1 + e2, corner + e2};
    m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    m.tangents.assign(4, normalize(e1));
    m.indices = {0, 1, 2, 0, 2, 3};
    m.material = material;
    m.area_light = light;
    scene.meshes.push_back(std::move(m));
  }

  void shape(const Node& n) {
    if (!n.value().is_object()) n.fail("must be a JSON object, got " + show(n.value()));
    const std::string type = n.required("type").string();
    if (type == "sphere") {
      n.object({"type", "center", "radius", "material"});
      Sphere s;
      s.center = n.required("center").vec3();
      s.radius = static_cast<Float>(n.required("radius").number(0, 1e30, true));
      s.material = material_of(n);
      if (sampled_emitter(scene.materials[static_cast<size_t>(s.material)]))
        s.area_light = emitting_shape(SphereLight{s.center, s.radius, {}, {}}, s.material);
      scene.spheres.push_back(s);
    } else if (type == "quad") {
      n.object({"type", "corner", "edge1", "edge2", "material"});
      Vec3 c, e1, e2;
      quad_geometry(n, c, e1, e2);
      const int material = material_of(n);
      const Material& mat = scene.materials[static_cast<size_t>(material)];
      add_quad_mesh(c, e1, e2, material,
                    sampled_emitter(mat) ? emitting_shape(QuadLight{c, e1, e2, {}, mat.emits_both_sides, {}}, material) : -1);
      check_walkable(n, scene.meshes.back(), "a quad");
    } else if (type == "mesh") {
      n.object({"type", "file", "material", "translate", "scale", "rotate"});
      const Node file = n.required("file");
      const MeshTransform t = shape_transform(n);
      Mesh m = load_obj_mesh(resolve(file.string()), t, file.where());
      m.material = material_of(n);
      check_walkable(n, m, "mesh " + file.string());
      scene.meshes.push_back(std::move(m));
    } else if (type == "gltf") {
      // A glTF file's default scene, with its own materials (SPEC §3); its cameras and
      // lights: the lights are added, the cameras ignored (the scene has its own).
      n.object({"type", "file", "translate", "scale", "rotate"});
      const Node file = n.required("file");
      const MeshTransform t = shape_transform(n);
      append_gltf(scene, resolve(file.string()), t, file.where());
    } else {
      n.at("type").fail("unknown shape type \"" + type + "\" (known: sphere, quad, mesh, gltf)");
    }
  }

  // A random walk needs a medium it cannot leave except through its boundary: the mesh
  // must be closed (every edge shared by exactly two triangles; spheres always are) and
  // consistently wound. A closed mesh wound clockwise seen from outside is turned around,
  // for either method, so that its geometric normals point out, as the boundary's BSDF
  // and the path tracer's test for "into the medium" expect (SPEC §1: the normal is on
  // the side of the first medium).
  void check_walkable(const Node& shape, Mesh& m, const std::string& what) {
    const Material& mat = scene.materials[static_cast<size_t>(m.material)];
    if (!mat.subsurface) return;
    const MeshClosure c = mesh_closure(m);
    if (mat.subsurface->method == SubsurfaceMethod::RandomWalk) {
      const std::string who = "material" + (mat.name.empty() ? std::string() : " \"" + mat.name + "\"") +
                              " (subsurface, random walk) needs a closed mesh: ";
      if (!c.closed())
        shape.fail(who + what + " has " + std::to_string(c.open_edges) + " open edge" + (c.open_edges == 1 ? "" : "s") +
                   " of " + std::to_string(c.edges) + " (an edge must be shared by exactly two triangles)");
      if (c.inconsistent_edges > 0)
        shape.fail(who + what + " is closed but wound inconsistently (" + std::to_string(c.inconsistent_edges) +
                   " edges run the same way by both their triangles)");
    }
    if (c.closed() && c.inconsistent_edges == 0 && c.volume < 0 && m.normals.empty())
      for (size_t t = 0; t + 2 < m.indices.size(); t += 3) std::swap(m.indices[t + 1], m.indices[t + 2]);
  }

  void light(const Node& n) {
    if (!n.value().is_object()) n.fail("must be a JSON object, got " + show(n.value()));
    const std::string type = n.required("type").string();
    if (type == "point") {
      n.object({"type", "position", "intensity"});
      PointLight l;
      l.position = n.required("position").vec3();
      l.intensity = n.required("intensity").color(base_dir, &l.spectrum);
      scene.point_lights.push_back(std::move(l));
    } else if (type == "quad") {
      n.object({"type", "corner", "edge1", "edge2", "radiance", "two_sided"});
      QuadLight q;
      quad_geometry(n, q.corner, q.edge1, q.edge2);
      q.radiance = n.required("radiance").color(base_dir, &q.spectrum);
      if (n.has("two_sided")) q.two_sided = n.at("two_sided").boolean();
      scene.area_lights.emplace_back(q);
      scene.area_light_material.push_back(-1);
      add_quad_mesh(q.corner, q.edge1, q.edge2, emitter_material(), static_cast<int>(scene.area_lights.size()) - 1);
    } else if (type == "sphere") {
      n.object({"type", "center", "radius", "radiance"});
      SphereLight s;
      s.center = n.required("center").vec3();
      s.radius = static_cast<Float>(n.required("radius").number(0, 1e30, true));
      s.radiance = n.required("radiance").color(base_dir, &s.spectrum);
      scene.area_lights.emplace_back(s);
      scene.area_light_material.push_back(-1);
      scene.spheres.push_back({s.center, s.radius, emitter_material(), static_cast<int>(scene.area_lights.size()) - 1});
    } else {
      n.at("type").fail("unknown light type \"" + type + "\" (known: point, quad, sphere)");
    }
  }

  // An emitting `openpbr` sphere or quad is also an area light, so that next-event
  // estimation samples it; its radiance is the largest it emits (normal exitance, no coat or
  // fuzz loss): light_power's estimate for light selection. The path tracer asks the
  // material for what leaves towards each direction. (A mesh, or a textured material,
  // emits only where paths hit it.)
  // A textured material's emission varies over the surface, which a light's uniform
  // radiance cannot say: it is found by paths only (with the textured model), as a mesh's.
  static bool sampled_emitter(const Material& m) { return m.emits && m.textures.empty(); }

  // What a `gltf_pbr` material adds beyond its BSDF (docs/gltf_pbr.md, "Rendering"): its
  // emission (emissive × emissive_strength, a Lambertian emitter on the front face, glTF 2.0
  // §3.9.3), and with a volume (KHR_materials_volume: thickness > 0) the absorbing interior,
  // σa = −ln(attenuation_color) / attenuation_distance (none for an infinite distance).
  void gltf_pbr_surface(Material& m, const GltfPbrBxDF& model, const Node& desc) {
    const GltfPbrParams<Color>& p = model.params;
    m.emits = p.emissive_strength > 0 && !p.emissive.is_black() && model.coverage() > 0;
    if (!model.volume() || !(p.attenuation_distance > 0) || p.attenuation_color == Color(1)) return;
    Color sigma;
    for (int i = 0; i < 3; ++i)
      sigma[i] = openpbr::extinction_from_colour(std::clamp(p.attenuation_color[i], Float(0), Float(1)), p.attenuation_distance);
    m.absorption = sigma;
    m.absorption_depth = p.attenuation_distance;
    try {
      m.absorption_colour.emplace(std::clamp(p.attenuation_color[0], Float(0), Float(1)),
                                  std::clamp(p.attenuation_color[1], Float(0), Float(1)),
                                  std::clamp(p.attenuation_color[2], Float(0), Float(1)));
    } catch (const InputError& e) {
      desc.fail(std::string("gltf_pbr: attenuation_color: ") + e.what());
    }
  }

  // A mesh's or glTF file's "translate", "scale" (a number or [x, y, z]) and "rotate"
  // ({"axis", "degrees"}).
  MeshTransform shape_transform(const Node& n) {
    MeshTransform t;
    if (n.has("translate")) t.translate = n.at("translate").vec3();
    if (n.has("scale")) {
      const Node s = n.at("scale");
      if (s.value().is_number()) {
        const Float k = static_cast<Float>(s.number(0, 1e30, true));
        t.scale = {k, k, k};
      } else {
        if (!s.value().is_array() || s.size() != 3) s.fail("must be a number or [x, y, z], got " + show(s.value()));
        t.scale = {static_cast<Float>(s.at(0).number(0, 1e30, true)), static_cast<Float>(s.at(1).number(0, 1e30, true)),
                   static_cast<Float>(s.at(2).number(0, 1e30, true))};
      }
    }
    if (n.has("rotate")) {
      const Node r = n.at("rotate").object({"axis", "degrees"});
      t.rotate_axis = r.required("axis").direction();
      t.rotate_degrees = static_cast<Float>(r.required("degrees").number());
    }
    return t;
  }

  int emitting_shape(AreaLight light, int material) {
    const BxDF& bxdf = scene.materials[static_cast<size_t>(material)].bxdf;
    Color peak;
    if (const auto* g = std::get_if<GltfPbrBxDF>(&bxdf.models())) peak = g->emission();
    else {
      const auto& model = std::get<OpenPbrBxDF>(bxdf.models());
      peak = model.params.emission_color * model.params.emission_luminance;
    }
    std::visit([&](auto& l) { l.radiance = peak; }, light);
    scene.area_lights.push_back(light);
    scene.area_light_material.push_back(material);
    return static_cast<int>(scene.area_lights.size()) - 1;
  }

  // SPEC-OPB "Subsurface": the subsurface slab is the specular layer's dielectric interface
  // over a scattering volume, mixed into the opaque base with weight S. For the RGB path
  // tracer the material becomes that: its subsurface share of the base turns into
  // transmission through the interface (transmission_weight T + (1 − T) S, subsurface 0),
  // and the shape fills with gonio's `subsurface` medium of albedo subsurface_color and mean
  // free path subsurface_radius × subsurface_radius_scale (μt = 1/r, as the spec has it),
  // whose single-scattering albedo is inverted against that boundary (albedo_inversion.h),
  // and g = subsurface_scatter_anisotropy. It is walked (random_walk.h). Spectral and
  // polarized renders keep the BSDF's subsurface lobe (bxdf/openpbr.h), which `bxdf` still is.
  // The surface seen from the medium inside it. The mixture's weights (metalness,
  // transmission, subsurface, opacity) are shares of the surface seen from outside: light
  // inside the medium is under the transmitting interface only, which it meets whole. The
  // coat and the fuzz lie outside that interface: light inside meets the bare interface
  // (their lobes would reflect it back as if from outside: a coated glass returned up to
  // twice the light at grazing, docs/openpbr.md).
  static OpenPbrBxDF inside_model(const OpenPbrBxDF& model) {
    OpenPbrParams<Color> q = model.params;
    q.transmission_weight = 1;
    q.base_metalness = 0;
    q.subsurface_weight = 0;
    q.geometry_opacity = 1;
    q.coat_weight = 0;
    q.fuzz_weight = 0;
    return OpenPbrBxDF::make(q, model.film, nullptr, {model.metal.fresnel.film, model.glass.film});
  }

  void subsurface_volume(Material& m, const OpenPbrBxDF& model, const Node& desc) {
    const OpenPbrParams<Color>& p = model.params;
    OpenPbrParams<Color> q = p;
    q.transmission_weight = p.transmission_weight + (1 - p.transmission_weight) * p.subsurface_weight;
    q.subsurface_weight = 0;
    const OpenPbrBxDF boundary = OpenPbrBxDF::make(q, model.film, nullptr, {model.metal.fresnel.film, model.glass.film});
    json medium = {{"type", "subsurface"}, {"eta", std::clamp(boundary.relative_eta(), Float(0.25), Float(4))}};
    json albedo = json::array(), mfp = json::array();
    for (int c = 0; c < Color::size(); ++c) {
      albedo.push_back(std::clamp(p.subsurface_color[c], Float(0), Float(0.999)));
      mfp.push_back(std::max(p.subsurface_radius * p.subsurface_radius_scale[c], Float(1e-6)));
    }
    medium["albedo"] = albedo;
    medium["mfp"] = mfp;
    medium["g"] = std::clamp(p.subsurface_scatter_anisotropy, Float(-0.99), Float(0.99));
    const MicrofacetDistribution& d = boundary.glass.distribution;
    if (!d.effectively_smooth()) medium["alpha"] = std::sqrt(d.alpha_x * d.alpha_y);
    Subsurface s = subsurface_from_json(medium, desc.where() + " (its subsurface medium)", base_dir);
    // The inversion takes albedos below 1; a white channel is ϖ = 1 exactly: no absorption.
    for (int c = 0; c < Color::size(); ++c)
      if (p.subsurface_color[c] >= 1) {
        s.medium.sigma_s[c] = s.medium.sigma_t()[c];
        s.medium.sigma_a[c] = 0;
      }
    s.boundary = boundary;
    m.subsurface = s;
    m.subsurface_bsdf_fallback = true;
    m.inside = inside_model(model);
  }

  // Emitters absorb everything they do not emit; they still need a material slot.
  int emitter_material() {
    for (size_t i = 0; i < scene.materials.size(); ++i)
      if (scene.materials[i].name == "<emitter>") return static_cast<int>(i);
    Material m;
    m.name = "<emitter>";
    m.bxdf = DiffuseBxDF{Color(0)};
    m.black_body = true;
    scene.materials.push_back(std::move(m));
    return static_cast<int>(scene.materials.size()) - 1;
  }

  void environment(const Node& n) {
    n.object({"radiance", "file", "scale", "rotation"});
    if (n.has("radiance") == n.has("file")) n.fail("give exactly one of \"radiance\" or \"file\"");
    if (n.has("radiance")) {
      if (n.has("scale") || n.has("rotation")) n.fail("\"scale\" and \"rotation\" apply to an environment \"file\"");
      std::optional<Spectrum> spectrum;
      const Color c = n.at("radiance").color(base_dir, &spectrum);
      scene.environment = Environment(c, std::move(spectrum));
      return;
    }
    const Node file = n.at("file");
    const Float scale = n.has("scale") ? static_cast<Float>(n.at("scale").number(0, 1e30)) : Float(1);
    const Float rotation = n.has("rotation") ? static_cast<Float>(n.at("rotation").number()) : Float(0);
    Image map;
    try {
      const std::string path = resolve(file.string());
      std::string ext = std::filesystem::path(path).extension().string();
      for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
      if (ext == ".exr" || ext == ".png") {
        map = read_image(path, true);
      } else {
        // Any other format OpenImageIO reads (Radiance .hdr, TIFF, JPEG, ...): through the
        // texture layer, 8/16-bit codes decoded from sRGB, float formats as they are.
        const TextureImage t = load_texture_file(path, ColorEncoding::Srgb);
        map = Image(t.width(), t.height());
        for (int y = 0; y < t.height(); ++y)
          for (int x = 0; x < t.width(); ++x) {
            const Rgba& c = t.level(0).at(x, y);
            map.at(x, y) = Color(c.r, c.g, c.b);
          }
      }
    } catch (const InputError& e) {
      file.fail(e.what());
    }
    for (const Color& c : map.pixels())
      if (!c.is_finite() || c.min_component() < 0) file.fail(file.string() + ": pixels must be finite and >= 0");
    scene.environment = Environment(std::move(map), scale, rotation);
  }

  void load(const json& root) {
    const Node r(root, &source, "");
    r.object({"camera", "render", "materials", "shapes", "lights", "environment"});
    if (r.has("camera")) camera(r.at("camera"));
    if (r.has("render")) render_settings(r.at("render"));
    if (r.has("materials")) {
      const Node ms = r.at("materials");
      if (!ms.value().is_object()) ms.fail("must be an object of named materials, got " + show(ms.value()));
      for (auto it = ms.value().begin(); it != ms.value().end(); ++it)
        named_materials[it.key()] = add_material(it.key(), ms.at(it.key()));
    }
    if (r.has("shapes")) {
      const Node shapes = r.at("shapes").array();
      for (size_t i = 0; i < shapes.size(); ++i) shape(shapes.at(i));
    }
    if (r.has("lights")) {
      const Node lights = r.at("lights").array();
      for (size_t i = 0; i < lights.size(); ++i) light(lights.at(i));
    }
    if (r.has("environment")) environment(r.at("environment"));
  }
};

}  // namespace

Scene parse_scene(std::string_view text, const std::string& source, const std::string& base_dir) {
  const json root = parse_json_text(text, source);
  Loader loader{source, base_dir, {}, {}, {}};
  loader.load(root);
  return std::move(loader.scene);
}

Scene load_scene_file(const std::string& path) {
  if (is_gltf_path(path)) return load_gltf_scene(path);
  const std::string text = read_text_file(path, kMaxJsonFileBytes, "a scene file");
  const std::string dir = std::filesystem::path(path).parent_path().string();
  return parse_scene(text, path, dir);
}

}  // namespace gonio::render
