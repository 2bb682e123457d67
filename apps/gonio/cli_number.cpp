#include "cli_number.h"

#include <algorithm>
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
      "", "decimal");
}

CLI::Validator decimal_in_range(std::int64_t lo, std::int64_t hi) {
  // A transform, not a check: leading zeros are dropped from the text before CLI11
  // converts it, since CLI11 would read 010 as octal 8.
  const CLI::Validator decimal(
      [](std::string& s) -> std::string {
        const size_t first = (!s.empty() && (s[0] == '-' || s[0] == '+')) ? 1 : 0;
        const bool ok = s.size() > first && s.find_first_not_of("0123456789", first) == std::string::npos;
        if (!ok) return "'" + s + "' is not a decimal integer";
        const size_t nonzero = std::min(s.find_first_not_of('0', first), s.size() - 1);
        s = (s[0] == '-' ? "-" : "") + s.substr(nonzero);
        return {};
      },
      "", "decimal");
  return decimal & CLI::Range(lo, hi);
}

}  // namespace gonio::cli
