// JSON parsing with errors that point into the text.

#include "gonio/json_text.h"

#include <algorithm>
#include <string>

#include "gonio/error.h"

namespace gonio {

nlohmann::json parse_json_text(std::string_view text, std::string_view source) {
  using nlohmann::json;
  try {
    return json::parse(text.begin(), text.end());
  } catch (const json::parse_error& e) {
    // Byte offset → line and column, so the message points into the text.
    size_t line = 1, col = 1;
    const size_t end = std::min(e.byte == 0 ? 0 : e.byte - 1, text.size());
    for (size_t i = 0; i < end; ++i) {
      if (text[i] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    std::string what = e.what();
    // nlohmann's text is "[json.exception.parse_error.101] parse error at line 1, column 2:
    // syntax error while parsing value - ..."; keep the part after the last " - ".
    const auto dash = what.rfind(" - ");
    if (dash != std::string::npos) what = what.substr(dash + 3);
    throw InputError(std::string(source) + ": malformed JSON at line " + std::to_string(line) + ", column " +
                     std::to_string(col) + ": " + what);
  } catch (const json::exception& e) {
    // e.g. out_of_range.406 "number overflow parsing '1e999'"; drop the "[json.exception...] ".
    std::string what = e.what();
    const auto bracket = what.find("] ");
    if (bracket != std::string::npos) what = what.substr(bracket + 2);
    throw InputError(std::string(source) + ": malformed JSON: " + what);
  }
}

}  // namespace gonio
