#include "engine/io/image_overlay.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace xcut {
namespace {

/// A 5 x 7 font (the classic character-LCD shapes): per glyph 7 rows, bit 4 the leftmost pixel.
const std::map<char, std::array<uint8_t, 7>>& font() {
    static const std::map<char, std::array<uint8_t, 7>> glyphs = {
        {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}}, {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
        {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}}, {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
        {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}}, {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
        {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}}, {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
        {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}}, {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
        {'.', {0, 0, 0, 0, 0, 0x0C, 0x0C}},               {'-', {0, 0, 0, 0x1F, 0, 0, 0}},
        {'+', {0, 0x04, 0x04, 0x1F, 0x04, 0x04, 0}},      {'[', {0x0E, 0x08, 0x08, 0x08, 0x08, 0x08, 0x0E}},
        {']', {0x0E, 0x02, 0x02, 0x02, 0x02, 0x02, 0x0E}}, {'|', {0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
        {'a', {0, 0, 0x0E, 0x01, 0x0F, 0x11, 0x0F}},      {'c', {0, 0, 0x0E, 0x10, 0x10, 0x11, 0x0E}},
        {'d', {0x01, 0x01, 0x0D, 0x13, 0x11, 0x11, 0x0F}}, {'e', {0, 0, 0x0E, 0x11, 0x1F, 0x10, 0x0E}},
        {'i', {0x04, 0, 0x0C, 0x04, 0x04, 0x04, 0x0E}},    {'k', {0x10, 0x10, 0x12, 0x14, 0x18, 0x14, 0x12}},
        {'l', {0x0C, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}}, {'m', {0, 0, 0x1A, 0x15, 0x15, 0x11, 0x11}},
        {'n', {0, 0, 0x16, 0x19, 0x11, 0x11, 0x11}},      {'o', {0, 0, 0x0E, 0x11, 0x11, 0x11, 0x0E}},
        {'p', {0, 0, 0x1E, 0x11, 0x1E, 0x10, 0x10}},      {'s', {0, 0, 0x0E, 0x10, 0x0E, 0x01, 0x1E}},
        {'t', {0x08, 0x08, 0x1C, 0x08, 0x08, 0x09, 0x06}}, {'u', {0, 0, 0x11, 0x11, 0x11, 0x13, 0x0D}},
        {'v', {0, 0, 0x11, 0x11, 0x11, 0x0A, 0x04}},      {'x', {0, 0, 0x11, 0x0A, 0x04, 0x0A, 0x11}},
        {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}}, {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
        {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}},
    };
    return glyphs;
}

void put(Image& img, int x, int y, const Rgb& c) {
    if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
    unsigned char* px = &img.rgb[3 * (size_t(y) * img.width + x)];
    for (int k = 0; k < 3; ++k) px[k] = static_cast<unsigned char>(std::lround(255.0 * std::clamp(c[k], 0.0, 1.0)));
}

const Rgb kInk = {0.1, 0.1, 0.12};

/// `value` with a prefix: {scaled value, prefix} (k, M, G for 1e3.., none below 1e3).
std::pair<double, std::string> prefixed(double value, double span) {
    if (span >= 1e9) return {value / 1e9, "G"};
    if (span >= 1e6) return {value / 1e6, "M"};
    if (span >= 1e3) return {value / 1e3, "k"};
    return {value, ""};
}

}  // namespace

int text_width(const std::string& text, int scale) { return static_cast<int>(text.size()) * 6 * scale; }

void draw_text(Image& img, int x, int y, const std::string& text, const Rgb& colour, int scale) {
    for (size_t i = 0; i < text.size(); ++i) {
        const auto it = font().find(text[i]);
        if (it == font().end()) continue;
        for (int row = 0; row < 7; ++row)
            for (int col = 0; col < 5; ++col)
                if (it->second[row] & (0x10 >> col))
                    for (int a = 0; a < scale; ++a)
                        for (int b = 0; b < scale; ++b)
                            put(img, x + int(i) * 6 * scale + col * scale + a, y + row * scale + b, colour);
    }
}

void fill_rect(Image& img, int x0, int y0, int x1, int y1, const Rgb& colour) {
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) put(img, x, y, colour);
}

void draw_scale_bar(Image& img, double pixels_per_metre) {
    if (!(pixels_per_metre > 0.0) || !std::isfinite(pixels_per_metre)) return;
    const double want = 0.2 * img.width / pixels_per_metre;  // [m]
    const double decade = std::pow(10.0, std::floor(std::log10(want)));
    double length = decade;
    for (double m : {2.0, 5.0, 10.0})
        if (m * decade <= want) length = m * decade;
    const int px = static_cast<int>(std::lround(length * pixels_per_metre));
    const int scale = overlay_scale(img.height), x0 = 12 * scale, y0 = img.height - 14 * scale;
    fill_rect(img, x0, y0, x0 + px, y0 + 2 * scale, kInk);
    fill_rect(img, x0, y0 - 3 * scale, x0 + scale, y0 + 2 * scale, kInk);
    fill_rect(img, x0 + px - scale, y0 - 3 * scale, x0 + px, y0 + 2 * scale, kInk);
    const std::string label = length < 0.1 ? fmt::format("{:g} mm", length * 1e3) : fmt::format("{:g} m", length);
    draw_text(img, x0 + px / 2 - text_width(label, scale) / 2, y0 - 11 * scale, label, kInk, scale);
}

Rgb field_colour(double u) {
    static constexpr std::array<Rgb, 5> kStops = {{{0.267, 0.005, 0.329}, {0.229, 0.322, 0.546}, {0.128, 0.567, 0.551},
                                                   {0.369, 0.789, 0.383}, {0.993, 0.906, 0.144}}};
    const double x = std::clamp(std::isfinite(u) ? u : 0.0, 0.0, 1.0) * (kStops.size() - 1);
    const int i = std::min(static_cast<int>(x), static_cast<int>(kStops.size()) - 2);
    const double f = x - i;
    return {kStops[i][0] + f * (kStops[i + 1][0] - kStops[i][0]), kStops[i][1] + f * (kStops[i + 1][1] - kStops[i][1]),
            kStops[i][2] + f * (kStops[i + 1][2] - kStops[i][2])};
}

void draw_colour_bar(Image& img, double low, double high, const std::string& unit, const std::string& title) {
    const int scale = overlay_scale(img.height);
    const int h = img.height / 2, w = 10 * scale, x0 = img.width - w - 50 * scale, y0 = (img.height - h) / 2;
    for (int y = 0; y < h; ++y) fill_rect(img, x0, y0 + y, x0 + w, y0 + y + 1, field_colour(1.0 - double(y) / (h - 1)));
    const auto [top, prefix] = prefixed(high, std::max(std::abs(high), std::abs(low)));
    const double bottom = prefixed(low, std::max(std::abs(high), std::abs(low))).first;
    draw_text(img, x0 + w + 3 * scale, y0 - 3 * scale, fmt::format("{:.3g}", top), kInk, scale);
    draw_text(img, x0 + w + 3 * scale, y0 + h - 4 * scale, fmt::format("{:.3g}", bottom), kInk, scale);
    const std::string heading = fmt::format("{} [{}{}]", title, prefix, unit);
    draw_text(img, std::min(x0, img.width - text_width(heading, scale) - 2 * scale), y0 - 14 * scale, heading, kInk, scale);
}

}  // namespace xcut
