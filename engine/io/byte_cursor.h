#pragma once
// A read position in a mesh file, text or mixed text and binary (Gmsh .msh, legacy VTK, TetGen
// .node/.ele, ASCII STL): whitespace-separated tokens for the text, fixed-size little- or big-endian values for the
// binary. Every error names the file and where: "line N" in text, "byte N (line L)" in binary data.
// Counts read from the file are bounded by the bytes left, so a corrupt count cannot allocate.
// Internal to engine/io.
#include <fmt/format.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>

#include "engine/error.h"

namespace xcut::mesh_io_detail {

class ByteCursor {
public:
    /// `hash_comments`: '#' to the end of the line is skipped like whitespace (TetGen files).
    ByteCursor(std::string path, std::string_view data, bool hash_comments = false)
        : path_(std::move(path)), data_(data), hash_comments_(hash_comments) {}

    const std::string& path() const { return path_; }
    size_t pos() const { return pos_; }
    size_t left() const { return data_.size() - pos_; }
    /// True when only whitespace is left.
    bool done() {
        skip_space();
        return pos_ >= data_.size();
    }
    /// The next whitespace-separated token.
    std::string_view token(const char* what) {
        skip_space();
        mark_ = pos_, binary_mark_ = false;
        if (pos_ >= data_.size()) fail(fmt::format("unexpected end of file, expected {}", what));
        const size_t start = pos_;
        while (pos_ < data_.size() && !is_space(data_[pos_])) ++pos_;
        return data_.substr(start, pos_ - start);
    }
    long long integer(const char* what);
    double real(const char* what);
    /// A count of items that each take at least `min_bytes` of what is left.
    long long count(const char* what, size_t min_bytes) {
        const long long n = integer(what);
        check_count(n, what, min_bytes);
        return n;
    }
    void check_count(long long n, const char* what, size_t min_bytes) const {
        if (n < 0 || static_cast<unsigned long long>(n) > left() / (min_bytes ? min_bytes : 1) + 1)
            fail(fmt::format("{} {} does not fit in the rest of the file ({} bytes)", what, n, left()));
    }
    /// The rest of the current line, without the line break (moves past it).
    std::string_view rest_of_line() {
        mark_ = pos_, binary_mark_ = false;
        const size_t start = pos_;
        while (pos_ < data_.size() && data_[pos_] != '\n') ++pos_;
        std::string_view s = data_.substr(start, pos_ - start);
        if (pos_ < data_.size()) ++pos_;
        if (!s.empty() && s.back() == '\r') s.remove_suffix(1);
        return s;
    }
    /// Moves past the line break that ends a text line before binary data.
    void end_line() {
        while (pos_ < data_.size() && (data_[pos_] == ' ' || data_[pos_] == '\t' || data_[pos_] == '\r')) ++pos_;
        if (pos_ < data_.size() && data_[pos_] == '\n') ++pos_;
    }
    void expect(std::string_view word) {
        const std::string_view w = token(std::string(word).c_str());
        if (w != word) fail(fmt::format("expected {}, found \"{}\"", word, clip(w)));
    }
    /// Moves to just after the next token equal to `marker`; false (at the end) if none.
    bool seek(std::string_view marker) {
        while (!done())
            if (token("marker") == marker) return true;
        return false;
    }
    /// A binary value of type T; `big_endian` as the file stores it.
    template <class T>
    T binary(const char* what, bool big_endian) {
        static_assert(std::is_arithmetic_v<T>);
        mark_ = pos_, binary_mark_ = true;
        if (left() < sizeof(T)) fail(fmt::format("binary data ends early, expected {}", what));
        unsigned char b[sizeof(T)];
        std::memcpy(b, data_.data() + pos_, sizeof(T));
        if (big_endian != host_big_endian())
            for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
        T v;
        std::memcpy(&v, b, sizeof(T));
        pos_ += sizeof(T);
        return v;
    }
    /// Where the last token or value began, as a message names it.
    std::string where() const;
    [[noreturn]] void fail(const std::string& message) const { throw InputError(path_, where(), message); }

    static bool host_big_endian() {
        const uint16_t one = 1;
        unsigned char b;
        std::memcpy(&b, &one, 1);
        return b == 0;
    }
    /// A token as a message quotes it: at most 40 bytes, a byte outside printable ASCII as \xNN (a
    /// binary file's bytes would otherwise reach the terminal raw).
    static std::string clip(std::string_view s);
    /// Whether a token holds a byte outside printable ASCII (binary data where text was expected).
    static bool is_binary(std::string_view s);

private:
    static bool is_space(char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t' || c == '\v' || c == '\f'; }
    void skip_space() {
        while (pos_ < data_.size()) {
            if (hash_comments_ && data_[pos_] == '#') {
                while (pos_ < data_.size() && data_[pos_] != '\n') ++pos_;
            } else if (is_space(data_[pos_])) {
                ++pos_;
            } else {
                return;
            }
        }
    }
    std::string path_;
    std::string_view data_;
    size_t pos_ = 0, mark_ = 0;
    bool binary_mark_ = false;
    bool hash_comments_ = false;
};

}  // namespace xcut::mesh_io_detail
