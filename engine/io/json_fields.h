#pragma once
// Typed, checked access to a JSON object that knows where it is ("scene.json: solver.dt: ..."), so
// every scene error names the file and the field path. Unknown keys are errors too: a typo in a
// field name must not silently fall back to a default.
#include <Eigen/Core>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace xcut {

/// The most characters a string field may hold (paths included): longer is an error naming the bound.
inline constexpr size_t kMaxJsonString = 4096;
/// The most entries a list field may hold unless its reader names another bound.
inline constexpr size_t kMaxJsonList = 4'000'000;

class JsonFields {
public:
    JsonFields(const nlohmann::json& object, std::string file, std::string path);

    bool has(const std::string& key) const;
    /// A nested object; throws if present and not an object. Missing: an empty object.
    JsonFields object(const std::string& key) const;
    /// At most `max_items` objects: more is an error naming the bound.
    std::vector<JsonFields> array_of_objects(const std::string& key, size_t max_items = 100000) const;

    double number(const std::string& key, double fallback, double min = -std::numeric_limits<double>::max(),
                  double max = std::numeric_limits<double>::max()) const;
    double required_number(const std::string& key, double min = -std::numeric_limits<double>::max(),
                           double max = std::numeric_limits<double>::max()) const;
    int integer(const std::string& key, int fallback, int min = std::numeric_limits<int>::min(),
                int max = std::numeric_limits<int>::max()) const;
    bool boolean(const std::string& key, bool fallback) const;
    std::string string(const std::string& key, const std::string& fallback) const;
    /// One of `choices`; the message lists them.
    std::string choice(const std::string& key, const std::string& fallback,
                       std::initializer_list<const char*> choices) const;
    Eigen::Vector3d vec3(const std::string& key, const Eigen::Vector3d& fallback) const;
    Eigen::Vector3d required_vec3(const std::string& key) const;
    std::vector<int> int_list(const std::string& key, size_t max_items = kMaxJsonList) const;
    /// An array of [x, y, z] points.
    std::vector<Eigen::Vector3d> vec3_list(const std::string& key, size_t max_items = 1'000'000) const;

    /// Throws if the object has a key not in `known`.
    void allow_only(std::initializer_list<const char*> known) const;

    /// The raw JSON value (must exist).
    const nlohmann::json& raw(const std::string& key) const { return get(key); }

    [[noreturn]] void fail(const std::string& key, const std::string& message) const;
    std::string field(const std::string& key) const;
    const std::string& file() const { return file_; }

private:
    const nlohmann::json& get(const std::string& key) const;

    const nlohmann::json* object_;
    std::string file_;
    std::string path_;
};

}  // namespace xcut
