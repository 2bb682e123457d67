// gonio.measure: the virtual gonioreflectometer (SPEC §3 `gonio measure`,
// docs/gonioreflectometer.md) from Python. The same C++ as the CLI's (run_gantry,
// measure_table), so the readings equal `gonio measure`'s for the same surface, rays and
// seed, whatever the thread count (instrument.h: fixed blocks, one stream each).

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "convert.h"
#include "gonio/measure/gantry.h"
#include "gonio/measure/surface.h"
#include "gonio/measure/table.h"
#include "gonio/merl.h"
#include "measure_binding.h"

namespace gonio::python {
namespace {

py::dict counts_dict(const measure::RayCounts& c) {
  py::dict d;
  d["launched"] = c.launched, d["up"] = c.up, d["down"] = c.down, d["absorbed"] = c.absorbed;
  d["capped"] = c.capped, d["lost"] = c.lost, d["segments"] = c.segments, d["bounces"] = c.bounces;
  return d;
}

template <typename T>
py::array_t<T> array_of(std::vector<py::ssize_t> shape, const std::vector<T>& values) {
  py::array_t<T> a(shape);
  std::copy(values.begin(), values.end(), a.mutable_data());
  return a;
}

void append(std::vector<double>& v, const Color& c) {
  for (int k = 0; k < 3; ++k) v.push_back(double(c[k]));
}

// Incidence-major arrays: theta_i (I,), albedo (I, 3), f (I, D, 3), ... with D detectors.
py::dict gantry_dict(const measure::GantryReading& g) {
  const auto ni = py::ssize_t(g.incidences.size());
  const auto nd = py::ssize_t(ni ? g.incidences[0].detectors.size() : 0);
  std::vector<double> ti, pi, alb, s_alb, tr, s_tr, to, po, omega, f, s_f;
  std::vector<std::uint64_t> hits;
  py::list rays;
  for (const measure::IncidenceReading& r : g.incidences) {
    ti.push_back(r.theta_i), pi.push_back(r.phi_i);
    append(alb, r.albedo), append(s_alb, r.stderr_albedo);
    append(tr, r.transmittance), append(s_tr, r.stderr_transmittance);
    rays.append(counts_dict(r.counts));
    for (const measure::DetectorReading& x : r.detectors) {
      append(f, x.f), append(s_f, x.stderr_f);
      hits.push_back(x.hits);
    }
  }
  if (ni > 0)
    for (const measure::DetectorReading& x : g.incidences[0].detectors)
      to.push_back(x.theta_o), po.push_back(x.phi_o), omega.push_back(x.solid_angle);
  py::dict d;
  d["mode"] = "gantry";
  d["aperture"] = g.aperture;
  d["rays_per_incidence"] = g.rays_per_incidence;
  d["theta_i"] = array_of<double>({ni}, ti), d["phi_i"] = array_of<double>({ni}, pi);
  d["albedo"] = array_of<double>({ni, 3}, alb), d["stderr_albedo"] = array_of<double>({ni, 3}, s_alb);
  d["transmittance"] = array_of<double>({ni, 3}, tr);
  d["stderr_transmittance"] = array_of<double>({ni, 3}, s_tr);
  d["theta_o"] = array_of<double>({nd}, to), d["phi_o"] = array_of<double>({nd}, po);
  d["solid_angle"] = array_of<double>({nd}, omega);
  d["f"] = array_of<double>({ni, nd, 3}, f), d["stderr"] = array_of<double>({ni, nd, 3}, s_f);
  d["hits"] = array_of<std::uint64_t>({ni, nd}, hits);
  d["rays"] = rays;
  return d;
}

py::dict table_dict(const measure::TableReading& t, const std::string& file, std::int64_t min_rays) {
  std::vector<double> edges, alb, s_alb;
  std::vector<std::uint64_t> band_rays;
  for (const measure::AlbedoBand& b : t.bands) {
    edges.push_back(b.theta_lo), edges.push_back(b.theta_hi);
    append(alb, b.albedo), append(s_alb, b.stderr_albedo);
    band_rays.push_back(b.rays);
  }
  const auto nb = py::ssize_t(t.bands.size());
  py::dict d;
  d["mode"] = "table";
  d["file"] = file;
  d["entries"] = MerlTable::kEntries;
  d["filled"] = t.filled, d["missing"] = t.missing, d["zero"] = t.zero, d["filled_by_pilot"] = t.filled_by_pilot;
  d["pooled"] = t.pooled;
  d["min_expected_rays"] = min_rays;
  py::dict above;
  above["0.01"] = t.fraction_above[0], above["0.05"] = t.fraction_above[1], above["0.2"] = t.fraction_above[2];
  d["relative_stderr_above"] = above;
  d["rays"] = counts_dict(t.counts);
  d["pilot_rays"] = t.pilot_rays;
  d["theta_i"] = array_of<double>({nb, 2}, edges);
  d["band_rays"] = array_of<std::uint64_t>({nb}, band_rays);
  d["albedo"] = array_of<double>({nb, 3}, alb), d["stderr_albedo"] = array_of<double>({nb, 3}, s_alb);
  return d;
}

// Ctrl-C. The instrument calls RunOptions::progress from the calling thread between
// batches of blocks (about half a million rays); there the interpreter runs its pending
// signal handlers, and a KeyboardInterrupt unwinds the run as this exception (no ray is
// traced after it), to be raised in Python once the GIL is back.
struct Interrupted {};

void check_signals(double) {
  py::gil_scoped_acquire acquire;
  if (PyErr_CheckSignals() != 0) throw Interrupted{};
}

py::dict measure_surface(const py::object& surface_arg, const py::object& gantry_arg, const std::string& output,
                         std::optional<std::int64_t> samples, int threads, std::int64_t seed, std::int64_t max_bounces,
                         std::int64_t min_rays) {
  // Every argument is checked before the first ray, in the CLI's words.
  if (gantry_arg.is_none() && output.empty())
    throw InputError("measure: give gantry= (detector readings) or output= (a MERL table to write)");
  if (!gantry_arg.is_none() && !output.empty())
    throw InputError("measure: gantry= (detector readings) and output= (a MERL table) are separate runs; give one");
  const measure::Surface surface = measure::parse_surface(json_text_of(surface_arg, "surface"), "surface", "");
  measure::GantrySpec spec;
  if (!gantry_arg.is_none()) spec = measure::parse_gantry(json_text_of(gantry_arg, "gantry"), "--gantry");
  measure::RunOptions options;
  // A table's default is its own (`gonio measure -o`, table.h).
  const std::int64_t rays = samples ? *samples
                                    : gantry_arg.is_none() ? std::int64_t(measure::kTableDefaultSamples) : 10'000'000;
  options.samples = checked_count(rays, 1, 1'000'000'000'000, "samples");
  options.threads = checked_threads(threads);
  options.seed = checked_count(seed, 0, 2'147'483'647, "seed");
  const auto bounces = std::uint32_t(checked_count(max_bounces, 1, 1'000'000, "max_bounces"));
  measure::TableOptions table;
  table.min_expected_rays = double(checked_count(min_rays, 0, 1'000'000, "min_rays"));
  options.progress = check_signals;
  try {
    if (gantry_arg.is_none()) {
      measure::TableReading t;
      {
        py::gil_scoped_release release;
        const measure::Microsurface micro(surface.field, surface.material, bounces);
        t = measure::measure_table(micro, options, table);
        write_merl(output, t.table);
      }
      return table_dict(t, output, min_rays);
    }
    measure::GantryReading g;
    {
      py::gil_scoped_release release;
      const measure::Microsurface micro(surface.field, surface.material, bounces);
      g = measure::run_gantry(micro, spec, options);
    }
    return gantry_dict(g);
  } catch (const Interrupted&) {
    throw py::error_already_set();  // the KeyboardInterrupt the signal handler set
  }
}

}  // namespace

void register_measure(py::module_& mod) {
  // gonio.distributed checks every surface on the client, before any cluster starts: the
  // same parse (and image load) as measure's, without a ray.
  mod.def(
      "_check_surface",
      [](const py::object& surface) { (void)measure::parse_surface(json_text_of(surface, "surface"), "surface", ""); },
      py::arg("surface"));
  mod.def("measure", &measure_surface, py::arg("surface"), py::arg("gantry") = py::none(), py::kw_only(),
          py::arg("output") = "", py::arg("samples") = py::none(), py::arg("threads") = 0, py::arg("seed") = 0,
          py::arg("max_bounces") = std::int64_t(measure::Microsurface::kDefaultMaxBounces),
          py::arg("min_rays") = std::int64_t(measure::kTableMinExpectedRays),
          R"doc(The virtual gonioreflectometer (SPEC §3 `gonio measure`; docs/gonioreflectometer.md).

surface: the microsurface, JSON text or a dict ({"type": "flat"|"gaussian"|"vgroove"|"image",
"material": {...}, ...}). Give either
  gantry: detector readings, JSON text or a dict {"theta_i", "phi_i", "theta_o", "phi_o",
    "aperture"} (degrees; numbers, lists or {"from", "to", "count"} ranges). Returns a dict of
    numpy arrays, incidence-major: theta_i, phi_i (I,); albedo, stderr_albedo, transmittance,
    stderr_transmittance (I, 3); theta_o, phi_o, solid_angle (D,); f, stderr (I, D, 3) in 1/sr;
    hits (I, D); rays (a list of I dicts of ray counts); aperture; rays_per_incidence.
  output: the path of a MERL table (.binary) to fill (isotropic surfaces; every entry above
    the horizon, own or pooled). Returns file, filled, pooled, missing, zero, filled_by_pilot,
    min_expected_rays, relative_stderr_above, rays, pilot_rays, and per 1° band of theta_i:
    theta_i (90, 2) edges, band_rays (90,), albedo and stderr_albedo (90, 3). min_rays: the
    rays an entry must expect to be its bin's own, else pooled over a region of bins (`gonio
    measure --min-rays`, default 25; 0: every bin above the horizon its own).
samples: total rays launched from the light (default 200,000,000 for a table, 10,000,000 split
evenly over the gantry's incidences); seed: the
random seed (the result does not depend on threads); max_bounces: facet interactions allowed
to a ray. The same numbers as `gonio measure` with the same arguments. Ctrl-C stops a run
within about half a million rays with KeyboardInterrupt (a table is then not written).)doc");
}

}  // namespace gonio::python
