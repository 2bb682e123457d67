#pragma once
// InputError: bad input from a user (a material description, a command-line value, a
// data file). Its message is one line that names the place and the problem; the CLI
// prints it and exits with status 2.

#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>

namespace gonio {

// A number as error messages show it: the shortest form that gives back the float
// (printf's %.9g), e.g. "0.1", "1e+39", "nan".
inline std::string format_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// `text` with every control character written as an escape (\n, \r, \t, else \xNN,
// DEL included), so that user text echoed in a message cannot break it into several
// lines or move the terminal's cursor. Backslashes are left alone: the function is
// idempotent, and a message built from messages is escaped once.
inline std::string escape_control(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c >= 0x20 && c != 0x7f) {
      out += ch;
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else {
      constexpr char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

class InputError : public std::runtime_error {
 public:
  // The message is stored escaped: one line whatever the user typed.
  explicit InputError(const std::string& message) : std::runtime_error(escape_control(message)) {}
};

}  // namespace gonio
