#pragma once
// Crack-tip enrichment: the branch functions of systems/kernels/branch_enrichment.h on the nodes
// around a crack's tip (2D) or along a straight crack front (3D, systems/kernels/front_enrichment.h),
// as a term of the implicit step (systems/step_term.h).
//
// The field of a zone element (one of the elements its enriched nodes belong to, or one side of such
// an element that is cut) is its corotational linear field plus Σ_a N_k ψ_l b_a, with b_a the
// function's amplitude in the world frame. In the element's frame (R from the polar decomposition of
// its linear part, as for every element: the tip's √r field is small-strain in that frame) the
// strain energy is the linear element's plus
//   (R^T b_a) · σ(R^T F - I) G_a  +  ½ (R^T b_a) · K_ab (R^T b_b),
//   K_ab = λ M_ab + μ M_ab^T + μ tr(M_ab) I,
// with G and M the integrals over the element's part (components/crack_tips.h). The amplitudes
// carry no mass: they are condensed out at each linearization (b = -H^-1 g, H = Σ R K R^T, g = Σ R σ G),
// which leaves on the nodes the Schur complement K_uu - G_x^T H^-1 G_x (symmetric positive definite
// where the whole enriched stiffness is) and the force -∂/∂x of ½ g·b. Massless enrichment of a
// quasi-static near-tip field: its own eigenfrequencies are the mesh's highest, which backward Euler
// damps anyway.
#include <memory>

#include "engine/scheduler.h"
#include "engine/world.h"
#include "systems/kernels/front_enrichment.h"
#include "systems/step_term.h"

