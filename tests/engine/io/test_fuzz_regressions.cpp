// Inputs that once crashed a reader under libFuzzer (docs/fuzzing.md), kept in tests/fuzz/corpus/:
// each must now be refused with an InputError naming the file and the field or line.
#include <gtest/gtest.h>

#include <cctype>
#include <fstream>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "engine/error.h"
#include "engine/io/mesh_io.h"
#include "engine/io/scene.h"

namespace xcut {
namespace {

struct Regression {
    const char* name;
    const char* reader;  ///< "scene", "mesh" (read_mesh_file) or "trajectory"
    const char* file;    ///< under tests/fuzz/corpus/
    const char* field;   ///< what the message must name after the file
    const char* phrase;  ///< and the reason it must give
};

const Regression kRegressions[] = {
    // TetGen's library asserts (aborts) on a flat point set: a "closed" STL whose facets all lie in z = 0.
    {"flat closed STL", "mesh", "surface/crash_flat_closed.stl", "faces", "encloses no volume"},
    // TetGen 1.5 segfaults on intersecting facets when meshing: a cube with a vertex moved through a face.
    {"self-intersecting OBJ", "mesh", "surface/crash_self_intersecting.obj", "faces", "intersects itself"},
    // Two copies of one triangle: "closed", 3 points; TetGen's Delaunay step segfaults on it.
    {"doubled triangle STL", "mesh", "surface/crash_three_points.stl", "faces", "encloses no volume"},
    // TetGen 1.5 asserts in its intersection predicates on a binary VTK surface with a coordinate of
    // 1e-309 beside zeros: surfaces are snapped to 1e-12 of their size first, and this one then has a
    // triangle without area.
    {"denormal coordinate in a VTK surface", "mesh", "vtk/crash_tetgen_denormal.vtk", "triangle 1", "has no area"},
    // And one TetGen aborts on whatever is checked first (an assertion in tri_tri_inter): TetGen runs
    // in a child process, whose abort becomes this error.
    {"TetGen abort in a child process", "mesh", "vtk/crash_tetgen_tri_tri_assert.vtk", "surface", "TetGen aborted on this surface"},
    // A number beyond double's range: nlohmann::json throws out_of_range, not parse_error.
    {"number overflow", "scene", "scene/crash_number_overflow.json", "JSON", "not valid JSON"},
    // A --set override that is not JSON becomes a string; one with invalid UTF-8 made the message's
    // json::dump() throw a type_error instead of the InputError.
    {"override with invalid UTF-8", "scene", "scene/crash_override_invalid_utf8.json", "material.young",
     "expected a number, got \""},
};

void PrintTo(const Regression& r, std::ostream* os) { *os << r.file; }

std::string corpus(const char* file) { return std::string(XCUT_SOURCE_DIR) + "/tests/fuzz/corpus/" + file; }

/// As tests/fuzz/fuzz_scene.cpp: lines "//set field.path=value" are --set overrides too.
std::vector<std::string> overrides_in(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::vector<std::string> out;
    for (std::string line; std::getline(in, line);)
        if (line.rfind("//set ", 0) == 0) out.push_back(line.substr(6));
    return out;
}

class FuzzRegression : public ::testing::TestWithParam<Regression> {};

TEST_P(FuzzRegression, RefusedWithAClearError) {
    const Regression& r = GetParam();
    const std::string path = corpus(r.file);
    try {
        const std::string reader = r.reader;
        if (reader == "scene") {
            load_scene(path, overrides_in(path));
        } else if (reader == "trajectory") {
            read_trajectory_csv(path);
        } else {
            read_mesh_file(path, 0.0);
        }
        FAIL() << "no InputError for " << path;
    } catch (const InputError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(e.file(), path) << msg;
        EXPECT_EQ(msg.rfind(path + ": " + r.field, 0), 0u) << msg;
        EXPECT_NE(msg.find(r.phrase), std::string::npos) << msg;
    }
}

INSTANTIATE_TEST_SUITE_P(Corpus, FuzzRegression, ::testing::ValuesIn(kRegressions),
                         [](const ::testing::TestParamInfo<Regression>& info) {
                             std::string name;
                             for (const char* c = info.param.name; *c; ++c)
                                 name += std::isalnum(static_cast<unsigned char>(*c)) ? *c : '_';
                             return name;
                         });

// A VTK surface with a sliver a few 1e-5 of its size thick: TetGen's quality mesh added 180,000
// points (702,478 tets, 13 s; past libFuzzer's 10 s under the sanitizers). At the fuzzers' limit of
// 20,000 added points (tests/fuzz/fuzz_common.h) it is refused, naming the limit.
TEST(FuzzRegressionLimit, ThinFeatureIsRefusedAtTheMeshersPointLimit) {
    const std::string path = corpus("vtk/timeout_tetgen_thin_feature.vtk");
    const long long before = mesher_point_limit();
    set_mesher_point_limit(20000);
    try {
        read_mesh_file(path, 0.0);
        ADD_FAILURE() << "no InputError for " << path;
    } catch (const InputError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.rfind(path + ": surface", 0), 0u) << msg;
        EXPECT_NE(msg.find("more than 20000 added points"), std::string::npos) << msg;
    }
    set_mesher_point_limit(before);
    EXPECT_EQ(mesher_point_limit(), before);
}

}  // namespace
}  // namespace xcut
