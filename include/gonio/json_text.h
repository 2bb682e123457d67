#pragma once
// Text input with limits: files read whole but bounded (devices and pipes included), and
// JSON text → nlohmann::json with bad input reported as one InputError line that names
// the source and the line and column, e.g.
//   "scene.json: malformed JSON at line 3, column 5: unexpected ','; expected string literal".
// Shared by material descriptions, renderer scenes and OBJ meshes.

#include <cstddef>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace gonio {

// Largest material description or scene file read: far above any hand-written scene
// (the default scene is 3 KB), small enough that parsing it stays well under a second.
inline constexpr std::size_t kMaxJsonFileBytes = std::size_t(16) << 20;  // 16 MiB
// Largest OBJ mesh file read: about a million triangles with normals and UVs.
inline constexpr std::size_t kMaxObjFileBytes = std::size_t(64) << 20;  // 64 MiB
// Deepest nesting of JSON arrays and objects. Deeper text is refused before it is
// parsed: the parser is iterative, but what works on its result (dump() for messages,
// the material parser) recurses, and 58,000 levels overflowed the stack.
inline constexpr int kMaxJsonDepth = 64;

// The whole file `path` (`kind` names it in messages, e.g. "a scene file"), reading at
// most limit + 1 bytes whatever it is: a regular file, a device (/dev/zero never ends),
// a FIFO or /dev/stdin. Throws InputError "PATH: file too large (more than 16 MiB, the
// limit for a scene file)" past the limit, and names the path and the reason when it
// cannot be opened or read, or is a directory.
std::string read_text_file(const std::string& path, std::size_t limit, std::string_view kind);

// Parses JSON text; a NUL byte (named by its byte offset), nesting deeper than
// kMaxJsonDepth, and a key that appears twice in one object, are InputErrors naming the
// line and column (of the NUL, of the first bracket too deep, of the second occurrence of
// the key).
nlohmann::json parse_json_text(std::string_view text, std::string_view source);

// A value as error messages show it: compact JSON, at most 60 bytes, cut on a character
// boundary (a multi-byte character is never split), "..." marking the cut.
std::string json_excerpt(const nlohmann::json& value);

// `text` as valid UTF-8 for a message: well-formed sequences kept, every other byte (a
// lone continuation byte, an overlong form such as C0 AE, a surrogate, a sequence cut
// short, F5..FF) written as \xNN. An error message that quotes bytes a user sent is then
// printable on a terminal and representable in a JSON answer (nlohmann's dump() throws on
// invalid UTF-8). Idempotent: the escapes are ASCII.
std::string printable_utf8(std::string_view text);

// The longest prefix of UTF-8 `text` of at most `max_bytes` bytes that ends on a
// character boundary (a well-formed sequence is kept whole or dropped whole).
std::string_view utf8_prefix(std::string_view text, std::size_t max_bytes);

}  // namespace gonio
