// The 5 × 7 bitmap font of bitmap_font.h. Each glyph is 7 rows of 5 characters, '#' for
// a set pixel, drawn for gonio (digits and letters in the usual dot-matrix shapes).

#include "gonio/render/bitmap_font.h"

#include <array>
#include <cstdint>

namespace gonio::render {
namespace {

struct Glyph {
  char32_t code;
  const char* rows;  // 35 characters: row 0 (top) first
};

constexpr Glyph kGlyphs[] = {
    {U' ', "..................................."},
    {U'0', ".###.#...##..###.#.###..##...#.###."},
    {U'1', "..#...##....#....#....#....#...###."},
    {U'2', ".###.#...#....#...#...#...#...#####"},
    {U'3', "####.....#....#.###.....#....#####."},
    {U'4', "...#...##..#.#.#..#.#####...#....#."},
    {U'5', "######....####.....#....##...#.###."},
    {U'6', ".###.#....#....####.#...##...#.###."},
    {U'7', "#####....#...#...#...#....#....#..."},
    {U'8', ".###.#...##...#.###.#...##...#.###."},
    {U'9', ".###.#...##...#.####....#....#.###."},
    {U'-', "................###................"},
    {U'+', ".......#....#..#####..#....#......."},
    {U'.', "..........................##...##.."},
    {U',', ".....................##....#...#..."},
    {U':', "......##...##........##...##......."},
    {U'(', "...#...#...#....#....#.....#.....#."},
    {U')', ".#.....#.....#....#....#...#...#..."},
    {U'/', "....#....#...#...#...#...#....#...."},
    {U'=', "..........#####.....#####.........."},
    {U'%', "##..###..#...#...#...#...#..###..##"},
    {U'\u00b0', ".##..#..#.#..#..##................."},  // °
    {U'\u03b8', ".###.#...##...#######...##...#.###."},  // θ
    {U'\u03c6', "..#...###.#.#.##.#.##.#.#.###...#.."},  // φ
    {U'A', ".###.#...##...#######...##...##...#"},
    {U'B', "####.#...##...#####.#...##...#####."},
    {U'Y', "#...##...#.#.#...#....#....#....#.."},
    {U'a', "...........###.....#.#####...#.####"},
    {U'b', "#....#....#.##.##..##...##...#####."},
    {U'c', "...........###.#....#....#...#.###."},
    {U'd', "....#....#.##.##..###...##...#.####"},
    {U'e', "...........###.#...#######.....###."},
    {U'f', "..##..#..#.#...###...#....#....#..."},
    {U'g', "......#####...#.####....##...#.###."},
    {U'h', "#....#....#.##.##..##...##...##...#"},
    {U'i', "..#........##....#....#....#...###."},
    {U'j', "...#........##....#....#.#..#..##.."},
    {U'k', "#....#....#..#.#.#..##...#.#..#..#."},
    {U'l', ".##....#....#....#....#....#...###."},
    {U'm', "..........##.#.#.#.##.#.##...##...#"},
    {U'n', "..........#.##.##..##...##...##...#"},
    {U'o', "...........###.#...##...##...#.###."},
    {U'p', "..........####.#...#####.#....#...."},
    {U'q', "...........##.##..##.####....#....#"},
    {U'r', "..........#.##.##..##....#....#...."},
    {U's', "...........###.#.....###.....#####."},
    {U't', ".#....#...###...#....#....#..#..##."},
    {U'u', "..........#...##...##...##..##.##.#"},
    {U'v', "..........#...##...##...#.#.#...#.."},
    {U'w', "..........#...##...##.#.##.#.#.#.#."},
    {U'x', "..........#...#.#.#...#...#.#.#...#"},
    {U'y', "..........#...##...#.####....#.###."},
    {U'z', "..........#####...#...#...#...#####"},
};

const Glyph* find(char32_t c) {
  for (const Glyph& g : kGlyphs)
    if (g.code == c) return &g;
  return nullptr;
}

// Next code point of `s` from `at` (advanced past it); U+FFFD for an invalid byte.
char32_t next_code_point(std::string_view s, size_t& at) {
  const auto b0 = static_cast<unsigned char>(s[at++]);
  if (b0 < 0x80) return b0;
  int extra = b0 >= 0xf0 && b0 < 0xf8 ? 3 : b0 >= 0xe0 ? 2 : b0 >= 0xc0 ? 1 : -1;
  if (extra < 0) return U'\ufffd';
  char32_t c = b0 & (0x3f >> extra);
  for (; extra > 0; --extra) {
    if (at >= s.size() || (static_cast<unsigned char>(s[at]) & 0xc0) != 0x80) return U'\ufffd';
    c = (c << 6) | (static_cast<unsigned char>(s[at++]) & 0x3f);
  }
  return c;
}

}  // namespace

bool has_glyph(char32_t c) { return find(c) != nullptr; }

bool glyph_pixel(char32_t c, int col, int row) {
  if (col < 0 || col >= kGlyphWidth || row < 0 || row >= kGlyphHeight) return false;
  const Glyph* g = find(c);
  if (!g) return col == 0 || row == 0 || col == kGlyphWidth - 1 || row == kGlyphHeight - 1;  // a box
  return g->rows[row * kGlyphWidth + col] == '#';
}

int text_width(std::string_view text, int scale) {
  int n = 0;
  for (size_t at = 0; at < text.size(); ++n) next_code_point(text, at);
  return n == 0 ? 0 : (n * kGlyphAdvance - 1) * scale;
}

void draw_text(Image& img, int x, int y, std::string_view text, int scale, const Color& colour) {
  for (size_t at = 0; at < text.size(); x += kGlyphAdvance * scale) {
    const char32_t c = next_code_point(text, at);
    for (int row = 0; row < kGlyphHeight; ++row)
      for (int col = 0; col < kGlyphWidth; ++col) {
        if (!glyph_pixel(c, col, row)) continue;
        for (int dy = 0; dy < scale; ++dy)
          for (int dx = 0; dx < scale; ++dx) {
            const int px = x + col * scale + dx, py = y + row * scale + dy;
            if (px >= 0 && py >= 0 && px < img.width() && py < img.height()) img.at(px, py) = colour;
          }
      }
  }
}

}  // namespace gonio::render
