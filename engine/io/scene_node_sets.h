#pragma once
// Named node sets held by constraints ("constraints.fixed_sets", docs/scene-format.md): the nodes of
// a region of a body's mesh, of a sphere, or listed in an index file. Read with the scene, resolved
// to node indices once the bodies' meshes are loaded. Internal to engine/io.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "components/constraints.h"
#include "engine/io/json_fields.h"
#include "engine/io/scene.h"

namespace xcut {

/// "axes": letters x, y, z -> bit mask (x = 1, y = 2, z = 4); default "xyz".
uint8_t read_axes(const JsonFields& f, const std::string& key);
std::vector<FixedSetSpec> read_fixed_sets(const JsonFields& constraints, const std::filesystem::path& scene_dir);
/// Each set's nodes; an InputError naming "constraints.fixed_sets[i]..." when a region or body does
/// not exist, a sphere holds no node, or an index file has a bad or out-of-range index.
std::vector<FixedSet> resolve_fixed_sets(const Scene& scene, const SceneBodies& bodies);

}  // namespace xcut
