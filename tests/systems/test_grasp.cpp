// Graspers (systems/grasp_system.h): what the jaws take when they close (against the skin's own
// vertex positions), that closing moves nothing, that they let go, that closing on nothing is said,
// and, on the excision scene, that they draw a freed piece out where the uncut skin holds.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "engine/io/scene.h"
#include "engine/io/scene_checks.h"
#include "engine/simulation.h"
#include "systems/cut/pieces_system.h"
#include "systems/grasp_system.h"
#include "systems/pipeline.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

/// A 10 x 10 mm sheet of 1 mm cells with its skin, held on its left border; a grasper at (6, 5) mm
/// (or `where`) closing at 0.02 s and opening at `open` s, then moving 2 mm along x by 0.08 s.
/// `solver`: more of the solver's settings.
std::unique_ptr<Simulation> sheet_with_grasper(const std::string& where = "0.006, 0.005", const std::string& open = "0.1",
                                               const std::string& solver = "") {
    const std::string text = R"({
      "mesh": {"generator": "plate", "size": [0.01, 0.01, 0], "element_size": 0.001},
      "visual": {"subdivisions": 0},
      "material": {"young": 1e4, "poisson": 0.3, "density": 1000, "thickness": 0.002},
      "constraints": {"fixed_boxes": [{"min": [-1, -1, -1], "max": [1e-6, 1, 1]}]},
      "tools": [{"name": "grasper", "grasp": {"radius": 0.0015, "close": 0.02, "open": )" + open + R"(, "stiffness": 5},
                 "trajectory": [{"time": 0, "position": [)" + where + R"(, 0]}, {"time": 0.03, "position": [)" + where +
                             R"(, 0]}, {"time": 0.08, "position": [0.008, 0.005, 0]}]}],
      "solver": {)" + solver + R"("dt": 0.01},
      "steps": 12
    })";
    return make_simulation(load_scene_text(text, "grasped sheet", "."), /*with_output=*/false);
}

TEST(Grasp, TheJawsTakeTheSkinWithinTheirReachHoldItWithoutAJumpAndLetItGo) {
    auto sim = sheet_with_grasper();
    World& w = sim->world;
    while (w.time < 0.015) step_simulation(*sim);
    EXPECT_EQ(w.grasps.state[0], Grasps::kWaiting);
    // The skin's vertices within 1.5 mm of (6, 5) mm, from the surface's own positions.
    int within = 0;
    for (const Vec3& x : w.visual.position) within += (x - Vec3(0.006, 0.005, 0)).norm() <= 0.0015;
    ASSERT_GT(within, 4);
    step_simulation(*sim);  // t = 0.02 s: the jaws close
    ASSERT_EQ(w.grasps.state[0], Grasps::kHolding);
    EXPECT_EQ(static_cast<int>(w.grasps.vertex[0].size()), within);
    EXPECT_EQ(w.grasps.held_at_close[0], within);
    EXPECT_LT(w.grasps.peak_force[0], 1e-12) << "each vertex is held where it was: closing pulls nothing";
    while (w.time < 0.075) step_simulation(*sim);
    EXPECT_LT(w.grasps.force[0].x(), -1e-4) << "drawn along +x, the skin held on its left pulls the jaws back";
    EXPECT_EQ(w.tools.reaction_force[0], w.grasps.force[0]) << "the pull is the tool's reaction";
    // The held vertices follow the jaws: their mean moved most of the tool's 2 mm (the skin resists).
    Vec3 mean = Vec3::Zero();
    for (int v : w.grasps.vertex[0]) mean += w.visual.position[v] / static_cast<double>(w.grasps.vertex[0].size());
    EXPECT_GT(mean.x() - 0.006, 0.001);
    while (w.time < 0.105) step_simulation(*sim);
    EXPECT_EQ(w.grasps.state[0], Grasps::kReleased);
    EXPECT_TRUE(w.grasps.vertex[0].empty());
    EXPECT_EQ(w.grasps.force[0], Vec3::Zero());
    for (const std::string& n : end_of_run_notes(w)) EXPECT_EQ(n.find("closed its jaws"), std::string::npos) << n;
}

TEST(Grasp, JawsThatCloseOnNoSkinSaySo) {
    auto sim = sheet_with_grasper("0.03, 0.03");  // 20 mm off the sheet
    while (sim->world.time < 0.025) step_simulation(*sim);
    EXPECT_EQ(sim->world.grasps.held_at_close[0], 0);
    std::string notes;
    for (const std::string& n : end_of_run_notes(sim->world)) notes += n + "\n";
    EXPECT_NE(notes.find("tool \"grasper\" closed its jaws at 0.02 s on no skin"), std::string::npos) << notes;
}

// The jaws change the step's matrix by a stiffness of low rank as they close and open: the kept
// Cholesky factor, made before, solves through the difference beside it (Woodbury by an augmented
// block, systems/solver/beside_augment.h), so neither step factors nor needs many more CG
// iterations than the steps around it, and every step keeps its tolerance.
TEST(Grasp, JawsThatCloseOrOpenKeepTheFactorInUse) {
    auto sim = sheet_with_grasper("0.006, 0.005", "0.2", R"("linear": "cholesky", "cg_tolerance": 1e-8, )");
    World& w = sim->world;
    std::vector<int> iterations, beside;  // per step: CG iterations, solves beside the factor so far
    int factored = 0;
    while (w.time < 0.3 - 1e-9) {
        step_simulation(*sim);
        const StepMetrics& m = w.metrics.current;
        iterations.push_back(m.cg_iterations);
        beside.push_back(w.linear.beside_factor ? w.linear.beside_factor->moving.solves : 0);
        EXPECT_LE(m.cg_residual, 1e-8) << "t = " << w.time;
        factored += m.preconditioner == 3 && w.step > 1;
    }
    EXPECT_EQ(factored, 0) << "no step but the first factors";
    // Step 3 starts at 0.02 s (the jaws close), step 21 at 0.2 s (they open); the factor in use at
    // 21 was asked for while they held. Without the block beside it: 8 iterations at 3, 14 at 21.
    for (int step : {3, 21}) {
        EXPECT_GT(beside[step - 1], beside[step - 2]) << "step " << step << " solved beside the factor";
        const int before = *std::max_element(iterations.begin() + std::max(0, step - 6), iterations.begin() + step - 1);
        EXPECT_LE(iterations[step - 1], before + 2) << "step " << step;
    }
}

/// The sheet of Grasp.JawsThatClose...: a scalpel that carries its tip 5 mm into it and stands from
/// 0.03 s, a grasper whose jaws close at 0.08 s; `solver` the scene's solver settings. Steps to
/// 0.11 s, every step within the tolerance; per step the CG iterations and the metrics'
/// preconditioner.
std::unique_ptr<Simulation> sheet_with_a_standing_tip(const std::string& solver, std::vector<int>& iterations,
                                                      std::vector<int>& preconditioner) {
    const std::string text = R"({
      "mesh": {"generator": "plate", "size": [0.01, 0.01, 0], "element_size": 0.001},
      "visual": {"subdivisions": 0},
      "material": {"young": 1e4, "poisson": 0.3, "density": 1000, "thickness": 0.002},
      "constraints": {"fixed_boxes": [{"min": [-1, -1, -1], "max": [1e-6, 1, 1]}]},
      "cutter": {"tip": {}},
      "tools": [{"name": "scalpel", "blade": {"tip": [0, 0, 0], "heel": [0, 0, 0.001]},
                 "trajectory": [{"time": 0, "position": [0.0045, 0.0105, 0]}, {"time": 0.03, "position": [0.0045, 0.0055, 0]}]},
                {"name": "grasper", "grasp": {"radius": 0.0015, "close": 0.08, "open": 1, "stiffness": 5},
                 "trajectory": [{"time": 0, "position": [0.008, 0.004, 0]}]}],
      "solver": )" + solver + R"(,
      "steps": 12
    })";
    auto sim = make_simulation(load_scene_text(text, "grasped sheet with a tip", "."), /*with_output=*/false);
    World& w = sim->world;
    while (w.time < 0.11 - 1e-9) {
        step_simulation(*sim);
        iterations.push_back(w.metrics.current.cg_iterations);
        preconditioner.push_back(w.metrics.current.preconditioner);
        EXPECT_LE(w.metrics.current.cg_residual, 1e-8) << "t = " << w.time;
    }
    EXPECT_EQ(w.grasps.state[1], Grasps::kHolding);
    EXPECT_FALSE(w.grasps.vertex[1].empty());
    return sim;
}

