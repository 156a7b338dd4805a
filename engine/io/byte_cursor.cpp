#include "engine/io/byte_cursor.h"

#include <algorithm>
#include <charconv>

namespace xcut::mesh_io_detail {

namespace {
std::string_view without_plus(std::string_view s) { return s.size() > 1 && s[0] == '+' ? s.substr(1) : s; }
}  // namespace

long long ByteCursor::integer(const char* what) {
    const std::string_view s = token(what);
    const std::string_view d = without_plus(s);
    long long v = 0;
    const auto [end, ec] = std::from_chars(d.data(), d.data() + d.size(), v);
    if (ec != std::errc() || end != d.data() + d.size()) fail(fmt::format("\"{}\" is not an integer ({})", clip(s), what));
    return v;
}

double ByteCursor::real(const char* what) {
    const std::string_view s = token(what);
    const std::string_view d = without_plus(s);
    double v = 0.0;
    const auto [end, ec] = std::from_chars(d.data(), d.data() + d.size(), v);
    // Out of range (1e999) is a number too large for a double: an error, not infinity.
    if (ec != std::errc() || end != d.data() + d.size()) fail(fmt::format("\"{}\" is not a number ({})", clip(s), what));
    return v;
}

std::string ByteCursor::clip(std::string_view s) {
    std::string out;
    for (const char ch : s.substr(0, 40)) {
        const auto c = static_cast<unsigned char>(ch);
        if (c >= 0x20 && c < 0x7f) out += ch;
        else out += fmt::format("\\x{:02X}", c);
    }
    return out + (s.size() > 40 ? "..." : "");
}

bool ByteCursor::is_binary(std::string_view s) {
    return std::any_of(s.begin(), s.end(), [](char ch) {
        const auto c = static_cast<unsigned char>(ch);
        return c < 0x20 || c >= 0x7f;
    });
}

std::string ByteCursor::where() const {
    const size_t at = std::min(mark_, data_.size());
    const long long line = 1 + std::count(data_.begin(), data_.begin() + static_cast<std::ptrdiff_t>(at), '\n');
    if (binary_mark_) return fmt::format("byte {} (binary data after line {})", at, line);
    return fmt::format("line {}", line);
}

}  // namespace xcut::mesh_io_detail
