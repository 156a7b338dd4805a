#pragma once
// Errors a user can cause: every one names the file and the field (or line) it came from, so the
// CLI can print it and exit non-zero instead of crashing or running on garbage.
#include <stdexcept>
#include <string>

namespace xcut {

class InputError : public std::runtime_error {
public:
    InputError(std::string file, std::string field, const std::string& what)
        : std::runtime_error(file + ": " + field + ": " + what), file_(std::move(file)), field_(std::move(field)),
          message_(what) {}
    const std::string& file() const { return file_; }
    const std::string& field() const { return field_; }
    const std::string& message() const { return message_; }  ///< what, without the file and field

private:
    std::string file_;
    std::string field_;
    std::string message_;
};

/// A numerical failure the run cannot recover from: a linear solve that stays above its tolerance
/// in the finest substeps, a NaN or an infinity in the state, energy growing past the work put in.
/// The run stops with this message (naming the step and what to change), never with garbage.
class NumericalError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace xcut
