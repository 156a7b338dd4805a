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

}  // namespace xcut
