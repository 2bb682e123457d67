#pragma once
// A 5 × 7 pixel bitmap font for the labels of gonio's figures (`gonio slice`): digits,
// lower-case letters, A, B, Y, a few signs, and θ, φ, ° (UTF-8). Drawn into an Image at an
// integer scale, so a label needs no font file and no text library.

#include <string_view>

#include "gonio/render/image.h"

namespace gonio::render {

inline constexpr int kGlyphWidth = 5, kGlyphHeight = 7;
// Horizontal distance from one glyph to the next, in font pixels (one blank column).
inline constexpr int kGlyphAdvance = kGlyphWidth + 1;

// True when `c` (a code point) has a glyph. A character without one is drawn as a box.
bool has_glyph(char32_t c);
// Whether font pixel (col, row) of `c` is set; col in [0, 5), row in [0, 7) from the top.
bool glyph_pixel(char32_t c, int col, int row);

// Width in image pixels of `text` (UTF-8) at `scale`: kGlyphAdvance · scale per character,
// less the trailing blank column.
int text_width(std::string_view text, int scale);

// Draws `text` with its top-left corner at (x, y) in `colour`; pixels outside the image
// are skipped. Invalid UTF-8 bytes are drawn as boxes.
void draw_text(Image& img, int x, int y, std::string_view text, int scale, const Color& colour);

}  // namespace gonio::render
