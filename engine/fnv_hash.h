#pragma once
// FNV-1a (Fowler, Noll & Vo) over the contents of values and vectors: the access check's component
// hashes (engine/access_check.h) and the tests' record of a run's end state.
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "components/tools.h"

namespace xcut {

/// FNV-1a over the bytes of what is added; vectors by their contents, not their pointers. A value
/// is taken as its bytes: only types without padding are added (numbers, ids, fixed-size Eigen
/// vectors and matrices, arrays of them), so no uninitialized byte reaches the hash.
struct Hasher {
    uint64_t h = 1469598103934665603ull;
    void bytes(const void* data, size_t n) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
    }
    template <class T>
    void add(const T& v) {
        if constexpr (std::is_same_v<T, std::string>) {
            add(v.size());
            bytes(v.data(), v.size());
        } else {
            bytes(&v, sizeof v);
        }
    }
    template <class T>
    void add(const std::vector<T>& v) {
        add(v.size());
        if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, Keyframe>) {
            for (const T& x : v) add(x);
        } else if constexpr (std::is_class_v<T> && requires(const T& x) { x.begin(); x.size(); }) {
            for (const T& x : v) add(x);
        } else {
            bytes(v.data(), v.size() * sizeof(T));
        }
    }
    void add(const Keyframe& k) { all(k.time, k.position, k.orientation.coeffs()); }
    template <class... T>
    void all(const T&... v) { (add(v), ...); }
};

/// FNV-1a of a text's bytes, from `seed` (a hash to go on from): stable file names for cached results.
inline uint64_t fnv1a(const std::string& text, uint64_t seed = Hasher{}.h) {
    Hasher h{seed};
    h.bytes(text.data(), text.size());
    return h.h;
}

}  // namespace xcut
