#pragma once
// Conversions the module's binding files share: Python descriptions to JSON text, and
// integer arguments checked against their range with the CLI's wording.

#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>

#include "gonio/error.h"

namespace gonio::python {

namespace py = pybind11;

// JSON text from a str (the text itself) or a dict (json.dumps); anything else is an error
// naming `what`.
inline std::string json_text_of(const py::object& description, const char* what = "Material") {
  if (py::isinstance<py::str>(description)) return description.cast<std::string>();
  if (py::isinstance<py::dict>(description))
    return py::module_::import("json").attr("dumps")(description).cast<std::string>();
  throw InputError(std::string(what) + ": expected JSON text (str) or a dict, got " +
                   py::str(py::type::of(description).attr("__name__")).cast<std::string>());
}

// v as a count, or InputError naming `name` and the range.
inline std::uint64_t checked_count(std::int64_t v, std::int64_t lo, std::int64_t hi, const char* name) {
  if (v < lo || v > hi)
    throw InputError(std::string(name) + " must be an integer from " + std::to_string(lo) + " to " +
                     std::to_string(hi) + ", got " + std::to_string(v));
  return std::uint64_t(v);
}

// A `threads` argument as the CLI's --threads takes it: 0 (every core) to 1024.
inline int checked_threads(std::int64_t threads) { return int(checked_count(threads, 0, 1024, "threads")); }

}  // namespace gonio::python
