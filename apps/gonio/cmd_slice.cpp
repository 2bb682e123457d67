// gonio slice: the θh × θd image of a BRDF at one φd (BRDF Explorer's view), log-scaled
// with a colour bar; with --compare, a second material beside it on the same scale and
// their relative difference (render/slice.h). Writes an sRGB PNG.

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_io.h"
#include "cli_number.h"
#include "cli_signals.h"
#include "commands.h"
#include "gonio/error.h"
#include "gonio/json_text.h"
#include "gonio/material.h"
#include "gonio/merl.h"
#include "gonio/render/image_output.h"
#include "gonio/render/slice.h"

namespace gonio::cli {

namespace {
struct SliceArgs {
  std::string bsdf, data, compare, output;
  double phi_d = 90;
  std::int64_t size = 180;
  bool sqrt_theta_h = false;
  std::vector<double> range;  // LO HI
  std::optional<double> diff_range;  // absent: automatic
};

// The `measured` material of a MERL file (SPEC §2).
BxDF measured_material(const std::string& path, const std::string& option) {
  const nlohmann::json m = {{"type", "measured"}, {"file", path}};
  return parse_material(m.dump(), option);
}

// Whether `path` is a regular file that starts with the MERL header (int32 90, 90, 180,
// little-endian).
bool has_merl_header(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char h[12];
  if (!in.read(reinterpret_cast<char*>(h), sizeof h)) return false;
  auto le32 = [&](int at) {
    return std::int32_t(std::uint32_t(h[at]) | std::uint32_t(h[at + 1]) << 8 | std::uint32_t(h[at + 2]) << 16 |
                        std::uint32_t(h[at + 3]) << 24);
  };
  return le32(0) == MerlTable::kThetaH && le32(4) == MerlTable::kThetaD && le32(8) == MerlTable::kPhiD;
}

// --compare OTHER: material JSON text, @path to a JSON file, or a MERL file.
BxDF load_other(const std::string& arg) {
  const auto first = arg.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && arg[first] == '{') return parse_material(arg, "--compare");
  if (!arg.empty() && arg[0] == '@') {
    const std::string path = arg.substr(1);
    std::string text;
    try {
      text = read_text_file(path, kMaxJsonFileBytes, "a material file");
    } catch (const InputError& e) {
      throw InputError(std::string("--compare: ") + e.what());
    }
    return parse_material(text, "--compare " + path);
  }
  std::error_code ec;
  const auto st = std::filesystem::status(arg, ec);
  if (st.type() == std::filesystem::file_type::regular && has_merl_header(arg)) return measured_material(arg, "--compare");
  if (st.type() == std::filesystem::file_type::not_found)
    throw InputError("--compare " + arg + ": neither material JSON nor an existing file");
  throw InputError("--compare " + arg + ": not a MERL table (no 90 x 90 x 180 header) and not material JSON");
}

void run_slice(const SliceArgs& a) {
  if (a.bsdf.empty() == a.data.empty()) throw InputError("slice: give one of --bsdf JSON and --data FILE");
  if (lower_extension(a.output) != ".png") throw InputError("-o " + a.output + ": the output must end in .png");
  render::SliceOptions o;
  o.size = int(a.size);
  if (!(a.phi_d >= 0 && a.phi_d <= 180)) throw InputError("--phi-d " + format_number(a.phi_d) + ": must be 0 to 180 degrees");
  o.phi_d = a.phi_d * (kPiD / 180);
  o.theta_h_axis = a.sqrt_theta_h ? render::ThetaHAxis::Sqrt : render::ThetaHAxis::Linear;
  if (!a.range.empty()) {
    if (!(a.range[0] > 0 && a.range[1] > a.range[0] && std::isfinite(a.range[1])))
      throw InputError("--range " + format_number(a.range[0]) + " " + format_number(a.range[1]) +
                       ": must be LOW HIGH with 0 < LOW < HIGH");
    o.lo = a.range[0], o.hi = a.range[1];
  }
  if (a.diff_range) {
    // 0 is the library's "automatic"; given on the command line it is a scale of no width.
    if (!(*a.diff_range > 0 && std::isfinite(*a.diff_range)))
      throw InputError("--diff-range " + format_number(*a.diff_range) + ": must be a positive fraction");
    o.diff_range = *a.diff_range;
  }

  // An unwritable location fails before any work; a signal removes the temporary.
  install_stop_signals();
  std::optional<render::ImageOutput> out;
  create_removable([&] { return out.emplace(a.output).temporary_path(); });
  const BxDF first = a.data.empty() ? load_bsdf(a.bsdf) : measured_material(a.data, "--data");
  std::unique_ptr<BxDF> other;
  if (!a.compare.empty()) other = std::make_unique<BxDF>(load_other(a.compare));
  const render::SliceFigure fig = render::make_slice(first, other.get(), o);
  out->write_png(fig.image, {0, render::ToneMap::Clamp});
  std::cout << a.output << "\n";
}
}  // namespace

void register_slice(CLI::App& app) {
  auto args = std::make_shared<SliceArgs>();
  auto* cmd = app.add_subcommand(
      "slice",
      "Write the θh × θd image of f at one φd (luminance, log scale, colour bar) as PNG; with --compare, "
      "a second material and the relative difference beside it");
  auto* bsdf = cmd->add_option("--bsdf", args->bsdf, "material JSON text, or @path to a file holding it");
  auto* data = cmd->add_option("--data", args->data, "a MERL table (the material {\"type\":\"measured\",\"file\":FILE})");
  bsdf->excludes(data);
  cmd->add_option("-o,--output", args->output, "output image (.png)")->required();
  cmd->add_option("--compare", args->compare,
                  "second material: JSON text, @path to a JSON file, or a MERL file; shown beside the first with "
                  "(B - A) / A");
  cmd->add_option("--phi-d", args->phi_d, "difference azimuth φd in degrees, 0 to 180 (default 90)")
      ->check(decimal_number());
  cmd->add_option("--size", args->size, "side of each panel in pixels, 16 to 2048 (default 180)")
      ->transform(decimal_in_range(render::kMinSliceSize, render::kMaxSliceSize));
  cmd->add_flag("--sqrt-theta-h", args->sqrt_theta_h, "θh axis linear in √θh (the MERL bins' spacing)");
  cmd->add_option("--range", args->range, "LOW HIGH: the colour scale of f in 1/sr (default: whole decades around the values)")
      ->expected(2)
      ->check(decimal_number());
  cmd->add_option("--diff-range", args->diff_range,
                  "half-width of the difference scale as a fraction > 0, e.g. 0.1 for ±10% (default: automatic)")
      ->check(decimal_number());
  cmd->callback([args] { run_slice(*args); });
}

}  // namespace gonio::cli
