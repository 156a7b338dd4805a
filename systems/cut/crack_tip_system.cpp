#include "systems/cut/crack_tip_system.h"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <limits>
#include <stdexcept>

#include "engine/error.h"
#include "engine/parallel.h"
#include "systems/cut/blade_front.h"
#include "systems/kernels/block_sums.h"
#include "systems/kernels/branch_enrichment.h"
#include "systems/kernels/corotational_kernel.h"
#include "systems/kernels/front_enrichment.h"
#include "systems/xfem_queries.h"

namespace xcut {

using namespace tip_triangles;

namespace {

/// Pivots of the Jacobi-scaled H (unit diagonal) below this share of the largest are the
/// functions' exact dependencies, at rounding (1e-16 measured; the smallest kept one on the
/// accuracy suite's zones is 1e-4).
constexpr double kDroppedPivot = 1e-10;

/// Force element fe's Lamé parameters under plane stress [Pa] (2D only, as the ForceSystem's).
LameParameters plane_lame(const World& w, int fe) {
    const Material& m = w.materials.list[w.elements.material[fe]];
    return {m.lambda_plane_stress(), m.mu()};
}

/// Whether rest point T lies in the closure of triangle X (to 1e-9 of its barycentric coordinates).
bool holds(const std::array<Vec2, 3>& X, const Vec2& T) { return barycentric(X, T).minCoeff() >= -1e-9; }

Vec2 normal_of(const TipFrame& f) { return Vec2(-f.direction.y(), f.direction.x()); }

/// The lip of a node on the crack's line behind the tip (systems/xfem_queries.h).
int node_lip(const World& w, const TipFrame& f, int node) { return tip_node_lip(w, f.point, f.direction, node); }

struct ZonePart {
    int element;               ///< force element
    std::vector<Vec2> polygon; ///< its part of the mesh element (rest)
    int lip;                   ///< the crack's side it lies on (0: uncut)
};

/// The force elements of mesh element e: e itself, or the two sides of its cut.
std::vector<ZonePart> parts_of(const World& w, int e, const TipFrame& f) {
    const std::array<Vec2, 3> X = rest_triangle(w, e);
    const std::vector<int>& cut_of = w.cuts.cut_of_element;
    if (e >= static_cast<int>(cut_of.size()) || cut_of[e] < 0) return {{e, {X[0], X[1], X[2]}, 0}};
    const int c = cut_of[e];
    const Vec2 a = xy(w.cuts.points[c][0]), b = xy(w.cuts.points[c][1]);
    int orient = 1;  // the side of a -> b (+1: left) where H = +1, from a node the cut did not pass through
    for (int k = 0; k < 3; ++k) {
        const int node = w.elements.nodes[e][k], H = w.enriched.sign[node];
        const double level = cross2(Vec2(b - a), Vec2(X[k] - a));
        if (H != 0 && std::abs(level) > 1e-9 * (b - a).squaredNorm()) {
            orient = (level > 0.0) == (H > 0) ? 1 : -1;
            break;
        }
    }
    std::vector<ZonePart> parts;
    for (int s = 0; s < 2; ++s) {
        const int ve = w.cuts.virtual_element[c][s];
        ZonePart p{w.virtual_elements.element[ve], clip_triangle(X, a, b, orient * w.virtual_elements.side[ve]), 0};
        if (p.polygon.empty()) continue;
        Vec2 centre = Vec2::Zero();
        for (const Vec2& q : p.polygon) centre += q / static_cast<double>(p.polygon.size());
        p.lip = (centre - f.point).dot(normal_of(f)) >= 0.0 ? 1 : -1;
        parts.push_back(std::move(p));
    }
    return parts;
}

/// A zone part of mesh element e with its enriched corners `slots`: its integrals taken on the
/// threads (zone_integrals), then appended in order (add_zone_part).
struct ZoneJob {
    int e;
    ZonePart part;
    std::vector<int> slots;
};

/// Zone part `job`'s integrals (tip frame f, kTipRuleOrder^2 Duffy points per fan triangle).
BranchIntegrals zone_integrals(const World& w, const ZoneJob& job, const TipFrame& f) {
    std::array<int, 3> lip{};
    for (int k = 0; k < 3; ++k) lip[k] = node_lip(w, f, w.elements.nodes[job.e][k]);
    return branch_integrals(rest_triangle(w, job.e), job.slots, lip, f, job.part.lip,
                            tip_polygon_rule(job.part.polygon, f, kTipRuleOrder));
}

/// Appends zone part `job` with its integrals `bi` (2D: times the thickness).
void add_zone_part(World& w, const ZoneJob& job, const BranchIntegrals& bi, const std::vector<int>& pair_of) {
    const double t = w.materials.list[w.elements.material[job.e]].thickness;
    std::vector<Vec3> G;
    std::vector<Mat3> M;
    for (const Vec2& g : bi.G) G.emplace_back(t * g.x(), t * g.y(), 0.0);
    for (const Eigen::Matrix2d& m : bi.M) {
        M.push_back(Mat3::Zero());
        M.back().topLeftCorner<2, 2>() = t * m;
    }
    add_zone_element(w, job.e, job.part.element, job.part.lip, job.slots, pair_of, G, M);
}

/// Force element fe's Lamé parameters [Pa]: plane stress in 2D (as the ForceSystem's), 3D's own.
template <int D>
LameParameters tip_lame(const World& w, int fe) {
    if constexpr (D == 2) return plane_lame(w, fe);
    const Material& m = w.materials.list[w.elements.material[fe]];
    return {m.lambda(), m.mu()};
}

/// Keeps amplitudes b as this step's and these zones' (CrackTips::amplitude).
void keep_amplitudes(World& w, Eigen::VectorXd b) {
    CrackTips& ct = w.tips;
    ct.amplitude = std::move(b), ct.amplitude_step = w.step, ct.amplitude_version = ct.version;
}

/// The condensation of the amplitudes at the current rotations, and the maps it is made of; D
/// amplitudes a function (the mesh's dimension).
template <int D>
class Condensation {
public:
    using Mat = MatD<D>;
    using Vec = VecD<D>;
    /// H = Σ_z R K R^T over the zone, factored.
    void factor(const World& w) {
        const CrackTips& ct = w.tips;
        Eigen::MatrixXd H = Eigen::MatrixXd::Zero(D * ct.functions(), D * ct.functions());
        stiffness_blocks(w, [&](int fa, int fb, const Mat& K) { H.template block<D, D>(D * fa, D * fb) += K; });
        // Jacobi scaling first: far from the tip a shifted function is nearly linear over its
        // element, so its diagonal is orders of magnitude below the tip's (Béchet et al. 2005).
        scale_ = H.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
        ldlt_.compute(scale_.asDiagonal() * H * scale_.asDiagonal());
        // Pivots at rounding are the functions' own dependencies, not a defect: z̄ √r e^{3iθ/2} =
        // z √r e^{-iθ/2} makes four combinations of them, with amplitudes linear in the nodes'
        // positions, vanish identically where every node of every element is enriched (a zone that
        // is the whole body). Their field is zero, g has no part along them, so they are dropped
        // (a generalized inverse). A clearly negative pivot is a defect and stops the run.
        const Eigen::VectorXd d = ldlt_.vectorD();
        const double largest = d.cwiseAbs().maxCoeff();
        if (!(d.minCoeff() > -kDroppedPivot * largest))
            throw NumericalError(fmt::format(
                "crack-tip enrichment: the branch functions' stiffness (H, {} amplitudes) is not positive semi-definite "
                "(smallest pivot {:.3g} of the largest)", H.rows(), d.minCoeff() / largest));
        inverse_pivot_ = d.unaryExpr([&](double p) { return p > kDroppedPivot * largest ? 1.0 / p : 0.0; });
    }
    /// The sparse system the condensation is the Schur complement of (BesideBlock): H's blocks as
    /// factor() sums them, and C = ∂g/∂x, the coupling's map from the nodes' displacements (3 per
    /// DOF node) to the amplitudes' forces, at the current rotations.
    /// Each (function, function) and (function, node) block is summed over the zone before it is
    /// written (a front's zone repeats a pair in every element around both nodes).
    void block(const World& w, BesideBlock& out) const {
        const CrackTips& ct = w.tips;
        out.rows = D * ct.functions();
        BlockSums<D, D> H, C;  // C's columns: the node's axes
        stiffness_blocks(w, [&](int fa, int fb, const Mat& K) { H.at(fa, fb) += K; });
        for (int z = 0; z < ct.zone(); ++z) {
            const int fe = ct.element[z];
            for (int k = 0; k <= D; ++k)
                for (int d = 0; d < D; ++d) {  // node k moved along axis d
                    std::array<Vec3, 4> x;
                    x.fill(Vec3::Zero());
                    x[k][d] = 1.0;
                    const Mat RS = rotated_stress(w, fe, x, 0.0);
                    for (int a = ct.first[z]; a < ct.first[z + 1]; ++a)
                        C.at(ct.function[a], w.elements.nodes[fe][k]).col(d) += RS * ct.gradient[a].template head<D>();
                }
        }
        H.write(D, D, out.stiffness);
        C.write(D, 3, out.coupling);
    }
    /// g = Σ_z R σ(R^T F - shift I) G_a, F from the nodal vectors v (positions, or a direction with shift 0).
    Eigen::VectorXd coupling(const World& w, const Vec3* v, double shift) const {
        const CrackTips& ct = w.tips;
        Eigen::VectorXd g = Eigen::VectorXd::Zero(D * ct.functions());
        for (int z = 0; z < ct.zone(); ++z) {
            const int fe = ct.element[z];
            std::array<Vec3, 4> x{};
            for (int k = 0; k <= D; ++k) x[k] = v[w.elements.nodes[fe][k]];
            const Mat RS = rotated_stress(w, fe, x, shift);
            for (int a = ct.first[z]; a < ct.first[z + 1]; ++a)
                g.template segment<D>(D * ct.function[a]) += RS * ct.gradient[a].template head<D>();
        }
        return g;
    }
    /// out += scale G_x^T y: per zone element, scale R σ(Σ_a R^T y_a G_a^T) g_k on its nodes.
    void scatter(const World& w, const Eigen::VectorXd& y, double scale, Eigen::VectorXd& out) const {
        const CrackTips& ct = w.tips;
        for (int z = 0; z < ct.zone(); ++z) {
            const int fe = ct.element[z];
            const Mat R = w.elements.rotation[fe].template topLeftCorner<D, D>();
            Mat B = Mat::Zero();
            for (int a = ct.first[z]; a < ct.first[z + 1]; ++a)
                B += (R.transpose() * y.template segment<D>(D * ct.function[a])) * ct.gradient[a].template head<D>().transpose();
            std::array<Vec3, 4> f;
            scatter_stress<D>(R, linear_stress<D>(B, tip_lame<D>(w, fe)),
                              w.elements.dm_inv[fe].template topLeftCorner<D, D>(), scale, f);
            for (int k = 0; k <= D; ++k) out.segment<3>(3 * w.elements.nodes[fe][k]) += f[k];
        }
    }
    /// H^+ g through the scaled factor P^T L D L^T P, dropped pivots as 0.
    /// (One column: a VectorXd takes Eigen's triangular vector solves, not the blocked matrix
    /// ones, which pack L anew at every call.)
    Eigen::VectorXd solve(const Eigen::VectorXd& g) const {
        Eigen::VectorXd y = scale_.cwiseProduct(g);
        y = ldlt_.transpositionsP() * y;
        ldlt_.matrixL().solveInPlace(y);
        y.array() *= inverse_pivot_.array();
        ldlt_.matrixU().solveInPlace(y);
        y = ldlt_.transpositionsP().transpose() * y;
        return y.cwiseProduct(scale_);
    }

private:
    /// R σ(R^T F - shift I) of force element fe with nodal vectors x (its first D + 1), F = D(x) D_m^-1.
    static Mat rotated_stress(const World& w, int fe, const std::array<Vec3, 4>& x, double shift) {
        const Mat R = w.elements.rotation[fe].template topLeftCorner<D, D>();
        const Mat dm_inv = w.elements.dm_inv[fe].template topLeftCorner<D, D>();
        const Mat H = R.transpose() * edge_matrix<D>(x) * dm_inv - shift * Mat::Identity();
        return R * linear_stress<D>(H, tip_lame<D>(w, fe));
    }
    /// f(fa, fb, R K_ab R^T) for every pair of functions of every zone element (H's terms).
    template <class F>
    static void stiffness_blocks(const World& w, F&& f) {
        const CrackTips& ct = w.tips;
        for (int z = 0; z < ct.zone(); ++z) {
            const int fe = ct.element[z], n = ct.first[z + 1] - ct.first[z];
            const Mat R = w.elements.rotation[fe].template topLeftCorner<D, D>();
            const LameParameters lame = tip_lame<D>(w, fe);
            for (int a = 0; a < n; ++a)
                for (int b = 0; b < n; ++b) {
                    const Mat M = ct.moment[ct.moment_first[z] + a * n + b].template topLeftCorner<D, D>();
                    const Mat K = lame.lambda * M + lame.mu * M.transpose() + lame.mu * M.trace() * Mat::Identity();
                    f(ct.function[ct.first[z] + a], ct.function[ct.first[z] + b], R * K * R.transpose());
                }
        }
    }
    Eigen::LDLT<Eigen::MatrixXd> ldlt_;
    Eigen::VectorXd scale_;          ///< H's Jacobi scaling, 1 / sqrt(H_ii)
    Eigen::VectorXd inverse_pivot_;  ///< 1 / D of the scaled factor, 0 where dropped
};

/// Both dimensions' condensations; `with` hands the world's to f.
struct Condensations {
    Condensation<2> plane;
    Condensation<3> space;
    template <class F>
    auto with(const World& w, F&& f) {
        return w.elements.dim == 3 ? f(space) : f(plane);
    }
    template <class F>
    auto with(const World& w, F&& f) const {
        return w.elements.dim == 3 ? f(space) : f(plane);
    }
};

class CrackTipTerm final : public StepTerm {
public:
    const char* name() const override { return "crack tips"; }
    bool active(const World& w) const override { return w.tips.count() > 0; }
    void linearize(World& w) override {
        if (active(w)) c_.with(w, [&](auto& c) { c.factor(w); }), factored_ = {w.step, w.tips.version};
    }
    /// f = -G_x^T b, b = -H^-1 g: the force of the condensed energy ½ g·b (added to the elastic energy).
    void force(World& w, bool first) override {
        if (first) throw std::logic_error("the crack-tip term adds to the elastic term's force: it comes after it");
        ensure_factor(w);
        c_.with(w, [&](const auto& c) {
            const Eigen::VectorXd g = c.coupling(w, w.nodes.position.data(), 1.0), b = -c.solve(g);
            w.forces.elastic_energy += 0.5 * g.dot(b);
            c.scatter(w, b, -1.0, w.forces.force);
        });
    }
    /// The amplitudes at the step's end positions, through the factor of the step's last
    /// linearization (the rotations are still its own): one solve, no factor.
    void finish_step(World& w) override {
        if (factored_[1] != w.tips.version) linearize(w);
        c_.with(w, [&](const auto& c) { keep_amplitudes(w, -c.solve(c.coupling(w, w.nodes.position.data(), 1.0))); });
    }
    /// The condensed energy ½ g·b at the current positions, through the step's factor (as force()).
    double energy_now(World& w) override {
        if (!active(w)) return 0.0;
        ensure_factor(w);
        return c_.with(w, [&](const auto& c) {
            const Eigen::VectorXd g = c.coupling(w, w.nodes.position.data(), 1.0);
            return 0.5 * g.dot(-c.solve(g));
        });
    }
    /// out (+)= -G_x^T H^-1 G_x p.
    void product(World& w, const Eigen::VectorXd& p, Eigen::VectorXd& out, bool first) override {
        if (first) out.setZero(3 * w.nodes.count());
        ensure_factor(w);
        c_.with(w, [&](const auto& c) {
            c.scatter(w, c.solve(c.coupling(w, reinterpret_cast<const Vec3*>(p.data()), 0.0)), -1.0, out);
        });
    }
    void product_in_team(World& w, const Eigen::VectorXd& p, Eigen::VectorXd& out, bool first) override {
#pragma omp single
        product(w, p, out, first);  // a few dozen amplitudes: one thread, the others wait at the barrier
    }
    /// Its stiffness has the rank of the amplitudes and couples the whole zone: the assembled
    /// methods apply it beside A rather than fill A's pattern with dense blocks.
    bool beside_assembly() const override { return true; }
    /// No system of its own: the SolverSystem adds its force at the step's start.
    bool from_system() const override { return false; }
    /// The amplitudes' sparse system, for the assembled methods' factor (systems/solver/beside_factor.h).
    bool beside_block(World& w, BesideBlock& out) const override {
        if (!active(w)) return false;
        c_.with(w, [&](const auto& c) { c.block(w, out); });
        return true;
    }
    bool gives_beside_block() const override { return true; }
    uint64_t beside_version(const World& w) const override { return static_cast<uint64_t>(w.tips.version); }

private:
    /// A step whose rotations came from the ForceSystem (no linearize through the terms) factors
    /// H at its first use.
    void ensure_factor(World& w) {
        if (factored_ != std::array<int, 2>{w.step, w.tips.version}) linearize(w);
    }
    Condensations c_;
    std::array<int, 2> factored_{-1, -1};  ///< step and zone version of the factor
};

}  // namespace

void enrich_crack_tip(World& w, const Vec3& point, const Vec3& direction, const TipZone& zone) {
    if (w.elements.dim != 2) throw std::invalid_argument("crack-tip enrichment: 2D meshes only (a 3D mesh takes a front: enrich_crack_front)");
    if (w.snap.enabled) throw std::invalid_argument("crack-tip enrichment is XFEM's: not with the snapping cutter");
    if (!(xy(direction).norm() > 0.0)) throw std::invalid_argument("crack-tip enrichment: the crack's direction is zero");
    if (!(zone.radius >= 0.0)) throw std::invalid_argument("crack-tip enrichment: the zone's radius must be >= 0 m");
    const TipFrame f{xy(point), xy(direction).normalized()};
    std::vector<int> nodes;
    for (int e = 0; e < w.mesh_elements; ++e)
        if (holds(rest_triangle(w, e), f.point))
            for (int k = 0; k < 3; ++k) nodes.push_back(w.elements.nodes[e][k]);
    if (nodes.empty())
        throw std::invalid_argument(fmt::format("crack-tip enrichment: the tip ({:.6g}, {:.6g}) m lies outside the mesh",
                                                point.x(), point.y()));
    for (int i = 0; i < w.mesh_nodes; ++i)
        if ((xy(w.nodes.rest[i]) - f.point).norm() <= zone.radius) nodes.push_back(i);
    const std::vector<int> pair_of =
        add_tip(w, Vec3(f.point.x(), f.point.y(), 0.0), Vec3(f.direction.x(), f.direction.y(), 0.0), Vec3::UnitZ(), nodes);
    std::vector<ZoneJob> jobs;
    for (int e = 0; e < w.mesh_elements; ++e) {
        const std::vector<int> slots = enriched_slots(w, e, pair_of);
        if (slots.empty()) continue;
        for (ZonePart& part : parts_of(w, e, f)) jobs.push_back({e, std::move(part), slots});
    }
    std::vector<BranchIntegrals> integrals(jobs.size());
    parallel_for_uneven(static_cast<int>(jobs.size()), [&](int j) { integrals[j] = zone_integrals(w, jobs[j], f); });
    for (size_t j = 0; j < jobs.size(); ++j) add_zone_part(w, jobs[j], integrals[j], pair_of);
}

std::vector<int> add_tip(World& w, const Vec3& point, const Vec3& direction, const Vec3& tangent, std::vector<int> nodes) {
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    CrackTips& ct = w.tips;
    const int tip = ct.count();
    ++ct.version;
    ct.point.push_back(point), ct.direction.push_back(direction), ct.tangent.push_back(tangent);
    std::vector<int> pair_of(w.mesh_nodes, -1);
    for (int i : nodes) {
        pair_of[i] = static_cast<int>(ct.node.size());
        ct.node.push_back(i);
        ct.tip.push_back(tip);
    }
    if (ct.first.empty()) ct.first.push_back(0);
    return pair_of;
}

void add_zone_element(World& w, int e, int force_element, int lip, const std::vector<int>& slots,
                      const std::vector<int>& pair_of, const std::vector<Vec3>& G, const std::vector<Mat3>& M) {
    CrackTips& ct = w.tips;
    ct.element.push_back(force_element);
    ct.lip.push_back(static_cast<int8_t>(lip));
    ct.moment_first.push_back(static_cast<int>(ct.moment.size()));
    for (size_t s = 0; s < slots.size(); ++s)
        for (int l = 0; l < 4; ++l) {
            ct.function.push_back(4 * pair_of[w.elements.nodes[e][slots[s]]] + l);
            ct.gradient.push_back(G[4 * s + l]);
        }
    ct.moment.insert(ct.moment.end(), M.begin(), M.end());
    ct.first.push_back(static_cast<int>(ct.function.size()));
}

std::vector<int> enriched_slots(const World& w, int e, const std::vector<int>& pair_of) {
    std::vector<int> slots;
    for (int k = 0; k <= w.elements.dim; ++k)
        if (pair_of[w.elements.nodes[e][k]] >= 0) slots.push_back(k);
    return slots;
}

Eigen::VectorXd crack_tip_amplitudes(World& w) {
    if (w.tips.functions() == 0) return {};  // no tips: no amplitudes (H would be empty)
    Condensations both;
    return both.with(w, [&](auto& c) -> Eigen::VectorXd {
        c.factor(w);
        return -c.solve(c.coupling(w, w.nodes.position.data(), 1.0));
    });
}

const Eigen::VectorXd& step_tip_amplitudes(World& w) {
    CrackTips& ct = w.tips;
    const bool kept = ct.amplitude_step == w.step && ct.amplitude_version == ct.version &&
                      ct.amplitude.size() == w.elements.dim * ct.functions();
    if (!kept) keep_amplitudes(w, crack_tip_amplitudes(w));
    return ct.amplitude;
}

std::shared_ptr<StepTerm> crack_tip_step_term() { return std::make_shared<CrackTipTerm>(); }

namespace {

/// Tool t's blade point (the blade's tip, world frame) in current coordinates, mapped to rest
/// through the uncut mesh element holding it; false if none does.
bool blade_rest_point(const World& w, int t, Vec3& rest) {
    const ToolBodies& tb = w.tools;
    const Vec2 p = xy(tb.position[t] + tb.orientation[t] * tb.blade_tip[t]);
    const std::vector<int>& cut_of = w.cuts.cut_of_element;
    for (int e = 0; e < w.mesh_elements; ++e) {
        if (w.elements.weight[e] <= 0.0 || (e < static_cast<int>(cut_of.size()) && cut_of[e] >= 0)) continue;
        const auto& n = w.elements.nodes[e];
        // Outside the corners' box (widened by 1e-6 of it, far beyond the 1e-12 the coordinates
        // allow below): not held; the solve is left for the few elements around p.
        const Vec2 a = xy(w.nodes.position[n[0]]), b = xy(w.nodes.position[n[1]]), c = xy(w.nodes.position[n[2]]);
        const Vec2 lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c), pad = Vec2::Constant(1e-6 * (hi - lo).maxCoeff());
        if ((p.array() < (lo - pad).array()).any() || (p.array() > (hi + pad).array()).any()) continue;
        Eigen::Matrix2d D;
        D << b - a, c - a;
        const Vec2 l = D.partialPivLu().solve(p - a);
        if (std::min({1.0 - l.x() - l.y(), l.x(), l.y()}) < -1e-12) continue;
        rest = (1.0 - l.x() - l.y()) * w.nodes.rest[n[0]] + l.x() * w.nodes.rest[n[1]] + l.y() * w.nodes.rest[n[2]];
        return true;
    }
    return false;
}

/// Moves each phantom made since the zones were built to the old tips' field on its lip.
void transfer_to_phantoms(World& w) {
    const CrackTips& ct = w.tips;
    if (ct.count() == 0 || w.enriched.count() <= ct.phantoms_seen) return;
    const Eigen::VectorXd b = step_tip_amplitudes(w);
    for (int p = ct.phantoms_seen; p < w.enriched.count(); ++p) {
        const int node = w.enriched.node_of_phantom[p];
        Vec3 shift = Vec3::Zero();
        for (int pair = 0; pair < static_cast<int>(ct.node.size()); ++pair) {
            if (ct.node[pair] != node) continue;
            const int tip = ct.tip[pair];
            if (w.elements.dim == 3) {
                const FrontFrame f{ct.point[tip], ct.direction[tip], ct.tangent[tip]};
                const int lip = crack_node_lip(w, f.point, f.direction, f.normal(), node);
                const FrontValues F = front_functions(f, w.nodes.rest[node], lip);
                for (int l = 0; l < 4; ++l) shift -= 2.0 * F.f[l] * b.segment<3>(3 * (4 * pair + l));
                continue;
            }
            const TipFrame f{xy(ct.point[tip]), xy(ct.direction[tip])};
            const BranchValues F = branch_functions(f, xy(w.nodes.rest[node]), node_lip(w, f, node));
            for (int l = 0; l < 4; ++l) shift.head<2>() -= 2.0 * F.f[l] * b.segment<2>(2 * (4 * pair + l));
        }
        w.nodes.position[w.mesh_nodes + p] = w.nodes.position[node] + shift;
    }
}

/// CrackTips' per-tool state sized for `tools` tools (a tool added since starts unseen).
void size_blade_state(CrackTips& ct, int tools) {
    ct.blade_point.resize(tools, Vec3::Zero());
    ct.blade_seen.resize(tools, 0);
    ct.blade_world.resize(tools, Vec3::Zero());
    ct.blade_heading_from.resize(tools, Vec3::Zero());
    ct.blade_not_through.resize(tools, 0);
    ct.blade_last.resize(tools, Vec3::Zero());
    ct.blade_last_seen.resize(tools, 0);
}

/// The blades' tips (2D) or fronts (3D) built anew at `wanted` (rest point, direction, tangent),
/// keeping what follows the blades (CrackTips' per-tool state).
void build_blade_zones(World& w, const std::vector<std::array<Vec3, 3>>& wanted) {
    CrackTips& ct = w.tips;
    clear_tip_zones(ct);
    for (const auto& [T, dir, tangent] : wanted) {
        if (w.elements.dim == 3)
            enrich_crack_front(w, T, dir, tangent, TipZone{ct.follow_radius, kBladeFrontRuleOrder, kBladeFrontSlabOrder, kBladeFrontConicalOrder});
        else
            enrich_crack_tip(w, T, dir, TipZone{ct.follow_radius});
    }
    ct.cuts_seen = w.cuts.count();
    ct.phantoms_seen = w.enriched.count();
}

}  // namespace

