// tools/accuracy/bitmap_font.h — a 5x7 pixel font for plot labels.
//
// Drawn for this tool (not copied from any font): digits, lowercase letters
// and the punctuation plot labels use (space . , - + / % ( ) _ : = < > ^ *).
// Uppercase letters are drawn with their lowercase glyph; any other character
// is a hollow box, so a missing glyph is visible rather than silent.
#pragma once

#include <cstdint>

namespace accuracy {

constexpr int kGlyphWidth = 5, kGlyphHeight = 7, kGlyphAdvance = 6;

// Row r (0 = top) of character c's glyph: bit 4 is the leftmost column.
uint8_t glyph_row(char c, int r);

}  // namespace accuracy
