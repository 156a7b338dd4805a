// The assembled step matrix and the linear-solver stage (systems/solver/linear_assembly.h,
// systems/solver/linear_solver.h): A v equals the matrix-free product (the reference) to 1e-12 relative,
// uncut, cut and with contacts, in 3D and 2D; every method reaches the tolerance; the factor is
// renewed at a cut; a solve that cannot converge is retried, split into substeps, then stops the run.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "engine/error.h"
#include "systems/force_system.h"
#include "systems/kernels/solver/amg.h"
#include "systems/kernels/solver/conjugate_gradient.h"
#include "systems/kernels/solver/team_cg.h"
#include "systems/solver/linear_assembly.h"
#include "systems/solver/fill_estimate.h"
#include "systems/solver/linear_solver.h"
#include "systems/pipeline.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

using testing::deformed;

/// max |A p - (mass_scale M p + stiff_scale K p)| over the free entries, relative to the largest.
double assembled_error(World& w) {
    const double mass_scale = 1.02, stiff_scale = 3e-4;
    ensure_linear_pattern(w);
    assemble_step_matrix(w, xcut_step_terms(), mass_scale, stiff_scale);
    const int n3 = 3 * w.nodes.count();
    const Eigen::VectorXd mask = free_mask(w);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::VectorXd p(n3);
    for (int i = 0; i < n3; ++i) p[i] = u(rng) * mask[i];
    Eigen::VectorXd assembled, reference;
    linear_multiply(w.linear, p, assembled);
    xcut_step_terms().stiffness_product(w, p, reference);
    for (int i = 0; i < w.nodes.count(); ++i)
        reference.segment<3>(3 * i) = (mass_scale * w.nodes.mass[i] * p.segment<3>(3 * i) +
                                       stiff_scale * reference.segment<3>(3 * i)).cwiseProduct(mask.segment<3>(3 * i));
    return (assembled - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff();
}

TEST(LinearAssembly, MatchesTheMatrixFreeProductUncut) {
    for (bool plate : {false, true}) {
        World w = deformed(plate);
        EXPECT_LT(assembled_error(w), 1e-12) << (plate ? "2D" : "3D");
    }
}

// The projected guess's products, all columns in one pass over A: the same bits as one product a
// column, for a full pass of six columns, one of six and two, and a single column.
TEST(LinearAssembly, ColumnsProductEqualsOneProductAColumn) {
    World w = deformed(false);
    ensure_linear_pattern(w);
    assemble_step_matrix(w, xcut_step_terms(), 1.0, 1e-4);
    const int n3 = 3 * w.nodes.count();
    for (int columns : {6, 8, 1}) {
        SCOPED_TRACE(columns);
        std::srand(columns);
        const Eigen::MatrixXd V = Eigen::MatrixXd::Random(n3, columns);
        Eigen::MatrixXd AV;
        linear_multiply_columns(w.linear, V, AV);
        ASSERT_EQ(AV.rows(), n3);
        ASSERT_EQ(AV.cols(), columns);
        for (int j = 0; j < columns; ++j) {
            Eigen::VectorXd one;
            linear_multiply(w.linear, V.col(j), one);
            EXPECT_EQ(AV.col(j), one) << "column " << j;
        }
    }
}

TEST(LinearAssembly, MatchesTheMatrixFreeProductCut) {
    World w = deformed(false);
    ASSERT_GT(testing::cut_now(w, testing::square_on_plane(Vec3(0.0152, 0.01, 0.005), Vec3(1, 0.2, 0.1), 0.05)), 0);
    update_rotations(w);
    compute_forces(w);
    EXPECT_GT(w.nodes.count(), w.mesh_nodes) << "the cut added enriched DOFs";
    EXPECT_LT(assembled_error(w), 1e-12);
}

TEST(LinearAssembly, MatchesTheMatrixFreeProductWithContacts) {
    World w = deformed(false);
    testing::cut_now(w, testing::square_on_plane(Vec3(0.0152, 0.01, 0.005), Vec3(1, 0, 0), 0.05));
    update_rotations(w);
    compute_forces(w);
    Contacts& c = w.contacts;
    for (int e : {3, w.elements.count() - 1, w.elements.count() - 2}) {  // a mesh and two virtual elements
        c.tool.push_back(0), c.vertex.push_back(0), c.element.push_back(e);
        c.bary.emplace_back(0.1, 0.2, 0.3, 0.4);
        c.normal.push_back(Vec3(0.3, -0.4, 0.5).normalized());
        c.depth.push_back(1e-4), c.stiffness.push_back(500.0), c.force.push_back(Vec3::Zero());
    }
    EXPECT_LT(assembled_error(w), 1e-12);
}

/// The default scene on 4 mm elements, `steps` steps with `method`; returns the largest residual.
double run_skin(const std::string& method, int steps, int cap = 400) {
    Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json");
    scene.mesh.grid.cells = Eigen::Vector3i(15, 10, 1);
    scene.visual_subdivisions = -1;
    scene.solver.linear = method;
    scene.solver.cg_max_iterations = cap;
    auto sim = make_simulation(scene, false);
    double worst = 0.0;
    for (int i = 0; i < steps; ++i) {
        step_simulation(*sim);
        worst = std::max(worst, sim->world.metrics.current.cg_residual);
    }
    return worst;
}

TEST(LinearSolver, EveryMethodReachesTheTolerance) {
    for (const char* method : {"jacobi", "block_jacobi", "amg", "cholesky", "direct"}) {
        SCOPED_TRACE(method);
        EXPECT_LE(run_skin(method, 60), 1e-6);
    }
}

// Every method on every shipped scene, 3 steps each: every step reaches the scene's tolerance (in
// substeps if it must) and none stops the run.
TEST(LinearSolver, EveryMethodConvergesOnEveryShippedScene) {
    int scenes = 0;
    for (const auto& entry : std::filesystem::directory_iterator(std::string(XCUT_SOURCE_DIR) + "/scenes")) {
        if (entry.path().extension() != ".json") continue;
        ++scenes;
        for (const char* method : {"jacobi", "block_jacobi", "amg", "cholesky", "direct"}) {
            SCOPED_TRACE(entry.path().filename().string() + " " + method);
            Scene scene = load_scene(entry.path().string());
            scene.solver.linear = method;
            // No visual skin unless a tool holds it (a grasp needs one) or the collision one is made.
            if (scene.collision_subdivisions < 0 && !scene.grasps.any()) scene.visual_subdivisions = -1;
            auto sim = make_simulation(scene, false);
            for (int i = 0; i < 3; ++i) {
                ASSERT_NO_THROW(step_simulation(*sim));
                EXPECT_LE(sim->world.metrics.current.cg_residual, scene.solver.cg_tolerance);
            }
        }
    }
    EXPECT_GE(scenes, 7);
}

TEST(LinearSolver, AutoPicksCholeskyWhenSmallAndAmgBeyond) {
    World w = deformed(false);
    std::string why;
    EXPECT_EQ(resolve_linear_method(w, &why), "cholesky");
    EXPECT_NE(why.find("auto"), std::string::npos) << why;
    w.solver.linear = "block_jacobi";
    EXPECT_EQ(resolve_linear_method(w), "block_jacobi");
    World large = deformed(false, Eigen::Vector3i(24, 14, 12));  // 14,625 DOFs: past 10,000
    EXPECT_EQ(resolve_linear_method(large, &why), "amg");
    EXPECT_NE(why.find("DOFs"), std::string::npos) << why;
    // Nearly incompressible tissue keeps the factor to 40k DOFs, as quadratic elements do: the
    // smoothed aggregation needs 38 CG iterations a step at nu 0.49 on the 1 mm skin (22.5k DOFs),
    // where cholesky runs 1.3x faster (systems/solver/linear_solver.cpp).
    for (Material& m : large.materials.list) m.poisson = 0.49;
    EXPECT_EQ(resolve_linear_method(large, &why), "cholesky");
    EXPECT_NE(why.find("nu >= 0.48"), std::string::npos) << why;
    for (Material& m : large.materials.list) m.poisson = 0.45;
    EXPECT_EQ(resolve_linear_method(large, &why), "amg") << "at 0.45 the multigrid is still the faster";
}

// Past 10k DOFs the factor's own fill decides (systems/solver/fill_estimate.h): the default skin at
// 1 mm elements (22.5k DOFs, two elements through its 4 mm) keeps cholesky, 2x amg's speed there
// (systems/solver/linear_solver.cpp, kAutoCholeskyNonzeros); its estimate is CHOLMOD's own L within
// 10 %; at 0.7 mm (60k DOFs) and in a block of 17k DOFs the fill is past 5 M and amg is taken.
TEST(LinearSolver, AutoKeepsCholeskyWhereTheFactorsFillIsThatOfAThinLayer) {
    const std::string skin = std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json";
    auto sim = make_simulation(load_scene(skin, {"mesh.element_size=0.001"}), false);
    std::string why;
    ASSERT_GT(3 * sim->world.nodes.count(), 20000);
    EXPECT_EQ(resolve_linear_method(sim->world, &why), "cholesky") << why;
    EXPECT_NE(why.find("estimated"), std::string::npos) << why;
    ASSERT_EQ(sim->world.linear.method, "cholesky");
    const double estimate = estimated_factor_nonzeros(sim->world), actual = sim->world.linear.factor_nonzeros;
    EXPECT_NEAR(estimate / actual, 1.0, 0.1) << estimate << " against CHOLMOD's " << actual;
    auto thinner = make_simulation(load_scene(skin, {"mesh.element_size=0.0007"}), false);
    EXPECT_EQ(thinner->world.linear.method, "amg");
    World block = deformed(false, Eigen::Vector3i(22, 22, 11));
    ASSERT_LT(3 * block.nodes.count(), 20000);
    EXPECT_EQ(resolve_linear_method(block, &why), "amg") << why;
    EXPECT_GT(estimated_factor_nonzeros(block), 5e6);
}

// A cut changes the pattern: the factor is analysed and computed again; the multigrid hierarchy is
// carried over to the new DOFs without a new setup (amg_extend). CG still converges right after.
TEST(LinearSolver, PreconditionerFollowsACut) {
    for (const char* method : {"cholesky", "amg"}) {
        SCOPED_TRACE(method);
        Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json");
        scene.visual_subdivisions = -1;
        scene.solver.linear = method;
        auto sim = make_simulation(scene, false);
        const World& w = sim->world;
        for (int i = 0; i < 15; ++i) step_simulation(*sim);  // before the blade moves (t < 0.2 s)
        ASSERT_EQ(w.cuts.count(), 0);
        const int symbolic = w.linear.symbolic_factorizations, built = w.linear.factorizations;
        while (w.cuts.count() == 0 && w.time < 1.0) step_simulation(*sim);
        ASSERT_GT(w.cuts.count(), 0);
        if (w.linear.amg) {
            EXPECT_EQ(w.linear.factorizations, built) << "no new setup at the cut";
            EXPECT_GT(w.linear.extensions, 0);
            EXPECT_EQ(w.linear.amg->topology, w.linear.topology);
            EXPECT_EQ(w.linear.amg->levels[0].P.rows(), 3 * w.nodes.count());
            EXPECT_LE(w.metrics.current.cg_iterations, 30);
        } else {
            EXPECT_GT(w.linear.symbolic_factorizations, symbolic);
            EXPECT_LE(w.metrics.current.cg_iterations, 10);
        }
        EXPECT_LE(w.metrics.current.cg_residual, 1e-6);
    }
}

// No silent failure: a cap of one CG iteration cannot reach 1e-6; the step is retried in 2, 4, ...
// 16 substeps and then the run stops with the step, the residual and what to change.
TEST(LinearSolver, UnreachableToleranceStopsTheRunWithAMessage) {
    try {
        run_skin("jacobi", 3, 1);
        ADD_FAILURE() << "a capped solve passed";
    } catch (const NumericalError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("step 1 "), std::string::npos) << msg;
        EXPECT_NE(msg.find("relative residual"), std::string::npos) << msg;
        EXPECT_NE(msg.find("16 substeps"), std::string::npos) << msg;
        EXPECT_NE(msg.find("solver.cg_max_iterations"), std::string::npos) << msg;
    }
}