// Beside a crack tip that stands (the blade stopped inside the sheet), cholesky with its factor
// renewed off the step solves with the factor in use and the tip's block beside it, as while the
// tip moved (systems/solver/beside_factor.h): no step factors the whole system, neither where the
// blade stops nor where the jaws close (their jump joins the block), and the step the jaws close
// needs no more CG iterations than the steps before.
TEST(Grasp, JawsThatCloseBesideAStandingCrackTipKeepTheFactorInUse) {
    std::vector<int> iterations, preconditioner;
    const auto sim = sheet_with_a_standing_tip(R"({"linear": "cholesky", "cg_tolerance": 1e-8, "dt": 0.01})", iterations,
                                               preconditioner);
    const World& w = sim->world;
    ASSERT_TRUE(w.linear.beside_factor && w.linear.beside_factor->moving.ok) << "solved beside the tip's block";
    EXPECT_FALSE(w.linear.beside_factor->ok) << "no factor of the whole system";
    for (size_t i = 1; i < preconditioner.size(); ++i) EXPECT_NE(preconditioner[i], 3) << "step " << i + 1;
    // Step 9 starts at 0.08 s, as the jaws close; the blade stood from 0.03 s.
    const int before = *std::max_element(iterations.begin() + 5, iterations.begin() + 8);
    EXPECT_LE(iterations[8], before + 1);
}

