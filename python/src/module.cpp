// gonio._gonio: the Python face of gonio (SPEC §4; docs/python.md). Every array call runs
// in C++ over the whole array through the batch API (gonio/batch.h), with the GIL
// released and one contiguous range per core (parallel.h). Bad input raises ValueError
// with the message the CLI prints after "gonio: ".

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "gonio/batch.h"
#include "gonio/bxdf/thin_film.h"
#include "gonio/fresnel.h"
#include "gonio/math/degrees.h"
#include "gonio/json_text.h"
#include "gonio/material.h"
#include "gonio/merl.h"
#include "gonio/named_index.h"
#include "gonio/io/notes.h"
#include "gonio/reflectance.h"
#include "gonio/spectral_material.h"
#include "gonio/tabulate.h"
#include "gonio/subsurface/diffusion.h"
#include "gonio/subsurface/slab_walk.h"
#include "gonio/subsurface/subsurface.h"
#include "gonio/validate.h"
#include "gonio/version.h"
#include "convert.h"
#include "parallel.h"

#ifdef GONIO_PYTHON_RENDER
#include "gonio/render/image_output.h"
#include "gonio/render/renderer.h"
#include "gonio/render/scene_loader.h"
#include "measure_binding.h"
#endif
#ifdef GONIO_PYTHON_FIT
#include "gonio/fit/fit.h"
#include "gonio/fit/metric.h"
#endif

namespace py = pybind11;

namespace gonio::python {
namespace {

// --- arrays ---------------------------------------------------------------------------

using DoubleArray = py::array_t<double, py::array::forcecast>;

// A read-only (N, 3) or (3,) view of doubles; a (3,) array is one row for every index.
struct Rows3 {
  const char* base = nullptr;
  py::ssize_t row_stride = 0, col_stride = 0;
  std::size_t n = 0;  // rows; 1 with row_stride 0 for a (3,) array
  double at(std::size_t i, int c) const {
    return *reinterpret_cast<const double*>(base + py::ssize_t(i) * row_stride + c * col_stride);
  }
};

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

Rows3 rows3(const DoubleArray& a, const char* name) {
  if (a.ndim() == 1 && a.shape(0) == 3) return {reinterpret_cast<const char*>(a.data()), 0, a.strides(0), 1};
  if (a.ndim() == 2 && a.shape(1) == 3)
    return {reinterpret_cast<const char*>(a.data()), a.strides(0), a.strides(1), std::size_t(a.shape(0))};
  throw InputError(std::string(name) + " must have shape (N, 3) or (3,), got " + shape_text(a));
}

// The common length of two row sets, either of which may be a single row.
std::size_t broadcast(const Rows3& a, const Rows3& b, const char* na, const char* nb) {
  if (a.n == b.n || b.n == 1) return a.n;
  if (a.n == 1) return b.n;
  throw InputError(std::string(na) + " and " + nb + " have different lengths: " + std::to_string(a.n) + " and " +
                   std::to_string(b.n));
}

[[gnu::noinline]] void note_bad_row(std::size_t k, std::atomic<std::size_t>& first_bad) {
  std::size_t cur = first_bad.load();
  while (k < cur && !first_bad.compare_exchange_weak(cur, k)) {
  }
}

// Row i of r (row 0 of a single row) as a unit vector; a bad row records its index in
// first_bad (the lowest one wins) and gives the normal, so that the loop runs on.
[[gnu::always_inline]] inline Vec3 row_direction(const Rows3& r, std::size_t i, std::atomic<std::size_t>& first_bad) {
  const std::size_t k = r.n == 1 ? 0 : i;
  const auto w = unit_direction(r.at(k, 0), r.at(k, 1), r.at(k, 2));
  if (w) [[likely]]
    return *w;
  note_bad_row(k, first_bad);
  return Vec3{0, 0, 1};
}

// Rows s .. s + c of a and b as unit vectors, both at once (unit_direction_pair); a row
// pair with a bad member is redone one at a time to find which.
[[gnu::always_inline]] inline void row_directions(const Rows3& a, const Rows3& b, std::size_t s, std::size_t c,
                                                  Vec3* wa, Vec3* wb, std::atomic<std::size_t>& bad_a,
                                                  std::atomic<std::size_t>& bad_b) {
  // The common case, two C-contiguous (N, 3) arrays, without the strides and broadcasts.
  constexpr py::ssize_t kRow = 3 * sizeof(double), kCol = sizeof(double);
  if (a.n == b.n && a.row_stride == kRow && a.col_stride == kCol && b.row_stride == kRow && b.col_stride == kCol) {
    const double* pa = reinterpret_cast<const double*>(a.base) + 3 * s;
    const double* pb = reinterpret_cast<const double*>(b.base) + 3 * s;
    if (!unit_direction_rows(pa, pb, c, wa, wb)) [[unlikely]]
      for (std::size_t j = 0; j < c; ++j)
        if (!unit_direction_pair(pa + 3 * j, pb + 3 * j, wa[j], wb[j])) {
          wa[j] = row_direction(a, s + j, bad_a);
          wb[j] = row_direction(b, s + j, bad_b);
        }
    return;
  }
  for (std::size_t j = 0; j < c; ++j) {
    const std::size_t ka = a.n == 1 ? 0 : s + j, kb = b.n == 1 ? 0 : s + j;
    const double ra[3] = {a.at(ka, 0), a.at(ka, 1), a.at(ka, 2)}, rb[3] = {b.at(kb, 0), b.at(kb, 1), b.at(kb, 2)};
    if (!unit_direction_pair(ra, rb, wa[j], wb[j])) [[unlikely]] {
      wa[j] = row_direction(a, s + j, bad_a);
      wb[j] = row_direction(b, s + j, bad_b);
    }
  }
}

// The same message for every thread count: the first bad row.
void raise_bad_row(const Rows3& r, std::size_t k, const char* name) {
  const bool finite = std::isfinite(r.at(k, 0)) && std::isfinite(r.at(k, 1)) && std::isfinite(r.at(k, 2));
  throw InputError(std::string(name) + "[" + std::to_string(k) + "] " +
                   (finite ? "is a zero vector" : "is not a finite vector"));
}

template <typename T>
py::array_t<T> empty_array(std::vector<py::ssize_t> shape) {
  return py::array_t<T>(shape);
}

// `mode` as the CLI's --mode takes it. A str only: pybind11 would turn bytes (b"radiance")
// into the same std::string, and a bytes value is not the text the docs name.
TransportMode parse_mode(const py::object& mode_arg) {
  if (!py::isinstance<py::str>(mode_arg))
    throw InputError("mode must be the str \"radiance\" or \"importance\", got " +
                     escape_control(py::repr(mode_arg).cast<std::string>()) + " (" +
                     py::str(py::type::of(mode_arg).attr("__name__")).cast<std::string>() + ")");
  const std::string mode = mode_arg.cast<std::string>();
  if (mode == "radiance") return TransportMode::Radiance;
  if (mode == "importance") return TransportMode::Importance;
  // CLI11's IsMember message for --mode, in the module's words.
  throw InputError("mode must be \"radiance\" or \"importance\", got \"" + escape_control(mode) + "\"");
}

// Chunk of directions normalised at a time: on the stack, then one batch call.
constexpr std::size_t kChunk = 256;

// --- materials ------------------------------------------------------------------------

// A material at one wavelength: the spectra, the scratch its blend parts live in and
// the spectral model pointing into it (as `gonio eval --wavelength`).
struct AtWavelength {
  MaterialWithSpectra material;
  SpectralScratch scratch;
  SampledWavelengths wavelengths;
  SpectralBxDF bxdf;
};

class Material {
 public:
  Material(const py::object& description, std::optional<double> wavelength) : json_(json_text_of(description)) {
    // "Material" as the source: the CLI's message for the same text, named after the Python
    // class rather than the command line's option (which a Python user never typed).
    if (!wavelength) {
      rgb_ = parse_material(json_, "Material");
      return;
    }
    const double nm = *wavelength;
    if (!std::isfinite(nm) || nm < double(kLambdaMin) || nm > double(kLambdaMax))
      throw InputError("wavelength must be a number of nanometres in [" + format_number(double(kLambdaMin)) + ", " +
                       format_number(double(kLambdaMax)) + "], got " + format_number(nm));
    auto s = std::make_shared<AtWavelength>();
    s->material = parse_material_with_spectra(json_, "Material");
    s->wavelengths = SampledWavelengths::single(Float(nm));
    s->bxdf = to_spectral(s->material.bxdf, s->material.spectra, s->wavelengths, s->scratch);
    rgb_ = s->material.bxdf;
    spectral_ = std::move(s);
    wavelength_ = nm;
  }

