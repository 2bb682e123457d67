#include "cli_number.h"

#include <charconv>
#include <cmath>
#include <string>
#include <system_error>

namespace gonio::cli {

std::optional<double> parse_decimal(std::string_view text) {
  const char* first = text.data();
  const char* last = first + text.size();
  // from_chars takes a '-' but not a '+'; a second sign stays and is refused.
  if (first != last && *first == '+') ++first;
  if (first == last) return std::nullopt;
  double v = 0;
  // chars_format::general: fixed or scientific, never the hexadecimal form.
  const auto res = std::from_chars(first, last, v, std::chars_format::general);
  if (res.ec != std::errc() || res.ptr != last) return std::nullopt;
  return v;
}

CLI::Validator decimal_number() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        const std::optional<double> v = parse_decimal(s);
        if (!v) return "'" + s + "' is not a decimal number";
        if (!std::isfinite(*v)) return "'" + s + "' is not a finite number";
        return {};
      },
      "NUMBER", "decimal");
}

}  // namespace gonio::cli