// With factors made in the step (factor_delay 0), a standing tip's steps are preconditioned by the
// factor of the whole system with the tip's block, made in the step. That factor holds the grasps
// as they were, so it is made again at the step the jaws close: that step needs no more CG
// iterations than the steps before.
TEST(Grasp, JawsThatCloseBesideAStandingCrackTipRenewTheWholeSystemsFactorInTheStep) {
    std::vector<int> iterations, preconditioner;
    const auto sim = sheet_with_a_standing_tip(R"({"linear": "cholesky", "cg_tolerance": 1e-8, "dt": 0.01, "factor_delay": 0})",
                                               iterations, preconditioner);
    ASSERT_TRUE(sim->world.linear.beside_factor && sim->world.linear.beside_factor->ok) << "solved beside the tip's block";
    const int before = *std::max_element(iterations.begin() + 5, iterations.begin() + 8);
    EXPECT_EQ(preconditioner[8], 3) << "the factor made again as the jaws close";
    EXPECT_LE(iterations[8], before + 1);
}

struct Excision {
    Vec3 pull;               ///< on the jaws at t = 3.5 s, halfway through the draw [N]
    Vec3 moved;              ///< mean displacement of the mesh nodes within 3 mm of the lesion [m]
    int pieces = 0;
    double smallest = 0.0;   ///< the smallest piece's rest volume [m^3]
};

/// The excision scene to t = 4.2 s (the grasper has drawn the lens 30 mm down), with or without its
/// two scalpels.
Excision excise(bool scalpel) {
    std::ifstream in(std::string(XCUT_SOURCE_DIR) + "/scenes/excision_2d.json");
    nlohmann::json j;
    in >> j;
    if (!scalpel) j["tools"].erase(0), j["tools"].erase(0);
    auto sim = make_simulation(load_scene_text(j.dump(), "excision", "."), /*with_output=*/false);
    World& w = sim->world;
    const int g = scalpel ? 2 : 0;
    Excision out;
    while (w.time < 4.2 - 1e-9) {
        step_simulation(*sim);
        if (std::abs(w.time - 3.5) < 1e-9) out.pull = w.grasps.force[g];
    }
    int n = 0;
    out.moved = Vec3::Zero();
    for (int i = 0; i < w.mesh_nodes; ++i)
        if ((w.nodes.rest[i] - Vec3(0.0303, 0.0207, 0)).norm() < 0.003)
            out.moved += w.nodes.position[i] - w.nodes.rest[i], ++n;
    out.moved /= n;
    count_pieces(w);
    out.pieces = w.pieces.count;
    out.smallest = *std::min_element(w.pieces.volume.begin(), w.pieces.volume.end());
    return out;
}

// The two arcs free the lens, and the grasper carries it 30 mm down at 20 mm/s. A free body carried
// at constant speed v needs only the step's Rayleigh mass damping, alpha rho V v (closed form: the
// relative damping of the grasp is zero, and the piece is not stretched); the same jaws on uncut skin
// stretch it and pull back more than a thousand times harder.
TEST(Grasp, TheExcisionsFreedPieceFollowsTheJawsWhereUncutSkinHolds) {
    const Excision cut = excise(true);
    ASSERT_EQ(cut.pieces, 2);
    const double alpha = 1.0, rho = 1000.0, v = 0.02;  // the scene's damping.mass [1/s], density, draw speed
    EXPECT_NEAR(cut.pull.y(), alpha * rho * cut.smallest * v, 0.01 * alpha * rho * cut.smallest * v)
        << "the lens is " << cut.smallest * 1e9 << " mm^3";
    EXPECT_NEAR(cut.moved.y(), -0.030, 0.002);
    EXPECT_NEAR(cut.moved.x(), 0.0, 0.002);
    if (testing::kInstrumented) return;  // the uncut run adds no cut code and 80 s under AddressSanitizer
    const Excision whole = excise(false);
    EXPECT_EQ(whole.pieces, 1);
    EXPECT_GT(whole.pull.norm(), 1000.0 * cut.pull.norm());
}

}  // namespace
}  // namespace xcut