// A cap the full step cannot meet but half steps can: the step is split, the metrics say so, and
// the result is a converged step.
TEST(LinearSolver, SubstepsRecoverAStepAboveTheCap) {
    Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json");
    scene.mesh.grid.cells = Eigen::Vector3i(15, 10, 1);
    scene.visual_subdivisions = -1;
    scene.solver.linear = "jacobi";
    scene.solver.cg_max_iterations = 150;
    scene.solver.dt = 0.04;
    auto sim = make_simulation(scene, false);
    step_simulation(*sim);
    const StepMetrics& m = sim->world.metrics.current;
    EXPECT_EQ(m.solve_flag, 2);
    EXPECT_GT(m.substeps, 1);
    EXPECT_LE(m.cg_residual, 1e-6);
    EXPECT_NEAR(sim->world.time, 0.04, 1e-15);
    EXPECT_EQ(sim->world.metrics.substepped_steps, 1);
}

// The watchdog: an absurd Young's modulus gives no finite answer; the run stops, never running on.
TEST(Watchdog, NonFiniteStateStopsTheRun) {
    Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json");
    scene.mesh.grid.cells = Eigen::Vector3i(15, 10, 1);
    scene.visual_subdivisions = -1;
    scene.material.young = 1e300;
    auto sim = make_simulation(scene, false);
    EXPECT_THROW(
        for (int i = 0; i < 5; ++i) step_simulation(*sim), NumericalError);
}

