#pragma once
// What a picture needs beyond the shaded surface (engine/io/render.h): text in a 5 x 7 bitmap font,
// a scale bar, and a colour bar with its range for a field. Pixels only; no font library.
#include <string>

#include "engine/io/render.h"

namespace xcut {

using Rgb = std::array<double, 3>;  ///< 0..1

/// The overlay's pixel size for a picture `height` pixels tall: one font pixel per 300 rows.
inline int overlay_scale(int height) { return height / 300 > 1 ? height / 300 : 1; }
/// Writes `text` with its top-left corner at (x, y) [px], each font pixel `scale` pixels wide.
/// Characters the font lacks are left blank.
void draw_text(Image& image, int x, int y, const std::string& text, const Rgb& colour, int scale);
/// Width of `text` as draw_text draws it [px].
int text_width(const std::string& text, int scale);
void fill_rect(Image& image, int x0, int y0, int x1, int y1, const Rgb& colour);
/// A bar of a round length (1, 2 or 5 times a power of ten) near a fifth of the picture's width,
/// bottom left, labelled ("10 mm"); `pixels_per_metre` at the depth of the bodies' centre.
void draw_scale_bar(Image& image, double pixels_per_metre);
/// The colour map of fields, perceptually ordered (after matplotlib's viridis); u in [0, 1].
Rgb field_colour(double u);
/// A vertical bar of field_colour on the right, `low` at its foot and `high` at its head, labelled
/// with those values in `unit` (a kilo/mega prefix chosen) and `title` above it.
void draw_colour_bar(Image& image, double low, double high, const std::string& unit, const std::string& title);

}  // namespace xcut
