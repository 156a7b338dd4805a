// Refactors keep the bits: every shipped scene, and the default scene with each linear method, the
// snapping cutter and Newton iterations, is run to its end and hashed (every node's position and
// velocity, the cut's counts, each step's CG iterations); the hashes must equal those recorded in
// tests/golden/runs.txt by the build before the refactor. The record is of the portable build
// (without -DXCUT_AVX2, whose fused multiply-adds round otherwise) with OpenBLAS's generic x86-64
// kernels (OPENBLAS_CORETYPE=Prescott, set by CMakeLists.txt for every test: the kernels OpenBLAS picks
// for a CPU round differently, so a record written on one machine failed on another), and with the
// factor solves' AVX2 kernels or their portable ones alike (ctest runs it once more with
// XCUT_KERNELS=generic: GoldenRuns.OnThePortableSolveKernels); XCUT_GOLDEN_WRITE=1
// rewrites it, for a change that is meant to move the numbers (say why in its commit).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "engine/fnv_hash.h"
#include "engine/parallel.h"
#include "systems/pipeline.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

struct Case {
    std::string name, scene;
    std::vector<std::string> overrides;
};

std::vector<Case> cases() {
    std::vector<Case> out;
    for (const auto& entry : fs::directory_iterator(fs::path(XCUT_SOURCE_DIR) / "scenes"))
        if (entry.path().extension() == ".json") out.push_back({entry.path().stem().string(), entry.path().string(), {}});
    std::sort(out.begin(), out.end(), [](const Case& a, const Case& b) { return a.name < b.name; });
    const std::string skin = std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json";
    for (const char* method : {"jacobi", "block_jacobi", "amg", "direct"})
        out.push_back({fmt::format("skin_slab_{}", method), skin, {fmt::format("solver.linear=\"{}\"", method)}});
    out.push_back({"skin_slab_snap", skin, {"cutter.type=\"snap\""}});
    out.push_back({"skin_slab_progressive", skin, {"cutter.front=\"progressive\""}});
    // The crack front at the blade, whose block rides on factors renewed off the step.
    out.push_back({"skin_slab_front", skin, {"cutter.tip={}"}});
    out.push_back({"open_surgery_newton", std::string(XCUT_SOURCE_DIR) + "/scenes/open_surgery.json",
                   {"solver.newton={\"iterations\": 3}"}});
    return out;
}

uint64_t run_and_hash(const Case& c) {
    std::vector<std::string> overrides = c.overrides;
    overrides.push_back("output.vtu=false");
    overrides.push_back("output.metrics_csv=false");
    Scene scene = load_scene(c.scene, overrides);
    auto sim = make_simulation(scene, /*with_output=*/false);
    Hasher h;
    for (int i = 0; i < scene.steps; ++i) {
        step_simulation(*sim);
        h.add(sim->world.metrics.current.cg_iterations);
    }
    const World& w = sim->world;
    h.bytes(w.nodes.position.data(), w.nodes.position.size() * sizeof(Vec3));
    h.bytes(w.nodes.velocity.data(), w.nodes.velocity.size() * sizeof(Vec3));
    h.add(w.cuts.count());
    h.add(w.enriched.count());
    h.add(w.snap.elements_split);
    h.add(w.step);
    return h.h;
}

std::map<std::string, std::string> read_record(const fs::path& p) {
    std::map<std::string, std::string> out;
    std::ifstream in(p);
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream ss(line);
        std::string name, hash;
        ss >> name >> hash;
        out[name] = hash;
    }
    return out;
}

TEST(GoldenRuns, EveryScenesBitsAreAsRecorded) {
#if defined(__AVX2__) || defined(__FMA__)
    GTEST_SKIP() << "the record is of the portable build";
#endif
    set_thread_count(2);
    const char* core = std::getenv("OPENBLAS_CORETYPE");
    if (!core || std::strcmp(core, "Prescott") != 0)
        GTEST_SKIP() << "the record is of OpenBLAS's generic kernels: run with OPENBLAS_CORETYPE=Prescott (ctest does)";
    const fs::path record = fs::path(XCUT_SOURCE_DIR) / "tests" / "golden" / "runs.txt";
    const bool write = std::getenv("XCUT_GOLDEN_WRITE") != nullptr;
    const std::map<std::string, std::string> recorded = read_record(record);
    std::ostringstream fresh;
    fresh << "# scene-or-variant  FNV-1a hash of the run's end state (tests/tools/test_golden_runs.cpp)\n";
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        const std::string hash = fmt::format("{:016x}", run_and_hash(c));
        fresh << c.name << " " << hash << "\n";
        if (write) continue;
        const auto it = recorded.find(c.name);
        ASSERT_NE(it, recorded.end()) << "no recorded hash: run with XCUT_GOLDEN_WRITE=1 on the build before the change";
        EXPECT_EQ(hash, it->second) << "the run's bits moved";
    }
    if (write) {
        fs::create_directories(record.parent_path());
        std::ofstream(record) << fresh.str();
    }
}

}  // namespace
}  // namespace xcut