/// A deformed block's step matrix assembled, its free mask, a right-hand side and the inverses of
/// its diagonal blocks: the systems the team CG tests solve.
struct BlockSystem {
    World w;
    Eigen::VectorXd mask, b;
    std::vector<double> inverse;
    explicit BlockSystem(const Eigen::Vector3i& cells) : w(deformed(false, cells)) {
        ensure_linear_pattern(w);
        assemble_step_matrix(w, xcut_step_terms(), 1.0, 1e-4);
        mask = free_mask(w);
        b = (w.forces.force + Eigen::VectorXd::Constant(3 * w.nodes.count(), 1e-3)).cwiseProduct(mask);
        block_diagonal_inverse(w.linear, inverse);
    }
    /// z = D^-1 r on the node rows [lo, hi) (block Jacobi).
    void jacobi_rows(int lo, int hi, const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
        for (int i = lo; i < hi; ++i)
            z.segment<3>(3 * i) = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(inverse.data() + 9 * i) *
                                  r.segment<3>(3 * i);
    }
    /// out = A v, its rows shared by the calling OpenMP team.
    void product_in_team(const Eigen::VectorXd& v, Eigen::VectorXd& out) const {
#pragma omp for schedule(static)
        for (int i = 0; i < w.linear.rows(); ++i) linear_multiply_rows(w.linear, i, i + 1, v, out);
    }
};

