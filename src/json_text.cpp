// Bounded file reads and JSON parsing with errors that point into the text.

#include "gonio/json_text.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <unordered_set>
#include <vector>

#include "gonio/error.h"

namespace gonio {
namespace {

// The length of the well-formed UTF-8 sequence at text[i], or 0 when the byte there
// starts none. RFC 3629 §4's table: the second byte's range depends on the first (E0
// needs A0..BF, ED 80..9F, F0 90..BF, F4 80..8F), which rules out overlong forms,
// surrogates and code points past U+10FFFF.
size_t utf8_sequence_length(std::string_view text, size_t i) {
  const auto at = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char c = at(i);
  if (c < 0x80) return 1;
  size_t n = 0;
  unsigned char lo = 0x80, hi = 0xBF;
  if (c >= 0xC2 && c <= 0xDF) n = 2;
  else if (c == 0xE0) n = 3, lo = 0xA0;
  else if (c >= 0xE1 && c <= 0xEC) n = 3;
  else if (c == 0xED) n = 3, hi = 0x9F;
  else if (c >= 0xEE && c <= 0xEF) n = 3;
  else if (c == 0xF0) n = 4, lo = 0x90;
  else if (c >= 0xF1 && c <= 0xF3) n = 4;
  else if (c == 0xF4) n = 4, hi = 0x8F;
  else return 0;
  if (i + n > text.size()) return 0;
  if (at(i + 1) < lo || at(i + 1) > hi) return 0;
  for (size_t k = 2; k < n; ++k)
    if (at(i + k) < 0x80 || at(i + k) > 0xBF) return 0;
  return n;
}

// "16 MiB", or the byte count when the limit is not a whole number of MiB.
std::string show_size(std::size_t bytes) {
  if (bytes % (std::size_t(1) << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
  return std::to_string(bytes) + " bytes";
}

// Line and column (1-based, in bytes) of byte `offset` of `text`.
std::string line_column(std::string_view text, size_t offset) {
  size_t line = 1, col = 1;
  const size_t end = std::min(offset, text.size());
  for (size_t i = 0; i < end; ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(col);
}

// Refuses nesting deeper than kMaxJsonDepth in one linear pass over the text: brackets
// are counted outside strings (a backslash escapes the next character inside one).
// Malformed text is left to the parser, which reports it.
void check_depth(std::string_view text, std::string_view source) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        throw InputError(std::string(source) + ": JSON nested deeper than " + std::to_string(kMaxJsonDepth) +
                         " levels of arrays and objects, at " + line_column(text, i));
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

// Refuses an object that names a key twice. RFC 8259 §4 leaves duplicates to the
// implementation and nlohmann keeps the last silently, so `{"eta": "x", "eta": 1.5}`
// would pass a typo unseen. One linear pass over text the parser has accepted (so every
// token is well formed); keys are compared decoded, "\u0065ta" being "eta".
void check_unique_keys(std::string_view text, std::string_view source) {
  struct Container {
    bool object;
    bool expect_key;
    std::unordered_set<std::string> keys;
  };
  std::vector<Container> stack;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '{' || c == '[') {
      stack.push_back({c == '{', c == '{', {}});
    } else if (c == '}' || c == ']') {
      if (!stack.empty()) stack.pop_back();
    } else if (c == ',') {
      if (!stack.empty() && stack.back().object) stack.back().expect_key = true;
    } else if (c == ':') {
      if (!stack.empty()) stack.back().expect_key = false;
    } else if (c == '"') {
      const size_t start = i;
      for (++i; i < text.size() && text[i] != '"'; ++i)
        if (text[i] == '\\') ++i;
      if (stack.empty() || !stack.back().expect_key) continue;
      // Fast path: a key without escapes is its own spelling.
      const std::string_view raw = text.substr(start + 1, i - start - 1);
      std::string key = raw.find('\\') == std::string_view::npos
                            ? std::string(raw)
                            : nlohmann::json::parse(text.substr(start, i - start + 1)).get<std::string>();
      if (!stack.back().keys.insert(key).second)
        throw InputError(std::string(source) + ": duplicate key \"" + key + "\" at " + line_column(text, start) +
                         " (a key may appear only once in an object)");
    }
  }
}

}  // namespace

std::string read_text_file(const std::string& path, std::size_t limit, std::string_view kind) {
  const std::string what(kind);
  if (path.empty()) throw InputError("cannot read " + what + ": the file name is empty");
  // A NUL (from "\u0000" in JSON) would silently cut the name short.
  if (path.find('\0') != std::string::npos) throw InputError(path + ": a file name cannot hold a NUL byte");
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a directory, not " + what);
  errno = 0;
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw InputError(path + ": cannot open " + what + ": " + std::strerror(errno));
  std::string text;
  char buf[1 << 16];
  // One byte past the limit tells a file at the limit from a larger one.
  while (text.size() <= limit) {
    const size_t want = std::min(sizeof buf, limit + 1 - text.size());
    const size_t got = std::fread(buf, 1, want, f.get());
    text.append(buf, got);
    if (got < want) {
      if (std::ferror(f.get())) throw InputError(path + ": cannot read " + what + ": " + std::strerror(errno));
      break;  // end of file
    }
  }
  if (text.size() > limit)
    throw InputError(path + ": file too large (more than " + show_size(limit) + ", the limit for " + what + ")");
  return text;
}

nlohmann::json parse_json_text(std::string_view text, std::string_view source) {
  using nlohmann::json;
  // nlohmann's lexer reads a NUL byte as the end of the input, so whatever follows one
  // would be ignored unseen; JSON text cannot hold one (RFC 8259 §7: only as \u0000).
  if (const size_t nul = text.find('\0'); nul != std::string_view::npos)
    throw InputError(std::string(source) + ": a NUL byte at byte offset " + std::to_string(nul) + " (" +
                     line_column(text, nul) + "): JSON text cannot hold one");
  check_depth(text, source);
  try {
    json parsed = json::parse(text.begin(), text.end());
    check_unique_keys(text, source);
    return parsed;
  } catch (const json::parse_error& e) {
    std::string what = e.what();
    // nlohmann's text is "[json.exception.parse_error.101] parse error at line 1, column 2:
    // syntax error while parsing value - ..."; keep the part after the last " - ".
    const auto dash = what.rfind(" - ");
    if (dash != std::string::npos) what = what.substr(dash + 3);
    // Byte offset → line and column, so the message points into the text.
    // nlohmann quotes the bytes last read, which may be part of a multi-byte character
    // ("last read: '\xc3'"): escaped, so that the message is valid UTF-8.
    throw InputError(printable_utf8(std::string(source) + ": malformed JSON at " +
                                    line_column(text, e.byte == 0 ? 0 : e.byte - 1) + ": " + what));
  } catch (const json::exception& e) {
    // e.g. out_of_range.406 "number overflow parsing '1e999'"; drop the "[json.exception...] ".
    std::string what = e.what();
    const auto bracket = what.find("] ");
    if (bracket != std::string::npos) what = what.substr(bracket + 2);
    throw InputError(printable_utf8(std::string(source) + ": malformed JSON: " + what));
  }
}

std::string json_excerpt(const nlohmann::json& value) {
  // A string holding invalid UTF-8 (one built in code, not parsed) is shown with U+FFFD
  // rather than making dump() throw.
  std::string s = value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  if (s.size() > 60) s = std::string(utf8_prefix(s, 57)) + "...";
  return s;
}

std::string printable_utf8(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size();) {
    const size_t n = utf8_sequence_length(text, i);
    if (n > 0) {
      out.append(text.substr(i, n));
      i += n;
    } else {
      constexpr char kHex[] = "0123456789abcdef";
      const auto c = static_cast<unsigned char>(text[i]);
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
      ++i;
    }
  }
  return out;
}

std::string_view utf8_prefix(std::string_view text, std::size_t max_bytes) {
  size_t end = 0;
  while (end < text.size()) {
    const size_t n = std::max<size_t>(1, utf8_sequence_length(text, end));  // a stray byte is one
    if (end + n > max_bytes) break;
    end += n;
  }
  return text.substr(0, end);
}

}  // namespace gonio