namespace xcut {

/// How far a tip's enrichment reaches: the nodes of the elements that hold the tip, and the mesh
/// nodes within `radius` of it, each with its own amplitudes (Moës, Dolbow & Belytschko 1999; a
/// fixed radius: Béchet, Minnebo, Moës & Burgardt, IJNME 64, 2005). docs/xfem.md weighs the radius.
struct TipZone {
    double radius = 0.0;  ///< [m] 0: the tip's elements only (topological)
    /// A 3D front's rule (enrich_crack_front): Gauss points per direction of each section's Duffy
    /// triangles, and per slab along the front (graded toward where the front enters or leaves a
    /// part). Problem 5's errors move by at most 0.01 points of percent from 6 x 6 and 6.
    int front_rule_order = 4, front_slab_order = 5;
    /// Points per direction of the conical rule of its parts away from the front (front_tet_rule).
    int front_conical_order = kConicalOrder;
};

/// The rule of a front a blade carries (follow_blades, 3D), whose zone is built again at each
/// stride the blade moves: 2 x 2 per Duffy triangle (3 x 3 where the section's fan is signed:
/// front_tet_rule), 3 per slab and 3³ conical points (4 x 4, 5 and 4³ in TipZone), 0.28 of the
/// points on the default skin. Problem 5's errors move by at most 0.17, 0.10, 0.08, 0.03, 0.013
/// points of percent at 8, 12, 16, 24, 32 cells with a zone of two cells (docs/xfem.md, Blades that
/// carry fronts), 0.10, 0.05, 0.035, 0.011, 0.003 on the front's elements, where the accuracy suite
/// takes it since 2026-12-07 (docs/xfem.md, Crack fronts in 3D).
constexpr int kBladeFrontRuleOrder = 2, kBladeFrontSlabOrder = 3, kBladeFrontConicalOrder = 3;

/// Gauss points per direction of a zone's Duffy rule (tip_polygon_rule): 5 x 5 per fan triangle of
/// at most 45 degrees. ∫ 1/r over a triangle with the tip at a corner comes out within 2e-8 of its
/// closed form (8 x 8: 5e-12); problem 6's CMOD moves by at most 0.003 points of percent from 8 x 8
/// at 10-160 cells, and a zone built while a blade carries its tip takes 0.39 of the points
/// (docs/xfem.md, Quadrature).
constexpr int kTipRuleOrder = 5;

/// Enriches the crack tip at rest point `point`, the crack behind it along -`direction` (rest
/// configuration; 2D meshes), over `zone`. The zone's integrals are taken at once (kTipRuleOrder^2
/// Duffy points per fan triangle). Throws std::invalid_argument for a 3D mesh, the snapping cutter, a
/// tip outside the mesh, a zero direction or a negative radius.
void enrich_crack_tip(World& world, const Vec3& point, const Vec3& direction, const TipZone& zone = {});

/// Enriches a straight crack front in a 3D mesh of linear tetrahedra (systems/kernels/front_enrichment.h):
/// the line through rest point `point` along `tangent`, the crack behind it along -`direction`
/// (made normal to the tangent), over `zone` (the elements the line runs through, or touches along a
/// face or an edge, and the mesh nodes within `zone.radius` of the line). Each zone element's
/// integrals are taken at once, in slabs along the front. Throws std::invalid_argument for a 2D mesh,
/// quadratic elements, the snapping cutter, an element cut more than once in the zone, a front that
/// misses the mesh, a zero or parallel direction and tangent, or a negative radius.
void enrich_crack_front(World& world, const Vec3& point, const Vec3& direction, const Vec3& tangent,
                        const TipZone& zone = {});
/// Zone building, 2D and 3D: registers a tip (rest point, unit direction and tangent) and its
/// enriched mesh nodes (sorted, made unique) in world.tips, and returns each mesh node's (tip, node)
/// pair, -1 where it is not enriched.
std::vector<int> add_tip(World& world, const Vec3& point, const Vec3& direction, const Vec3& tangent, std::vector<int> nodes);
/// Appends zone element `force_element` (mesh element e, or a side of its cut, on the crack's side
/// `lip`, 0: each point's own) with the functions of its enriched corners `slots`, their gradient
/// integrals G and moments M (CrackTips::gradient, CrackTips::moment, in the functions' order).
void add_zone_element(World& world, int e, int force_element, int lip, const std::vector<int>& slots,
                      const std::vector<int>& pair_of, const std::vector<Vec3>& G, const std::vector<Mat3>& M);
/// The local corners of mesh element e whose nodes have a pair in `pair_of` (add_tip).
std::vector<int> enriched_slots(const World& world, int e, const std::vector<int>& pair_of);

/// The displacement the tips' (2D) or fronts' (3D) functions add at rest point X of force element
/// fe (its barycentric coordinates `bary`; 2D: the first three), amplitudes b (crack_tip_amplitudes):
/// Σ_k N_k Σ_l (F_l(X) - F_l(X_k)) b_kl, on the element's lip (or X's side of the crack) [m]: what a
/// probe adds to its element's linear interpolation.
Vec3 crack_enrichment_at(const World& world, const Eigen::VectorXd& amplitudes, int fe, const Vec3& X,
                         const Eigen::Vector4d& bary);

/// Blades carry tips (2D, scene cutter.tip, CrackTips::follow_radius >= 0): a bladed tool whose
/// blade point lies in an uncut mesh element (the one the semi-progressive front has not split yet)
/// gets a tip at that point, the crack behind it along the blade's travel. In 3D a blade whose edge
/// crosses the tissue whole carries a straight front along it (systems/cut/blade_front.h), through
/// the rest point of the middle of its stretch in uncut tissue, enriched by enrich_crack_front with
/// the blade's rule (kBladeFrontRuleOrder); an edge that ends inside the tissue carries none
/// (CrackTips::blade_not_through counts those steps). A moving blade moves its tip on in strides
/// (CrackTips::follow_stride of the mean edge, in the world or through the tissue), and to where
/// it stands once it stops. When a tip moved or the topology changed, the zones are built again; before that, each phantom the cuts made since the
/// last build takes the position the old tips' field gives its lip at its node, x_j - 2 Σ_l F_l b_jl
/// (the other lip's branch functions are the own lip's negated), so the opening the tip carried in
/// an element survives its split (state transfer). Returns whether it built the zones again.
bool follow_blades(World& world);
/// Drops every tip and its zone, keeping what is not a zone's: the count of zones built, the
/// blades' follow settings and their per-tool state (follow_blades' and the scripted fronts'
/// rebuilds start from it).
void clear_tip_zones(CrackTips& tips);
/// The CrackTipSystem: follow_blades each step, after the EnrichmentSystem.
SystemDesc crack_tip_system();

/// The amplitudes b of every function (2 per function, world frame [sqrt(m)]) at the current
/// positions and rotations, as the step's term condenses them: for output and tests (empty
/// without tips).
Eigen::VectorXd crack_tip_amplitudes(World& world);
/// The same at the step's end without a factor of its own: the ones the step's term left
/// (CrackTips::amplitude: the SolverSystem's step, a static solve's last iterate) while they are
/// this step's and these zones', else crack_tip_amplitudes (kept there for the step's other readers).
const Eigen::VectorXd& step_tip_amplitudes(World& world);

/// What the volume output shows inside each tip's element (CrackTips::shown_*): the mesh element
/// the tip lies in (uncut, the tip strictly inside) as four triangles fanned from the tip, with the
/// point where the crack behind the tip enters the element written once per lip, each placed by the
/// enriched field x(X) = Σ_k N_k x_k + Σ_k N_k Σ_l (F_l(X) - F_l(X_k)) b_kl on its lip: the opening
/// the branch functions carry up to the tip, which the element's nodes alone do not show. A tip on
/// an edge or at a node, or in a cut element, is shown whole.
void show_crack_tips(World& world);
/// The CrackTipDisplaySystem, before the MappingSystem: step_tip_amplitudes and show_crack_tips at
/// every step when the world has a visual surface (systems/surface/surface_tips.h places it by the
/// enriched field, and opens it inside a 2D tip's elements), else at the steps the volume output
/// writes. The amplitudes are the step's own (CrackTips::amplitude), which the surface reads.
SystemDesc crack_tip_display_system();

/// The term: active when the world has tips; the assembled methods apply it beside A.
std::shared_ptr<StepTerm> crack_tip_step_term();

}  // namespace xcut
