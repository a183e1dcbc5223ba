#!/usr/bin/python3
"""Writes source/patient/bitmap_font_glyphs.h: the glyphs of the preview's
text (ASCII 32-126), 8 x 14 pixels each, rasterised once from DejaVu Sans
Mono Bold (Bitstream Vera licence) at 13 px with FreeType's autohinter and
thresholded at half coverage. Run from the repository's root; the output is
committed, so that softface needs no font at run time."""

import sys

import numpy as np
from matplotlib.ft2font import FT2Font, LOAD_FORCE_AUTOHINT

FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSansMono-Bold.ttf"
WIDTH, HEIGHT, SIZE, BASELINE = 8, 14, 13, 11


def glyph(code):
    font = FT2Font(FONT)
    font.set_size(SIZE, 72)
    font.set_text(chr(code), 0, flags=LOAD_FORCE_AUTOHINT)
    font.draw_glyphs_to_bitmap(antialiased=True)
    image = np.asarray(font.get_image())
    metrics = font.load_char(code, flags=LOAD_FORCE_AUTOHINT)
    top = BASELINE - metrics.horiBearingY // 64
    left = metrics.horiBearingX // 64
    rows = [0] * HEIGHT
    for y in range(image.shape[0]):
        for x in range(image.shape[1]):
            if image[y, x] > 127 and 0 <= top + y < HEIGHT and 0 <= left + x < WIDTH:
                rows[top + y] |= 0x80 >> (left + x)
    return rows


def main():
    out = sys.stdout if len(sys.argv) < 2 else open(sys.argv[1], "w")
    out.write("// Made by scripts/make_bitmap_font.py (DejaVu Sans Mono Bold, Bitstream\n"
              "// Vera licence): ASCII 32-126, 14 rows of 8 pixels each, the leftmost\n"
              "// pixel in the highest bit.\n")
    out.write("// clang-format off\n")
    out.write("constexpr unsigned char glyph_rows[95][14] = {\n")
    for code in range(32, 127):
        rows = ", ".join("0x%02x" % r for r in glyph(code))
        name = {" ": "space", "\\": "backslash"}.get(chr(code), chr(code))
        out.write("  {%s}, // %s\n" % (rows, name))
    out.write("};\n// clang-format on\n")


if __name__ == "__main__":
    main()