// The team CG (one OpenMP team per solve, Chronopoulos & Gear's single-reduction iteration) on a
// block large enough for a 2-thread team: 1 and 2 threads give the same bits, it reaches the
// tolerance in the true residual, and it agrees with textbook PCG (Saad alg. 9.1) to the tolerance.
TEST(TeamCg, MatchesPcgAndIsThreadIndependent) {
    BlockSystem sys(Eigen::Vector3i(20, 12, 10));
    World& w = sys.w;
    const Eigen::VectorXd &mask = sys.mask, &b = sys.b;
    const int n3 = 3 * w.nodes.count();
    ASSERT_GE(n3, kParallelMin) << "large enough for a team of two";
    const auto product_in_team = [&](const Eigen::VectorXd& v, Eigen::VectorXd& out) { sys.product_in_team(v, out); };
    const auto jacobi_rows = [&](int lo, int hi, const Eigen::VectorXd& r, Eigen::VectorXd& z) {
        sys.jacobi_rows(lo, hi, r, z);
    };
    const auto none = [](const Eigen::VectorXd&, Eigen::VectorXd&) {};
    const double tol = 1e-10;
    auto solve = [&](int threads, CgResult& result) {
        set_thread_count(threads);
        Eigen::VectorXd x = Eigen::VectorXd::Zero(n3);
        result = team_cg(w.linear.rows(), product_in_team, Preconditioning::kRows, jacobi_rows, none, b, mask, tol, 2000, x);
        return x;
    };
    CgResult one, two;
    const Eigen::VectorXd x1 = solve(1, one), x2 = solve(2, two);
    set_thread_count(2);
    EXPECT_EQ(one.iterations, two.iterations);
    EXPECT_TRUE(x1 == x2) << "bit-identical for 1 and 2 threads";
    ASSERT_LE(two.relative_residual, tol);
    Eigen::VectorXd ax;
    linear_multiply(w.linear, x2, ax);
    EXPECT_LE((b - ax).cwiseProduct(mask).norm() / b.norm(), 10 * tol) << "the recurrence residual is the true one";
    // Textbook PCG with the same preconditioner.
    Eigen::VectorXd xp = Eigen::VectorXd::Zero(n3);
    const auto product = [&](const Eigen::VectorXd& v, Eigen::VectorXd& out) { linear_multiply(w.linear, v, out); };
    const auto jacobi = [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
        z.resize(r.size());
        jacobi_rows(0, w.linear.rows(), r, z);
    };
    const CgResult pcg = preconditioned_cg(product, jacobi, b, mask, tol, 2000, xp);
    EXPECT_NEAR(two.iterations, pcg.iterations, 2) << "the same iteration in exact arithmetic";
    EXPECT_LE((x2 - xp).norm(), 1e-8 * xp.norm());
}