  // fn(model, channels): the RGB model (3 channels) or the spectral one at the
  // wavelength (1 channel: slot 0, as the CLI prints).
  template <typename F>
  decltype(auto) with_model(F&& fn) const {
    if (spectral_) return fn(spectral_->bxdf, 1);
    return fn(rgb_, 3);
  }

  const BxDF& rgb() const { return rgb_; }
  const std::string& json() const { return json_; }
  std::optional<double> wavelength() const { return wavelength_; }
  int channels() const { return spectral_ ? 1 : 3; }

 private:
  std::string json_;
  BxDF rgb_;
  std::shared_ptr<AtWavelength> spectral_;
  std::optional<double> wavelength_;
};

template <typename C>
void store_colour(float* out, const C& c, int channels) {
  for (int k = 0; k < channels; ++k) out[k] = c[k];
}

py::tuple eval(const Material& m, const DoubleArray& wo_a, const DoubleArray& wi_a, const py::object& mode_name,
               int threads) {
  checked_threads(threads);
  const TransportMode mode = parse_mode(mode_name);
  const Rows3 wo = rows3(wo_a, "wo"), wi = rows3(wi_a, "wi");
  const std::size_t n = broadcast(wo, wi, "wo", "wi");
  const int ch = m.channels();
  auto f = empty_array<float>({py::ssize_t(n), ch});
  auto pdf = empty_array<float>({py::ssize_t(n)});
  float* fp = f.mutable_data();
  float* pp = pdf.mutable_data();
  std::atomic<std::size_t> bad_wo{n}, bad_wi{n};
  {
    py::gil_scoped_release release;
    m.with_model([&](const auto& bxdf, int channels) {
      using C = typename std::decay_t<decltype(bxdf)>::color_type;
      parallel_ranges(n, threads, [&](std::size_t begin, std::size_t end) {
        Vec3 o[kChunk], i[kChunk];
        C fc[kChunk];
        for (std::size_t s = begin; s < end; s += kChunk) {
          const std::size_t c = std::min(kChunk, end - s);
          row_directions(wo, wi, s, c, o, i, bad_wo, bad_wi);
          if constexpr (std::is_same_v<C, Color>) {
            // Color is three packed floats: the batch writes straight into the array.
            static_assert(sizeof(Color) == 3 * sizeof(float));
            eval_batch<C>(bxdf, std::span<const Vec3>(o, c), std::span<const Vec3>(i, c),
                          mode, std::span<C>(reinterpret_cast<C*>(fp + 3 * s), c), std::span<Float>(pp + s, c));
          } else {
            eval_batch<C>(bxdf, std::span<const Vec3>(o, c), std::span<const Vec3>(i, c), mode,
                          std::span<C>(fc, c), std::span<Float>(pp + s, c));
            for (std::size_t j = 0; j < c; ++j) store_colour(fp + std::size_t(channels) * (s + j), fc[j], channels);
          }
        }
      });
      return 0;
    });
  }
  if (bad_wo.load() < n) raise_bad_row(wo, bad_wo.load(), "wo");
  if (bad_wi.load() < n) raise_bad_row(wi, bad_wi.load(), "wi");
  return py::make_tuple(f, pdf);
}

py::array_t<float> pdf(const Material& m, const DoubleArray& wo_a, const DoubleArray& wi_a,
                       const py::object& mode_name, int threads) {
  checked_threads(threads);
  const TransportMode mode = parse_mode(mode_name);
  const Rows3 wo = rows3(wo_a, "wo"), wi = rows3(wi_a, "wi");
  const std::size_t n = broadcast(wo, wi, "wo", "wi");
  auto pdf = empty_array<float>({py::ssize_t(n)});
  float* pp = pdf.mutable_data();
  std::atomic<std::size_t> bad_wo{n}, bad_wi{n};
  {
    py::gil_scoped_release release;
    m.with_model([&](const auto& bxdf, int) {
      using C = typename std::decay_t<decltype(bxdf)>::color_type;
      parallel_ranges(n, threads, [&](std::size_t begin, std::size_t end) {
        Vec3 o[kChunk], i[kChunk];
        for (std::size_t s = begin; s < end; s += kChunk) {
          const std::size_t c = std::min(kChunk, end - s);
          row_directions(wo, wi, s, c, o, i, bad_wo, bad_wi);
          pdf_batch<C>(bxdf, std::span<const Vec3>(o, c), std::span<const Vec3>(i, c), mode,
                       std::span<Float>(pp + s, c));
        }
      });
      return 0;
    });
  }
  if (bad_wo.load() < n) raise_bad_row(wo, bad_wo.load(), "wo");
  if (bad_wi.load() < n) raise_bad_row(wi, bad_wi.load(), "wi");
  return pdf;
}

// u in [0, 1), kept below 1 after rounding to float (as `gonio sample`). A broadcast view
// (row stride 0: np.broadcast_to of one row) holds one row however many it shows.
std::optional<std::string> check_u(const Rows3& u) {
  const std::size_t distinct = u.row_stride == 0 ? std::min<std::size_t>(u.n, 1) : u.n;
  for (std::size_t i = 0; i < distinct; ++i)
    for (int c = 0; c < 3; ++c) {
      const double v = u.at(i, c);
      if (!(v >= 0 && v < 1))
        return "u[" + std::to_string(i) + ", " + std::to_string(c) + "] must be in [0, 1), got " + format_number(v);
    }
  return std::nullopt;
}

py::tuple sample(const Material& m, const DoubleArray& wo_a, const DoubleArray& u_a, const py::object& mode_name,
                 int threads) {
  checked_threads(threads);
  const TransportMode mode = parse_mode(mode_name);
  const Rows3 wo = rows3(wo_a, "wo"), u = rows3(u_a, "u");
  const std::size_t n = broadcast(wo, u, "wo", "u");
  // The outputs first, as eval and pdf do: rows too many for memory fail at once
  // (MemoryError naming the size), not after every u was checked.
  const int ch = m.channels();
  auto wi = empty_array<float>({py::ssize_t(n), 3});
  auto weight = empty_array<float>({py::ssize_t(n), ch});
  auto pdf = empty_array<float>({py::ssize_t(n)});
  auto delta = empty_array<bool>({py::ssize_t(n)});
  auto lobe = empty_array<std::uint8_t>({py::ssize_t(n)});
  if (const auto e = check_u(u)) throw InputError(*e);
  float* wip = wi.mutable_data();
  float* wp = weight.mutable_data();
  float* pp = pdf.mutable_data();
  auto* dp = reinterpret_cast<std::uint8_t*>(delta.mutable_data());
  auto* lp = reinterpret_cast<BatchLobe*>(lobe.mutable_data());
  std::atomic<std::size_t> bad_wo{n};
  {
    py::gil_scoped_release release;
    m.with_model([&](const auto& bxdf, int channels) {
      using C = typename std::decay_t<decltype(bxdf)>::color_type;
      parallel_ranges(n, threads, [&](std::size_t begin, std::size_t end) {
        Vec3 o[kChunk], wic[kChunk];
        SampleUniforms uc[kChunk];
        C wc[kChunk];
        static_assert(sizeof(Vec3) == 3 * sizeof(float));
        for (std::size_t s = begin; s < end; s += kChunk) {
          const std::size_t c = std::min(kChunk, end - s);
          for (std::size_t j = 0; j < c; ++j) {
            o[j] = row_direction(wo, s + j, bad_wo);
            const std::size_t k = u.n == 1 ? 0 : s + j;
            uc[j] = {std::min(Float(u.at(k, 0)), kOneMinusEpsilon), std::min(Float(u.at(k, 1)), kOneMinusEpsilon),
                     std::min(Float(u.at(k, 2)), kOneMinusEpsilon)};
          }
          sample_batch<C>(bxdf, std::span<const Vec3>(o, c), std::span<const SampleUniforms>(uc, c), mode,
                          {std::span<Vec3>(wic, c), std::span<C>(wc, c), std::span<Float>(pp + s, c),
                           std::span<std::uint8_t>(dp + s, c), std::span<BatchLobe>(lp + s, c)});
          for (std::size_t j = 0; j < c; ++j) {
            float* w3 = wip + 3 * (s + j);
            w3[0] = wic[j].x;
            w3[1] = wic[j].y;
            w3[2] = wic[j].z;
            store_colour(wp + std::size_t(channels) * (s + j), wc[j], channels);
          }
        }
      });
      return 0;
    });
  }
  if (bad_wo.load() < n) raise_bad_row(wo, bad_wo.load(), "wo");
  return py::make_tuple(wi, weight, pdf, delta, lobe);
}

// --- albedo -----------------------------------------------------------------------------

template <typename C>
py::array_t<float> colour_rows(const std::vector<C>& v, int channels) {
  auto a = empty_array<float>({py::ssize_t(v.size()), channels});
  float* p = a.mutable_data();
  for (std::size_t i = 0; i < v.size(); ++i) store_colour(p + std::size_t(channels) * i, v[i], channels);
  return a;
}

double checked_degrees(double v, double lo, double hi, const char* name) {
  if (!std::isfinite(v) || v < lo || v > hi)
    throw InputError(std::string(name) + " must be in [" + format_number(lo) + ", " + format_number(hi) +
                     "] degrees, got " + format_number(v));
  return v * kPiD / 180;
}

py::dict albedo(const Material& m, const DoubleArray& theta_a, double phi, bool inside, std::int64_t samples,
                std::int64_t seed, int threads) {
  checked_threads(threads);
  if (theta_a.ndim() > 1) throw InputError("theta must be a number or a 1-D array, got shape " + shape_text(theta_a));
  const std::size_t n = theta_a.ndim() == 0 ? 1 : std::size_t(theta_a.shape(0));
  const double p = checked_degrees(phi, -360, 360, "phi");
  std::vector<double> thetas(n);
  for (std::size_t i = 0; i < n; ++i) {
    thetas[i] = theta_a.ndim() == 0 ? *theta_a.data() : theta_a.at(py::ssize_t(i));
    checked_degrees(thetas[i], 0, 90, "theta");
  }
  const ReflectanceOptions opt{checked_count(samples, 1, 1'000'000'000'000, "samples"),
                               checked_count(seed, 0, 2'147'483'647, "seed")};
  return m.with_model([&](const auto& bxdf, int channels) {
    using C = typename std::decay_t<decltype(bxdf)>::color_type;
    std::vector<AlbedoEstimateT<C>> est(n);
    {
      py::gil_scoped_release release;
      // One angle per task, each with the same seed: entry i equals `gonio albedo --theta`.
      parallel_ranges(
          n, threads,
          [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
              const double t = thetas[i] * kPiD / 180, z = std::cos(t);
              const Vec3 wo{Float(std::sin(t) * std::cos(p)), Float(std::sin(t) * std::sin(p)),
                            Float(inside ? -z : z)};
              est[i] = directional_albedo(bxdf, wo, opt);
            }
          },
          1);
    }
    auto pick = [&](auto member) {
      std::vector<C> v(n);
      for (std::size_t i = 0; i < n; ++i) v[i] = est[i].*member;
      return colour_rows(v, channels);
    };
    py::array_t<bool> exact{py::ssize_t(n)};
    for (std::size_t i = 0; i < n; ++i) exact.mutable_at(py::ssize_t(i)) = est[i].exact;
    py::dict d;
    d["theta"] = py::array_t<double>(py::ssize_t(n), thetas.data());
    d["reflectance"] = pick(&AlbedoEstimateT<C>::reflectance);
    d["transmittance"] = pick(&AlbedoEstimateT<C>::transmittance);
    d["albedo"] = pick(&AlbedoEstimateT<C>::albedo);
    d["stderr"] = pick(&AlbedoEstimateT<C>::se_albedo);
    d["stderr_reflectance"] = pick(&AlbedoEstimateT<C>::se_reflectance);
    d["stderr_transmittance"] = pick(&AlbedoEstimateT<C>::se_transmittance);
    d["exact"] = exact;
    // A model that is not reciprocal: the light's figures too (SPEC §3).
    if (n > 0 && est[0].light) {
      auto light = [&](auto member) {
        std::vector<C> v(n);
        for (std::size_t i = 0; i < n; ++i) v[i] = (*est[i].light).*member;
        return colour_rows(v, channels);
      };
      d["reflectance_light"] = light(&AlbedoSplitT<C>::reflectance);
      d["transmittance_light"] = light(&AlbedoSplitT<C>::transmittance);
      d["stderr_reflectance_light"] = light(&AlbedoSplitT<C>::se_reflectance);
      d["stderr_transmittance_light"] = light(&AlbedoSplitT<C>::se_transmittance);
    }
    return d;
  });
}

// --- the validator --------------------------------------------------------------------

py::dict check(const Material& m, std::int64_t seed, double scale) {
  const ValidationOptions opt{checked_count(seed, 0, 2'147'483'647, "seed"), scale};
  if (!(scale > 0 && scale <= 1e3)) throw InputError("scale must be in (0, 1000], got " + format_number(scale));
  ValidationReport report;
  {
    py::gil_scoped_release release;
    report = validate(m.rgb(), opt);
  }
  py::list props;
  for (const auto& p : report.properties) {
    py::dict d;
    d["name"] = p.name;
    d["figure"] = p.figure ? py::object(py::float_(*p.figure)) : py::object(py::none());
    d["threshold"] = p.threshold;
    d["pass"] = p.pass;
    d["detail"] = p.detail;
    props.append(d);
  }
  py::dict out;
  out["pass"] = report.pass();
  out["name"] = m.rgb().name();
  out["properties"] = props;
  return out;
}

// `gonio tabulate`: the material written as a MERL table at `path` (tabulate.h; the same
// file the CLI writes). Returns what the CLI prints.
py::dict tabulate_material(const Material& m, const std::string& path) {
  MerlTable table;
  {
    py::gil_scoped_release release;
    table = tabulate(m.rgb());
    write_merl(path, table);
  }
  std::size_t missing = 0;
  for (std::size_t e = 0; e < MerlTable::kEntries; ++e) missing += table.rgb[3 * e] < 0;
  py::dict out;
  out["file"] = path;
  out["entries"] = MerlTable::kEntries;
  out["below_horizon"] = missing;
  return out;
}

// --- Fresnel ----------------------------------------------------------------------------

// A 1-D view of a number or an array (0-D: one element for every index).
struct Vec1 {
  DoubleArray a;
  std::size_t n;
  double operator[](std::size_t i) const { return a.ndim() == 0 ? *a.data() : a.at(py::ssize_t(n == 1 ? 0 : i)); }
};
Vec1 vec1(const DoubleArray& a, const char* name) {
  if (a.ndim() > 1) throw InputError(std::string(name) + " must be a number or a 1-D array, got shape " + shape_text(a));
  return {a, a.ndim() == 0 ? 1 : std::size_t(a.shape(0))};
}

// fresnel(theta, eta, k) as `gonio fresnel`: per angle in degrees, Rs, Rp, R, T, cos_t
// (0 and tir True under total internal reflection; 0 for a conductor) and Schlick.
py::dict fresnel(const DoubleArray& theta_a, double eta, double k, const std::optional<std::string>& material,
                 std::optional<double> wavelength) {
  const Vec1 theta = vec1(theta_a, "theta");
  std::vector<std::pair<double, double>> index;
  std::optional<Float> nm;
  if (wavelength) {
    if (!(*wavelength >= double(kLambdaMin) && *wavelength <= double(kLambdaMax)))
      throw InputError("wavelength must be a number of nanometres in [" + format_number(double(kLambdaMin)) + ", " +
                       format_number(double(kLambdaMax)) + "], got " + format_number(*wavelength));
    nm = Float(*wavelength);
  }
  if (material) {
    index = named_index(*material, nm);
  } else {
    check_fresnel_index(eta, k);
    index.emplace_back(eta, k);
  }
  for (std::size_t i = 0; i < theta.n; ++i)
    if (!(theta[i] >= 0 && theta[i] <= 90))
      throw InputError("--theta must be in [0, 90] degrees, got " + format_number(theta[i]));
  const std::size_t n = theta.n, ch = index.size();
  std::vector<py::ssize_t> shape = ch == 1 ? std::vector<py::ssize_t>{py::ssize_t(n)}
                                           : std::vector<py::ssize_t>{py::ssize_t(n), py::ssize_t(ch)};
  py::array_t<double> rs(shape), rp(shape), r(shape), t(shape), cos_t(shape), schlick(shape);
  py::array_t<bool> tir(shape);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t c = 0; c < ch; ++c) {
      const auto [e, kk] = index[c];
      const double cos_i = cos_degrees(theta[i]);  // as the CLI: exact at 30°, 60°, 90°
      const FresnelTerms<double> f = fresnel_terms(cos_i, e, kk);
      const std::size_t j = i * ch + c;
      rs.mutable_data()[j] = f.rs;
      rp.mutable_data()[j] = f.rp;
      r.mutable_data()[j] = f.r();
      t.mutable_data()[j] = 1 - f.r();
      cos_t.mutable_data()[j] = kk > 0 || f.tir ? 0.0 : f.cos_t;
      tir.mutable_data()[j] = f.tir;
      schlick.mutable_data()[j] = fresnel_schlick_terms(cos_i, e, kk);
    }
  std::vector<double> angles(n);
  for (std::size_t i = 0; i < n; ++i) angles[i] = theta[i];
  py::dict d;
  d["theta"] = py::array_t<double>(py::ssize_t(n), angles.data());
  d["Rs"] = rs;
  d["Rp"] = rp;
  d["R"] = r;
  d["T"] = t;
  d["cos_t"] = cos_t;
  d["tir"] = tir;
  d["schlick"] = schlick;
  py::list eta_l, k_l;
  for (const auto& [e, kk] : index) {
    eta_l.append(e);
    k_l.append(kk);
  }
  d["eta"] = eta_l;
  d["k"] = k_l;
  return d;
}

// thin_film(theta, wavelength, thickness, film_eta, ...): the reflectance of a film on an
// interface from the outside (SPEC §2 "thin_film"), by the models' own Airy sum
// (bxdf/thin_film.h) at each (θ, λ, d); the arguments broadcast as numbers or 1-D arrays
// of one common length.
py::dict thin_film(const DoubleArray& theta_a, const DoubleArray& nm_a, const DoubleArray& d_a, double film_eta,
                   double eta, double k, const std::optional<std::string>& material) {
  const Vec1 theta = vec1(theta_a, "theta"), nm = vec1(nm_a, "wavelength"), d = vec1(d_a, "thickness");
  std::size_t n = 1;
  for (const Vec1* v : {&theta, &nm, &d}) {
    if (v->n == 1) continue;
    if (n != 1 && v->n != n)
      throw InputError("theta, wavelength and thickness must be numbers or arrays of one length, got lengths " +
                       std::to_string(theta.n) + ", " + std::to_string(nm.n) + ", " + std::to_string(d.n));
    n = v->n;
  }
  // The ranges of the material descriptions (SPEC §2 "thin_film").
  if (!(film_eta >= 1 && film_eta <= 1e4)) throw InputError("film_eta must be in [1, 10000], got " + format_number(film_eta));
  if (!material) check_fresnel_index(eta, k);
  std::vector<double> rs(n), rp(n), r(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!(theta[i] >= 0 && theta[i] <= 90)) throw InputError("theta must be in [0, 90] degrees, got " + format_number(theta[i]));
    if (!(nm[i] >= double(kLambdaMin) && nm[i] <= double(kLambdaMax)))
      throw InputError("wavelength must be a number of nanometres in [" + format_number(double(kLambdaMin)) + ", " +
                       format_number(double(kLambdaMax)) + "], got " + format_number(nm[i]));
    if (!(d[i] >= 0 && d[i] <= 1e4)) throw InputError("thickness must be in [0, 10000] nm, got " + format_number(d[i]));
    double n3 = eta, k3 = k;
    if (material) std::tie(n3, k3) = named_index(*material, Float(nm[i])).front();
    const double cos_i = cos_degrees(theta[i]);
    const FilmAmplitudes<double> a = airy_film<double>(cos_i, film_eta, d[i], n3, k3, nm[i]);
    rs[i] = a.Rs;
    rp[i] = a.Rp;
    r[i] = a.R();
  }
  py::dict out;
  out["Rs"] = py::array_t<double>(py::ssize_t(n), rs.data());
  out["Rp"] = py::array_t<double>(py::ssize_t(n), rp.data());
  out["R"] = py::array_t<double>(py::ssize_t(n), r.data());
  return out;
}

// "name" for a number, "name[i]" for an element of an array.
std::string element_name(const char* name, const DoubleArray& a, std::size_t i) {
  return a.ndim() == 0 ? std::string(name) : std::string(name) + "[" + std::to_string(i) + "]";
}

// Element-wise Fresnel functions of the core on arrays (cos_i signed as in fresnel.h).
// A cosine must be a number in [−1, 1]; up to 1e-6 beyond (the rounding of a dot product
// of unit vectors) it is taken as ±1 by the core, further out or NaN it is an error, not
// a reflectance (the core's clamping would give one).
template <typename F>
py::array_t<double> map1(const DoubleArray& a, F fn) {
  const Vec1 x = vec1(a, "cos_i");
  py::array_t<double> out(py::ssize_t(x.n));
  for (std::size_t i = 0; i < x.n; ++i) {
    if (!(std::abs(x[i]) <= 1 + 1e-6))
      throw InputError(element_name("cos_i", a, i) + " must be a cosine in [-1, 1], got " + format_number(x[i]));
    out.mutable_data()[i] = fn(x[i]);
  }
  return out;
}

// --- subsurface ---------------------------------------------------------------------------

py::dict subsurface(const py::object& description, std::int64_t samples, std::int64_t seed, int threads) {
  checked_threads(threads);
  const std::string text = json_text_of(description);
  // Checked as `gonio subsurface --bsdf` checks it: first as any material (the same
  // messages, named after the Python argument), then the type, then the medium.
  parse_material(text, "description");
  const nlohmann::json j = parse_json_text(text, "description");
  const auto type = j.find("type");
  if (type == j.end() || *type != "subsurface")
    throw InputError(std::string("description: subsurface needs a material of type \"subsurface\", got ") +
                     (type == j.end() ? std::string("none") : json_excerpt(*type)));
  const Subsurface s = subsurface_from_json(j, "description");
  const std::uint64_t paths = checked_count(samples, 1, 1'000'000'000'000, "samples");
  const std::uint64_t sd = checked_count(seed, 0, 2'147'483'647, "seed");
  SlabResult r;
  {
    py::gil_scoped_release release;
    r = s.method == SubsurfaceMethod::Diffusion ? slab_diffusion(s) : slab_random_walk(s, paths, sd, threads);
  }
  std::vector<double> radius(r.profile.size());
  std::vector<Color> value(r.profile.size());
  for (std::size_t i = 0; i < r.profile.size(); ++i) {
    radius[i] = r.profile[i].r;
    value[i] = r.profile[i].value;
  }
  py::dict d;
  d["Rd"] = colour_rows(std::vector<Color>{r.Rd}, 3).attr("reshape")(3);
  d["stderr"] = colour_rows(std::vector<Color>{r.stderr_}, 3).attr("reshape")(3);
  d["radius"] = py::array_t<double>(py::ssize_t(radius.size()), radius.data());
  d["profile"] = colour_rows(value, 3);
  return d;
}

#ifdef GONIO_PYTHON_RENDER
// --- the renderer ---------------------------------------------------------------------------

// A scene from a gonio.Scene, a path, JSON text, a dict, or None (the default scene).
render::Scene scene_of(const py::object& scene_arg) {
  if (scene_arg.is_none()) return render::parse_scene(render::default_scene_json(), "default scene", "");
  if (py::isinstance<render::Scene>(scene_arg)) return scene_arg.cast<const render::Scene&>();
  if (py::isinstance<py::dict>(scene_arg)) return render::parse_scene(json_text_of(scene_arg), "scene", "");
  const std::string s = py::str(scene_arg).cast<std::string>();  // str or os.PathLike
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && s[first] == '{') return render::parse_scene(s, "scene", "");
  return render::load_scene_file(s);
}

py::array render_scene(const py::object& scene_arg, std::optional<int> spp, int threads,
                       std::optional<std::int64_t> seed, bool spectral, const py::object& sample_range) {
  render::Scene scene = scene_of(scene_arg);
  if (spp) scene.settings.spp = int(checked_count(*spp, 1, 1'048'576, "spp"));
  if (seed) scene.settings.seed = checked_count(*seed, 0, 2'147'483'647, "seed");
  if (spectral) scene.settings.spectral = true;
  checked_threads(threads);
  render::RenderOptions options;
  options.threads = threads;
  const bool ranged = !sample_range.is_none();
  if (ranged) {
    // The per-pixel sample indices [a, b) alone, as their sums (gonio render --sample-range).
    const auto r = sample_range.cast<std::pair<std::int64_t, std::int64_t>>();
    const auto a = checked_count(r.first, 0, 1'048'575, "sample_range[0]");
    const auto b = checked_count(r.second, std::int64_t(a) + 1, 1'048'576, "sample_range[1]");
    options.sample_begin = int(a);
    options.sample_end = int(b);
    options.sums = true;
  }
  // Ctrl-C: the render runs on a worker thread while this one, the interpreter's, checks
  // for signals every 100 ms; on one it asks the render to stop (at the next tile), waits
  // for it and raises the KeyboardInterrupt (or the handler's exception).
  std::atomic<bool> stop{false};
  options.stop = &stop;
  render::Image image;
  std::exception_ptr error;
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    std::mutex m;
    std::condition_variable finished;
    bool done = false;
    std::thread worker([&] {
      try {
        image = render::render(scene, options);
      } catch (...) {
        error = std::current_exception();
      }
      const std::lock_guard<std::mutex> lock(m);
      done = true;
      finished.notify_one();
    });
    std::unique_lock<std::mutex> lock(m);
    while (!finished.wait_for(lock, std::chrono::milliseconds(100), [&] { return done; })) {
      lock.unlock();
      {
        py::gil_scoped_acquire acquire;
        interrupted = PyErr_CheckSignals() != 0;
      }
      lock.lock();
      if (interrupted) {
        stop = true;
        finished.wait(lock, [&] { return done; });
        break;
      }
    }
    lock.unlock();
    worker.join();
  }
  if (interrupted) throw py::error_already_set();
  if (error) std::rethrow_exception(error);
  if (ranged) {
    // The float sums, exactly, as doubles: passes add up in double (docs/distributed.md).
    auto a = empty_array<double>({image.height(), image.width(), 3});
    double* p = a.mutable_data();
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x)
        for (int c = 0; c < 3; ++c) *p++ = double(image.at(x, y)[c]);
    return a;
  }
  auto a = empty_array<float>({image.height(), image.width(), 3});
  float* p = a.mutable_data();
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      for (int c = 0; c < 3; ++c) *p++ = image.at(x, y)[c];
  return a;
}
#endif

#ifdef GONIO_PYTHON_RENDER
// A linear float32 (H, W, 3) image to .exr (linear) or .png (tone-mapped sRGB), through the
// CLI's own writer (a temporary renamed over the path when complete).
void write_image(const std::string& path, const py::array_t<float, py::array::c_style | py::array::forcecast>& img,
                 double exposure, bool filmic) {
  if (img.ndim() != 3 || img.shape(2) != 3 || img.shape(0) < 1 || img.shape(1) < 1)
    throw InputError("image must have shape (H, W, 3), H and W at least 1");
  const int h = int(img.shape(0)), w = int(img.shape(1));
  render::Image image(w, h);
  const float* p = img.data();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x, p += 3) image.at(x, y) = Color(p[0], p[1], p[2]);
  render::ImageOutput out(path);
  render::PngOptions png;
  png.exposure_stops = Float(exposure);
  png.tonemap = filmic ? render::ToneMap::Filmic : render::ToneMap::Clamp;
  out.write(image, png);
}
#endif

#ifdef GONIO_PYTHON_FIT
// gonio.fit's arguments other than the table, checked in the CLI's words.
FitOptions fit_options(const std::string& model, const std::string& distribution, const std::string& metric,
                       const py::object& init, int stride) {
  FitOptions options;
  options.model = model;
  options.distribution = distribution;
  options.metric = parse_fit_metric(metric);
  if (stride < 1 || stride > 45) throw InputError("stride must be an integer from 1 to 45, got " + std::to_string(stride));
  options.stride = stride;
  if (!init.is_none()) options.init = parse_json_text(json_text_of(init), "init");
  check_fit_options(options);
  return options;
}

py::dict fit(const std::string& data, const std::string& model, const std::string& distribution,
             const std::string& metric, const py::object& init, int stride) {
  const FitOptions options = fit_options(model, distribution, metric, init, stride);
  quiet_solver_log();  // a failed fit is the one exception, not Ceres's log on stderr before it
  FitResult r;
  {
    py::gil_scoped_release release;
    const MerlTable table = read_merl(data);
    r = fit_merl(table, options);
  }
  py::dict d;
  d["material"] = py::module_::import("json").attr("loads")(r.material.dump());
  d["error"] = r.error;
  d["metric"] = std::string(fit_metric_name(options.metric));
  d["evaluations"] = r.evaluations;
  d["seconds"] = r.seconds;
  return d;
}
#endif

}  // namespace
}  // namespace gonio::python