void clear_tip_zones(CrackTips& ct) {
    CrackTips fresh;
    fresh.version = ct.version;
    fresh.follow_radius = ct.follow_radius;
    fresh.follow_stride = ct.follow_stride;
    fresh.blade_point = std::move(ct.blade_point);
    fresh.blade_seen = std::move(ct.blade_seen);
    fresh.blade_world = std::move(ct.blade_world);
    fresh.blade_heading_from = std::move(ct.blade_heading_from);
    fresh.blade_not_through = std::move(ct.blade_not_through);
    fresh.blade_last = std::move(ct.blade_last);
    fresh.blade_last_seen = std::move(ct.blade_last_seen);
    ct = std::move(fresh);
}

bool follow_blades(World& w) {
    CrackTips& ct = w.tips;
    const ToolBodies& tb = w.tools;
    size_blade_state(ct, tb.count());
    const bool space = w.elements.dim == 3;
    const double follow = kTipFollowFraction * w.cut_state.mean_edge, turn = kTipTurnFraction * w.cut_state.mean_edge;
    const double stride = std::max(follow, ct.follow_stride * w.cut_state.mean_edge);
    std::vector<std::array<Vec3, 3>> wanted;  // point, direction, tangent (rest)
    for (int t = 0; t < tb.count(); ++t) {
        // 2D: the blade's point, the front's tangent z; 3D: the edge through the tissue.
        Vec3 T, tangent = Vec3::UnitZ();
        const BladeFront held = !tb.has_blade[t] ? BladeFront::kNone
                                : space          ? blade_rest_front(w, t, T, tangent)
                                : blade_rest_point(w, t, T) ? BladeFront::kFront : BladeFront::kNone;
        ct.blade_not_through[t] += held == BladeFront::kNotThrough;
        // Whether the blade moved in the world since the step before (past the drift of `follow`).
        const Vec3 P = tb.position[t] + tb.orientation[t] * tb.blade_tip[t];
        const bool moving = ct.blade_last_seen[t] && (P - ct.blade_last[t]).norm() > follow;
        ct.blade_last[t] = P, ct.blade_last_seen[t] = tb.has_blade[t];
        if (held != BladeFront::kFront) {
            ct.blade_seen[t] = 0;
            continue;
        }
        // The crack's direction lies across the front (2D: in the plane).
        const auto across = [&](Vec3 v) {
            if (space) return Vec3(v - v.dot(tangent) * tangent);
            v.z() = 0.0;
            return v;
        };
        // The crack runs behind the tip along the blade's travel through the rest configuration
        // since the tip was put; one just entering takes its velocity's direction. A blade that
        // has not moved `follow` in the world since (the tissue drifting under a blade that
        // stands moves its rest point, and a direction taken from that drift is noise), or
        // backs into its own wound, keeps its tip: neither the zone nor the crack turns. A moving
        // blade keeps it until it has run a stride from it; one come to stand takes it along.
        Vec3 dir = Vec3::Zero();
        if (ct.blade_seen[t]) {
            int own = -1;
            for (int k = 0; k < ct.count(); ++k)
                if ((ct.point[k] - ct.blade_point[t]).norm() <= 1e-12) own = k;
            dir = across(T - ct.blade_point[t]);
            const double in_world = (P - ct.blade_world[t]).norm(), in_tissue = dir.norm();
            const bool stands = std::min(in_world, in_tissue) <= follow;
            const bool striding = own >= 0 && moving && std::max(in_world, in_tissue) < stride;
            // (3D: while the front it keeps still runs through uncut tissue; a split that caught up
            // with it hands the front to where the edge is now.)
            const bool keeps = stands || striding || (own >= 0 && dir.dot(ct.direction[own]) < 0.0);
            if (keeps && (own < 0 || !space || front_in_uncut_tissue(w, ct.point[own], ct.tangent[own]))) {
                if (own >= 0) wanted.push_back({ct.point[own], ct.direction[own], ct.tangent[own]});
                continue;
            }
            // The crack turns with the blade once it has run `turn` in its new direction: a
            // shorter stretch is the crack's own (a tip turned by a blade creeping sideways puts the
            // branch functions' discontinuity across uncut material, beside the crack).
            const Vec3 heading = across(T - ct.blade_heading_from[t]);
            if (own >= 0 && heading.norm() < turn) {
                dir = across(ct.direction[own]);
            } else {
                dir = heading.norm() > 0.0 ? heading : dir;
                ct.blade_heading_from[t] = T;
            }
        } else {
            for (int k = 0; k < ct.count(); ++k)
                if ((ct.point[k] - T).norm() <= 1e-12) dir = ct.direction[k];
            if (dir.norm() == 0.0) dir = tb.velocity[t];
            ct.blade_heading_from[t] = T;
        }
        dir = across(dir);
        ct.blade_point[t] = T, ct.blade_world[t] = P, ct.blade_seen[t] = 1;
        if (dir.norm() > 1e-12) wanted.push_back({T, dir.normalized(), tangent});  // else from its next move
    }
    bool same = static_cast<int>(wanted.size()) == ct.count() && w.cuts.count() == ct.cuts_seen;
    for (int k = 0; same && k < ct.count(); ++k)
        same = (wanted[k][0] - ct.point[k]).norm() <= 1e-12 && (wanted[k][1] - ct.direction[k]).norm() <= 1e-9 &&
               (wanted[k][2] - ct.tangent[k]).norm() <= 1e-9;
    if (same) return false;
    transfer_to_phantoms(w);
    build_blade_zones(w, wanted);
    return true;
}

SystemDesc crack_tip_system() {
    SystemDesc s{"CrackTipSystem", kNodes | kElements | kTools | kCutEvents, kNodes | kXfem,
                 [](World& w) { follow_blades(w); }, "crack tips (2D) and fronts (3D) at the blades"};
    return s.also_reads(kXfem);
}

}  // namespace xcut