// A solve of k iterations applies a whole-vector preconditioner (a factor's solves) k times and the
// product k + 1 times (the start's A x among them): the test for convergence comes before the
// application whose result it would not use.
TEST(TeamCg, AppliesThePreconditionerOnceAnIterationAndNotAfterTheLast) {
    BlockSystem sys(Eigen::Vector3i(6, 4, 4));
    World& w = sys.w;
    const Eigen::VectorXd &mask = sys.mask, &b = sys.b;
    const int n3 = 3 * w.nodes.count();
    int products = 0, applications = 0;
    const auto product_in_team = [&](const Eigen::VectorXd& v, Eigen::VectorXd& out) {
#pragma omp single
        ++products;
        sys.product_in_team(v, out);
    };
    const auto no_rows = [](int, int, const Eigen::VectorXd&, Eigen::VectorXd&) {};
    const auto jacobi = [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
        ++applications;
        z.resize(r.size());
        sys.jacobi_rows(0, w.linear.rows(), r, z);
    };
    Eigen::VectorXd x = Eigen::VectorXd::Zero(n3);
    const CgResult result = team_cg(w.linear.rows(), product_in_team, Preconditioning::kSingle, no_rows, jacobi, b, mask,
                                    1e-8, 2000, x);
    ASSERT_GT(result.iterations, 3);
    ASSERT_LE(result.relative_residual, 1e-8);
    EXPECT_EQ(applications, result.iterations);
    EXPECT_EQ(products, result.iterations + 1);
    // Converged at the start: no application, no product beyond A x.
    products = applications = 0;
    const CgResult again = team_cg(w.linear.rows(), product_in_team, Preconditioning::kSingle, no_rows, jacobi, b, mask,
                                   1e-8, 2000, x);
    EXPECT_EQ(again.iterations, 0);
    EXPECT_EQ(applications, 0);
    EXPECT_EQ(products, 1);
}

// The matrix-free product as a team runs it (the jacobi method's CG) gives the same bits as the
// one-region-per-loop product, on 2 threads.
TEST(TeamCg, MatrixFreeProductInTeamMatchesTheProduct) {
    World w = deformed(false, Eigen::Vector3i(12, 8, 6));
    const int n3 = 3 * w.nodes.count();
    Eigen::VectorXd p = Eigen::VectorXd::LinSpaced(n3, -1.0, 1.0), reference, in_team;
    xcut_step_terms().stiffness_product(w, p, reference);
    const StepOperator op = xcut_step_terms();
    op.prepare_product(w);
    in_team.resize(n3);
#pragma omp parallel num_threads(2)
    op.stiffness_product_in_team(w, p, in_team);
    EXPECT_TRUE(in_team == reference);
}

// The kept preconditioner is built at load, and the first step takes it into use instead of
// building another; the methods that keep none build nothing.
TEST(LinearSolver, KeptPreconditionerIsBuiltAtLoad) {
    for (const char* method : {"cholesky", "amg", "block_jacobi", "jacobi"}) {
        SCOPED_TRACE(method);
        Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json");
        scene.visual_subdivisions = scene.collision_subdivisions = -1;
        scene.solver.linear = method;
        auto sim = make_simulation(scene, false);
        const LinearSystem& A = sim->world.linear;
        const bool keeps = std::string(method) == "cholesky" || std::string(method) == "amg";
        EXPECT_EQ(A.factorizations, keeps ? 1 : 0);
        EXPECT_EQ(A.load_setup_ms > 0.0, keeps);
        step_simulation(*sim);
        EXPECT_EQ(A.factorizations, keeps ? 1 : 0) << "the first step used the one built at load";
        EXPECT_LE(sim->world.metrics.current.cg_residual, scene.solver.cg_tolerance);
    }
}

// With a fixed thread count the cholesky and amg methods replay bit for bit; 1 and 2 threads agree
// to the CG tolerance (here bit for bit too: the factor's solve is serial, every row of the
// multigrid cycle is written by one thread, and every sum has a fixed order). The default scene's
// 3,906 DOFs give the multigrid a coarse level.
TEST(LinearSolver, KeptPreconditionersAreDeterministic) {
    for (const char* method : {"cholesky", "amg"}) {
        SCOPED_TRACE(method);
        auto run = [&](int threads) {
            set_thread_count(threads);
            Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json");
            scene.visual_subdivisions = -1;
            scene.solver.linear = method;
            auto sim = make_simulation(scene, false);
            for (int i = 0; i < 40; ++i) step_simulation(*sim);
            return sim->world.nodes.position;
        };
        const auto a = run(2), b = run(2), c = run(1);
        set_thread_count(2);
        EXPECT_EQ(a, b);
        ASSERT_EQ(a.size(), c.size());
        double worst = 0.0;
        for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, (a[i] - c[i]).norm());
        EXPECT_LE(worst, 1e-6 * 0.001) << "1 vs 2 threads: within the CG tolerance of a 1 mm displacement";
    }
}

}  // namespace
}  // namespace xcut