PYBIND11_MODULE(_gonio, mod) {
  using namespace gonio;
  using namespace gonio::python;
  mod.doc() = "gonio's C++ core: materials evaluated, sampled and validated over numpy arrays";
  mod.attr("__version__") = GONIO_VERSION_STRING;
  // The library's notes (notes.h; e.g. a measured table with missing entries) become
  // Python warnings, which a caller can filter or turn into errors.
  set_note_sink([](const std::string& line) {
    py::gil_scoped_acquire gil;
    py::module_::import("warnings").attr("warn")(line, py::module_::import("builtins").attr("UserWarning"), 2);
  });
  mod.attr("LOBE_NONE") = int(BatchLobe::None);
  mod.attr("LOBE_REFLECTION") = int(BatchLobe::Reflection);
  mod.attr("LOBE_TRANSMISSION") = int(BatchLobe::Transmission);
  // InputError is bad input: ValueError, with the CLI's one-line message.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  py::class_<Material>(mod, "Material", R"doc(
A material of SPEC §2, from its JSON text or a dict with the same content.

    m = gonio.Material({"type": "roughconductor", "material": "Au", "alpha": 0.2})

`wavelength` (nm, 360 to 830): the material at that one wavelength (spectral mode, as
`gonio eval --wavelength`); colours then have one channel instead of three.
A bad description raises ValueError with the message `gonio eval --bsdf` prints, the
source named `Material` instead of `--bsdf`.
Directions are in the local shading frame (z = the normal), pointing away from the
surface; they need not be unit length (each row is normalised in double, as the CLI does).
)doc")
      .def(py::init<const py::object&, std::optional<double>>(), py::arg("description"),
           py::arg("wavelength") = py::none())
      .def_property_readonly("name", [](const Material& m) { return m.rgb().name(); }, "The model's name.")
      .def_property_readonly("json", &Material::json, "The JSON text the material was made from.")
      .def_property_readonly("channels", &Material::channels, "Colour channels: 3 (RGB) or 1 (at a wavelength).")
      .def_property_readonly("wavelength", &Material::wavelength, "The wavelength in nm, or None (RGB).")
      .def_property_readonly("eta", [](const Material& m) { return m.rgb().relative_eta(); },
                             "Relative index n_inside / n_outside; 1 for a model that does not refract.")
      .def_property_readonly("isotropic", [](const Material& m) { return m.rgb().is_isotropic(); },
                             "True when the model is invariant under rotation about the normal.")
      .def("eval", &eval, py::arg("wo"), py::arg("wi"), py::arg("mode") = "radiance", py::arg("threads") = 0,
           R"doc(
f (1/sr, no cosine) and pdf (1/sr) for every pair of rows of wo and wi.

wo, wi: arrays of shape (N, 3) (or (3,): the same direction for every row).
mode: "radiance" (default) or "importance".  threads: 0 = every core.
Returns (f, pdf): float32 arrays of shapes (N, C) and (N,); the same numbers as
`gonio eval` on the same directions.
)doc")
      .def("pdf", &pdf, py::arg("wo"), py::arg("wi"), py::arg("mode") = "radiance", py::arg("threads") = 0,
           "The pdf alone (N,), float32: the density per solid angle with which sample() yields wi.")
      .def("sample", &sample, py::arg("wo"), py::arg("u"), py::arg("mode") = "radiance", py::arg("threads") = 0,
           R"doc(
Importance-sample wi for each row of wo with the uniform numbers u[i] = (u_lobe, u1, u2)
in [0, 1) (shape (N, 3) or (3,)).

Returns (wi, weight, pdf, delta, lobe): float32 (N, 3), float32 (N, C) = f |cos θi| / pdf,
float32 (N,), bool (N,) and uint8 (N,) with gonio.LOBE_REFLECTION,
gonio.LOBE_TRANSMISSION, or gonio.LOBE_NONE where no sample was made (wi, weight and
pdf 0 there; `gonio sample` prints {"wi":null}). For a delta sample pdf holds the discrete
probability of its lobe (the CLI prints null).
)doc")
      .def("albedo", &albedo, py::arg("theta"), py::arg("phi") = 0.0, py::arg("inside") = false,
           py::arg("samples") = 1 << 20, py::arg("seed") = 1, py::arg("threads") = 0, R"doc(
The lecture's directional albedo rho_hd of the view direction wo at polar angle theta
(degrees, a number or a 1-D array; 90 reports the limit) and azimuth phi (degrees), as
`gonio albedo --theta`: a dict of arrays theta (N,), reflectance, transmittance, albedo,
stderr, stderr_reflectance, stderr_transmittance (N, C) and exact (N,) bool; for a model
that is not reciprocal also the light's figures reflectance_light, transmittance_light,
stderr_reflectance_light, stderr_transmittance_light (N, C). inside: wo on the z < 0 side.
Each angle uses the same seed, so entry i equals `gonio albedo --theta theta[i]`.
)doc")
      .def("check", &check, py::arg("seed") = 1, py::arg("scale") = 1.0, R"doc(
Run the validator (`gonio check`): a dict {"pass": bool, "name": str, "properties": [
{"name", "figure" (float or None), "threshold", "pass", "detail"}, ...]}.
scale multiplies every sample count (< 1 for a quick look; thresholds follow).
)doc")
      .def("tabulate", &tabulate_material, py::arg("path"), R"doc(
`gonio tabulate`: write the material as a MERL table at path (an isotropic material
without delta lobes; SPEC §2 `measured`). A dict: file, entries, below_horizon.
)doc")
      .def("__repr__", [](const Material& m) { return "gonio.Material(" + m.json() + ")"; });

  mod.def("material_types", [] {
    std::vector<std::string> v;
    for (auto n : material_type_names()) v.emplace_back(n);
    return v;
  }, "The material types this build knows, in SPEC §2's order.");

  mod.def("read_material_file",
          [](const std::string& path) { return py::bytes(read_text_file(path, kMaxJsonFileBytes, "a material file")); },
          py::arg("path"), R"doc(
The bytes of a material file, read as `--bsdf @PATH` reads it: at most 16 MiB whatever
the file is (a regular file, a device such as /dev/zero, a pipe); larger, missing or
unreadable files raise ValueError naming the path and the reason.
)doc");
  mod.def("fresnel", &fresnel, py::arg("theta"), py::arg("eta") = 1.5, py::arg("k") = 0.0,
          py::arg("material") = py::none(), py::arg("wavelength") = py::none(), R"doc(
Fresnel reflectance from the outside at incidence theta (degrees, a number or a 1-D
array) onto relative index eta + i k, or a named metal or glass (material="Au", "BK7"),
as `gonio fresnel`: a dict of float64 arrays Rs, Rp, R, T, cos_t, schlick, the bool
array tir, theta, and the index used (lists eta, k). A named material in RGB mode gives
arrays of shape (N, 3), else (N,). cos_t is 0 for a conductor and under total internal
reflection (the CLI prints null). wavelength (nm): a named material's index there.
)doc");
  mod.def("thin_film", &thin_film, py::arg("theta"), py::arg("wavelength"), py::arg("thickness"),
          py::arg("film_eta"), py::arg("eta") = 1.5, py::arg("k") = 0.0, py::arg("material") = py::none(), R"doc(
Reflectance of a thin film (index film_eta, thickness in nm) on an interface of relative
index eta + i k (or a named metal or glass, material="Au", "BK7", read at each
wavelength), for light from the outside at theta degrees and wavelength nm: the Airy sum
of the film's two faces (Belcour & Barla 2017, eq. 1) that the models use in spectral
mode (SPEC §2 "thin_film"). theta, wavelength and thickness are numbers or 1-D arrays of
one common length. Returns a dict of float64 arrays Rs, Rp and R.
)doc");
  mod.def("fresnel_dielectric",
          [](const DoubleArray& c, double eta) {
            check_fresnel_index(eta, 0);
            return map1(c, [eta](double ci) { return fresnel_dielectric(ci, eta); });
          },
          py::arg("cos_i"), py::arg("eta"),
          "Unpolarised dielectric reflectance (Hecht §4.6.2) at cos_i (negative: from inside, eta inverted).");
  mod.def("fresnel_conductor",
          [](const DoubleArray& c, double eta, double k) {
            check_fresnel_index(eta, k);
            return map1(c, [eta, k](double ci) { return fresnel_conductor(ci, eta, k); });
          },
          py::arg("cos_i"), py::arg("eta"), py::arg("k"),
          "Unpolarised reflectance of a conductor eta + i k at |cos_i| (Born & Wolf §14.2).");
  mod.def("fresnel_schlick",
          [](const DoubleArray& c, double f0) {
            if (!(f0 >= 0 && f0 <= 1)) throw InputError("f0 must be in [0, 1], got " + format_number(f0));
            return map1(c, [f0](double ci) { return fresnel_schlick(f0, ci); });
          },
          py::arg("cos_i"), py::arg("f0"), "Schlick's approximation F0 + (1 - F0)(1 - cos)^5 (Schlick 1994, eq. 24).");
  mod.def("named_index",
          [](const std::string& name, std::optional<double> nm) {
            const auto idx = named_index(name, nm ? std::optional<Float>(Float(*nm)) : std::nullopt);
            std::vector<double> e, k;
            for (const auto& [a, b] : idx) {
              e.push_back(a);
              k.push_back(b);
            }
            return py::make_tuple(e, k);
          },
          py::arg("name"), py::arg("wavelength") = py::none(),
          "(eta, k) lists of a named metal or glass: RGB (3 channels) or at one wavelength in nm.");

  mod.def("half_diff_directions",
          [](const DoubleArray& th, const DoubleArray& td, const DoubleArray& pd) {
            const Vec1 a = vec1(th, "theta_h"), b = vec1(td, "theta_d"), c = vec1(pd, "phi_d");
            const std::size_t n = std::max({a.n, b.n, c.n});
            for (const Vec1* v : {&a, &b, &c})
              if (v->n != n && v->n != 1) throw InputError("theta_h, theta_d and phi_d have different lengths");
            for (const auto& [v, arr, name] : {std::tuple{&a, &th, "theta_h"}, std::tuple{&b, &td, "theta_d"},
                                               std::tuple{&c, &pd, "phi_d"}})
              for (std::size_t i = 0; i < v->n; ++i)
                if (!std::isfinite((*v)[i]))
                  throw InputError(element_name(name, *arr, i) + " must be a finite angle in degrees, got " +
                                   format_number((*v)[i]));
            py::array_t<double> wo({py::ssize_t(n), py::ssize_t(3)}), wi({py::ssize_t(n), py::ssize_t(3)});
            for (std::size_t i = 0; i < n; ++i) {
              const auto [o, w] = merl_directions(a[i] * kPiD / 180, b[i] * kPiD / 180, c[i] * kPiD / 180);
              for (int k = 0; k < 3; ++k) {
                wo.mutable_data()[3 * i + std::size_t(k)] = o[k];
                wi.mutable_data()[3 * i + std::size_t(k)] = w[k];
              }
            }
            return py::make_tuple(wo, wi);
          },
          py::arg("theta_h"), py::arg("theta_d"), py::arg("phi_d"), R"doc(
(wo, wi) arrays (N, 3) of the half/difference angles in degrees, with phi_h = 0
(Rusinkiewicz 1998; MERL's parametrisation, gonio/merl.h). Either may lie below the horizon.
)doc");
  mod.def("subsurface", &subsurface, py::arg("description"), py::arg("samples") = 1 << 17, py::arg("seed") = 1,
          py::arg("threads") = 0, R"doc(
`gonio subsurface`: a semi-infinite slab of a material of type "subsurface" under a
collimated beam at normal incidence. A dict: Rd (3,), stderr (3,), radius (M,) and
profile (M, 3), by the material's method (random walk: `samples` paths).
)doc");
#ifdef GONIO_PYTHON_RENDER
  py::class_<render::Scene>(mod, "Scene", R"doc(
A scene loaded once (meshes, textures and tables read): Scene(path | JSON text | dict |
None for the default scene), to render many times (gonio.render(scene, ...)).
)doc")
      .def(py::init([](const py::object& arg) { return scene_of(arg); }), py::arg("scene") = py::none())
      .def_property_readonly("width", [](const render::Scene& s) { return s.camera.width; })
      .def_property_readonly("height", [](const render::Scene& s) { return s.camera.height; })
      .def_property_readonly("spp", [](const render::Scene& s) { return s.settings.spp; })
      .def_property_readonly("seed", [](const render::Scene& s) { return s.settings.seed; })
      .def_property_readonly("spectral", [](const render::Scene& s) { return s.settings.spectral; })
      .def_property_readonly("polarized", [](const render::Scene& s) { return s.settings.polarized; });
  mod.def("render", &render_scene, py::arg("scene") = py::none(), py::kw_only(), py::arg("spp") = py::none(),
          py::arg("threads") = 0, py::arg("seed") = py::none(), py::arg("spectral") = false,
          py::arg("sample_range") = py::none(), R"doc(
Render a scene (docs/scene-format.md) as `gonio render` does, returning the linear image
as a float32 array of shape (H, W, 3), row 0 at the top. scene: a gonio.Scene, a path,
JSON text, a dict, or None for the built-in default scene. spp, seed override the scene's;
threads 0 = all. sample_range=(a, b): only the per-pixel sample indices [a, b), returned as
their per-pixel SUMS, float64 (H, W, 3) (`gonio render --sample-range`; the sums of
disjoint ranges add up to the whole render's, docs/distributed.md).
Ctrl-C stops the render at its next tile and raises KeyboardInterrupt.
)doc");
  mod.def("write_image", &write_image, py::arg("path"), py::arg("image"), py::kw_only(), py::arg("exposure") = 0.0,
          py::arg("filmic") = true, R"doc(
Write a linear (H, W, 3) image as `gonio render` does: .exr linear float32, .png
tone-mapped sRGB (exposure in stops; filmic or clamped), by the path's extension.
)doc");
  register_measure(mod);
#endif
#ifdef GONIO_PYTHON_FIT
  mod.def("fit", &fit, py::arg("data"), py::arg("model"), py::kw_only(), py::arg("distribution") = "",
          py::arg("metric") = "log", py::arg("init") = py::none(), py::arg("stride") = 3, R"doc(
`gonio fit`: fit an analytic model to the MERL table at path `data`. A dict: material
(a dict, valid input to Material), error, metric, evaluations, seconds.
)doc");
  // gonio.distributed checks every input on the client, before any cluster starts.
  mod.def(
      "_check_fit_options",
      [](const std::string& model, const std::string& distribution, const std::string& metric, const py::object& init,
         int stride) { fit_options(model, distribution, metric, init, stride); },
      py::arg("model"), py::kw_only(), py::arg("distribution") = "", py::arg("metric") = "log",
      py::arg("init") = py::none(), py::arg("stride") = 3);
#endif
}
