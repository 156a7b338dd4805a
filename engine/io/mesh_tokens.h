#pragma once
// Whitespace-separated tokens with their line numbers, for the text mesh readers (Gmsh, TetGen):
// every error names the file and the line as the file numbers it. Internal to engine/io.
#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "engine/error.h"

namespace xcut::mesh_io_detail {

/// Whitespace-separated tokens with their line numbers; '#' comments skipped when asked.
class Tokens {
public:
    Tokens(const std::string& path, const std::string& text, bool hash_comments) : path_(path) {
        int line = 1;
        size_t i = 0;
        while (i < text.size()) {
            const char ch = text[i];
            if (ch == '\n') {
                ++line, ++i;
            } else if (std::isspace(static_cast<unsigned char>(ch))) {
                ++i;
            } else if (hash_comments && ch == '#') {
                while (i < text.size() && text[i] != '\n') ++i;
            } else {
                const size_t start = i;
                while (i < text.size() && !std::isspace(static_cast<unsigned char>(text[i]))) ++i;
                tokens_.push_back({text.substr(start, i - start), line});
            }
        }
    }
    bool done() const { return at_ >= tokens_.size(); }
    size_t remaining() const { return tokens_.size() - at_; }
    int line() const { return at_ < tokens_.size() ? tokens_[at_].line : (tokens_.empty() ? 1 : tokens_.back().line); }
    const std::string& peek(const char* what) const {
        if (done()) fail(fmt::format("unexpected end of file, expected {}", what));
        return tokens_[at_].text;
    }
    std::string word(const char* what) {
        const std::string& s = peek(what);
        ++at_;
        return s;
    }
    long long integer(const char* what) {
        const std::string s = word(what);
        char* end = nullptr;
        errno = 0;
        const long long v = std::strtoll(s.c_str(), &end, 10);
        if (end == s.c_str() || *end != '\0' || errno != 0)
            fail(fmt::format("\"{}\" is not an integer ({})", s, what), -1);
        return v;
    }
    double real(const char* what) {
        const std::string s = word(what);
        char* end = nullptr;
        const double v = std::strtod(s.c_str(), &end);
        if (end == s.c_str() || *end != '\0') fail(fmt::format("\"{}\" is not a number ({})", s, what), -1);
        return v;
    }
    /// A count read from the file, bounded by what the rest of the file could hold.
    long long count(const char* what, int tokens_each) {
        const long long n = integer(what);
        if (n < 0 || n > static_cast<long long>(remaining() / std::max(1, tokens_each) + 1))
            fail(fmt::format("{} {} does not fit in the rest of the file", what, n), -1);
        return n;
    }
    [[noreturn]] void fail(const std::string& message, int back = 0) const {
        const size_t k = std::min(tokens_.size() ? tokens_.size() - 1 : 0, static_cast<size_t>(std::max<long long>(0, static_cast<long long>(at_) + back)));
        throw InputError(path_, fmt::format("line {}", tokens_.empty() ? 1 : tokens_[k].line), message);
    }
    void expect(const std::string& word_expected) {
        const std::string w = word(word_expected.c_str());
        if (w != word_expected) fail(fmt::format("expected {}, found \"{}\"", word_expected, w), -1);
    }
    /// Skips to the token after `marker`; false if none.
    bool seek(const std::string& marker) {
        while (!done())
            if (tokens_[at_++].text == marker) return true;
        return false;
    }
    void rewind() { at_ = 0; }

private:
    struct Token {
        std::string text;
        int line;
    };
    std::string path_;
    std::vector<Token> tokens_;
    size_t at_ = 0;
};

}  // namespace xcut::mesh_io_detail
