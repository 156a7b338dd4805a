#include "engine/io/json_fields.h"

#include <cmath>
#include <fmt/format.h>

#include "engine/error.h"

namespace xcut {
namespace {
const nlohmann::json kEmptyObject = nlohmann::json::object();

/// A value for a message. Strings from --set overrides may hold invalid UTF-8, which a plain dump()
/// throws on: replace it instead.
std::string shown(const nlohmann::json& v) { return v.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace); }
}

JsonFields::JsonFields(const nlohmann::json& object, std::string file, std::string path)
    : object_(&object), file_(std::move(file)), path_(std::move(path)) {
    if (!object.is_object()) throw InputError(file_, path_.empty() ? "(top level)" : path_, "expected an object");
}

std::string JsonFields::field(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

void JsonFields::fail(const std::string& key, const std::string& message) const {
    throw InputError(file_, field(key), message);
}

bool JsonFields::has(const std::string& key) const { return object_->contains(key); }

const nlohmann::json& JsonFields::get(const std::string& key) const { return object_->at(key); }

JsonFields JsonFields::object(const std::string& key) const {
    if (!has(key)) return JsonFields(kEmptyObject, file_, field(key));
    if (!get(key).is_object()) fail(key, "expected an object");
    return JsonFields(get(key), file_, field(key));
}

/// Fails when the array at `key` holds more than `max_items` entries.
static void check_length(const JsonFields& f, const std::string& key, const nlohmann::json& v, size_t max_items) {
    if (v.size() > max_items)
        f.fail(key, fmt::format("holds {} entries, above the limit of {}", v.size(), max_items));
}

std::vector<JsonFields> JsonFields::array_of_objects(const std::string& key, size_t max_items) const {
    std::vector<JsonFields> out;
    if (!has(key)) return out;
    if (!get(key).is_array()) fail(key, "expected an array");
    const auto& arr = get(key);
    check_length(*this, key, arr, max_items);
    for (size_t i = 0; i < arr.size(); ++i) {
        const std::string item = fmt::format("{}[{}]", key, i);
        if (!arr[i].is_object()) fail(item, "expected an object");
        out.emplace_back(arr[i], file_, field(item));
    }
    return out;
}

double JsonFields::required_number(const std::string& key, double min, double max) const {
    if (!has(key)) fail(key, "required field is missing");
    const auto& v = get(key);
    if (!v.is_number()) fail(key, fmt::format("expected a number, got {}", shown(v)));
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(key, "must be finite");
    if (d < min || d > max) fail(key, fmt::format("{} is out of range [{}, {}]", d, min, max));
    return d;
}

double JsonFields::number(const std::string& key, double fallback, double min, double max) const {
    return has(key) ? required_number(key, min, max) : fallback;
}

int JsonFields::integer(const std::string& key, int fallback, int min, int max) const {
    if (!has(key)) return fallback;
    const auto& v = get(key);
    if (!v.is_number_integer()) fail(key, fmt::format("expected an integer, got {}", shown(v)));
    const long long i = v.get<long long>();
    if (i < min || i > max) fail(key, fmt::format("{} is out of range [{}, {}]", i, min, max));
    return static_cast<int>(i);
}

bool JsonFields::boolean(const std::string& key, bool fallback) const {
    if (!has(key)) return fallback;
    if (!get(key).is_boolean()) fail(key, fmt::format("expected true or false, got {}", shown(get(key))));
    return get(key).get<bool>();
}

std::string JsonFields::string(const std::string& key, const std::string& fallback) const {
    if (!has(key)) return fallback;
    if (!get(key).is_string()) fail(key, fmt::format("expected a string, got {}", shown(get(key))));
    const auto& s = get(key).get_ref<const std::string&>();
    if (s.size() > kMaxJsonString)
        fail(key, fmt::format("is {} characters long, above the limit of {}", s.size(), kMaxJsonString));
    return s;
}

std::string JsonFields::choice(const std::string& key, const std::string& fallback,
                               std::initializer_list<const char*> choices) const {
    const std::string s = string(key, fallback);
    std::string list;
    for (const char* c : choices) {
        if (s == c) return s;
        list += list.empty() ? "" : ", ";
        list += fmt::format("\"{}\"", c);
    }
    fail(key, fmt::format("\"{}\" is not one of {}", s, list));
}

Eigen::Vector3d JsonFields::required_vec3(const std::string& key) const {
    if (!has(key)) fail(key, "required field is missing");
    const auto& v = get(key);
    if (!v.is_array() || v.size() != 3) fail(key, fmt::format("expected an array of 3 numbers, got {}", shown(v)));
    Eigen::Vector3d out;
    for (int k = 0; k < 3; ++k) {
        if (!v[k].is_number()) fail(fmt::format("{}[{}]", key, k), "expected a number");
        out[k] = v[k].get<double>();
        if (!std::isfinite(out[k])) fail(fmt::format("{}[{}]", key, k), "must be finite");
    }
    return out;
}

Eigen::Vector3d JsonFields::vec3(const std::string& key, const Eigen::Vector3d& fallback) const {
    return has(key) ? required_vec3(key) : fallback;
}

std::vector<int> JsonFields::int_list(const std::string& key, size_t max_items) const {
    std::vector<int> out;
    if (!has(key)) return out;
    const auto& v = get(key);
    if (!v.is_array()) fail(key, "expected an array of integers");
    check_length(*this, key, v, max_items);
    for (size_t i = 0; i < v.size(); ++i) {
        if (!v[i].is_number_integer() || v[i].get<long long>() < 0 || v[i].get<long long>() > 2147483647)
            fail(fmt::format("{}[{}]", key, i), "expected a non-negative integer");
        out.push_back(v[i].get<int>());
    }
    return out;
}

std::vector<Eigen::Vector3d> JsonFields::vec3_list(const std::string& key, size_t max_items) const {
    std::vector<Eigen::Vector3d> out;
    if (!has(key)) return out;
    const auto& v = get(key);
    if (!v.is_array()) fail(key, "expected an array of [x, y, z] points");
    check_length(*this, key, v, max_items);
    for (size_t i = 0; i < v.size(); ++i) {
        const std::string item = fmt::format("{}[{}]", key, i);
        if (!v[i].is_array() || v[i].size() != 3) fail(item, fmt::format("expected [x, y, z], got {}", shown(v[i])));
        Eigen::Vector3d p;
        for (int k = 0; k < 3; ++k) {
            if (!v[i][k].is_number() || !std::isfinite(v[i][k].get<double>()))
                fail(fmt::format("{}[{}]", item, k), "expected a finite number");
            p[k] = v[i][k].get<double>();
        }
        out.push_back(p);
    }
    return out;
}

void JsonFields::allow_only(std::initializer_list<const char*> known) const {
    for (auto it = object_->begin(); it != object_->end(); ++it) {
        bool ok = false;
        for (const char* k : known) ok = ok || it.key() == k;
        if (ok) continue;
        std::string list;
        for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
        const std::string& key = it.key();
        fail(key.size() > 80 ? key.substr(0, 80) + "..." : key, fmt::format("unknown field (known here: {})", list));
    }
}

}  // namespace xcut
