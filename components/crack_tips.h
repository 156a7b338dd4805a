#pragma once
// Crack tips (2D) and straight crack fronts (3D) enriched with branch functions
// (systems/cut/crack_tip_system.h, systems/kernels/front_enrichment.h,
// systems/kernels/branch_enrichment.h). Each enriched node carries, per tip, four branch functions
// times an amplitude of the mesh's dimension; the amplitudes are condensed out of the step (they
// have no mass), so this holds only what the condensation needs: which force elements the enrichment reaches and the
// integrals of its shape functions' gradients over each, at rest (SI units).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "components/nodes.h"

namespace xcut {

/// A blade's tip follows it once the blade has moved this fraction of the mesh's mean edge length,
/// in the world and in the rest configuration, since the tip was put (systems/cut/crack_tip_system.cpp,
/// follow_blades). Until then the tip stands: the tissue drifting under a blade held still moves
/// the blade's rest point (by about 1e-6 m a step on the face skin, 2 mm cells), and a direction
/// taken from that drift is noise (it turned the crack by up to 180 degrees a step) [-].
inline constexpr double kTipFollowFraction = 0.01;

/// A moving blade moves its tip (2D) or front (3D) on in strides of this fraction of the mean edge
/// length (CrackTips::follow_stride, scene cutter.tip.stride; follow_blades): each stride builds the
/// zone again (its integrals, the amplitudes' block beside the factor), so the crack ends within a
/// stride behind the blade while it moves, and where the blade is once it stands. Measured on the
/// default skin with a front (docs/xfem.md, Crack fronts in 3D): the step's median 7.4-9.5 ms with
/// a stride of 0 (every step the blade moves) against 4.6-6.0 ms at a quarter edge [-].
inline constexpr double kTipStrideFraction = 0.25;

/// A tip's crack turns with its blade once the blade has run this fraction of the mean edge length
/// in the new direction (follow_blades); a shorter stretch keeps the crack's direction [-].
inline constexpr double kTipTurnFraction = 0.25;

struct CrackTips {
    // ---- per tip (rest configuration)
    std::vector<Vec3> point;       ///< where the crack ends [m]
    std::vector<Vec3> direction;   ///< the crack's unit direction at the tip, pointing ahead of it [-]
    std::vector<Vec3> tangent;     ///< the front's unit tangent (3D: a straight front through point; 2D: z) [-]
    // ---- per enriched (tip, node) pair: functions 4 pair + l, 2 amplitudes each
    std::vector<int> node;         ///< the mesh node
    std::vector<int> tip;          ///< the tip
    // ---- per zone element: a force element whose mesh element holds an enriched node
    std::vector<int> element;      ///< force element (a mesh element, or a virtual element of a cut one)
    std::vector<int> first;        ///< its functions: [first[z], first[z + 1]) in `function`; size zone + 1
    std::vector<int> moment_first; ///< its n_z^2 gradient moments start here in `moment`
    std::vector<int8_t> lip;       ///< the crack's side its part lies on (+1 the normal's, -1; 0 uncut: atan2)
    // ---- per zone element and function a (its own order)
    std::vector<int> function;     ///< global function: 4 pair + l
    std::vector<Vec3> gradient;    ///< G_a = ∫ ∇φ_a over the element's part [m^2.5] (2D: t ∫, z = 0)
    std::vector<Mat3> moment;      ///< M_ab = ∫ ∇φ_a ∇φ_b^T, row-major by (a, b) [m^2] (2D: t ∫, z row, column 0)

    // ---- blades that carry tips (scene cutter.tip; systems/cut/crack_tip_system.h, follow_blades)
    double follow_radius = -1.0;     ///< [m] each blade's tip enriched within this radius; < 0: off
    double follow_stride = kTipStrideFraction;  ///< [-] of the mean edge: a moving blade's tip follows in such strides
    std::vector<Vec3> blade_point;   ///< per tool: the rest point its tip was put at (or its blade entered at) [m]
    std::vector<Vec3> blade_world;   ///< per tool: its blade point in the world then [m]
    std::vector<Vec3> blade_heading_from;  ///< per tool: the rest point its crack's direction was last taken from [m]
    std::vector<uint8_t> blade_seen; ///< per tool: blade_point holds one
    std::vector<Vec3> blade_last;    ///< per tool: its blade point in the world at the step before [m]
    std::vector<uint8_t> blade_last_seen;  ///< per tool: blade_last holds one
    /// per tool (3D): steps its edge lay in the tissue but carried no front, as it ended inside the
    /// tissue or crossed it more than once (systems/cut/blade_front.h); the end of the run says so
    std::vector<int> blade_not_through;
    int cuts_seen = 0;               ///< cut elements when the zones were last built
    int phantoms_seen = 0;           ///< phantoms then: later ones take the tips' field (transfer)
    int version = 0;                 ///< counts the zones built (a factor knows which it was made for)

    // ---- the amplitudes at the latest positions the step's term evaluated (D per function, world
    //      frame [sqrt(m)]): the step's end (the SolverSystem, once the step is counted), a static
    //      solve's last iterate. What is shown, the phantoms' transfer and the probes read them
    //      (step_tip_amplitudes, systems/cut/crack_tip_system.h) while amplitude_step is the world's
    //      step and amplitude_version the zones' version, instead of factoring H again
    Eigen::VectorXd amplitude;
    int amplitude_step = -1;
    int amplitude_version = -1;

    // ---- what is shown inside the tips' elements (show_crack_tips, at the steps the volume output
    //      writes or a visual surface shows; engine/io/clipped_cells.cpp and
    //      systems/surface/surface_tips.cpp read it when shown_step is the world's step): the
    //      element as four triangles fanned from the tip, the crack's entry point once per lip
    int shown_step = -1;
    std::vector<int> shown_tip;                       ///< per shown tip: the tip
    std::vector<int> shown_element;                   ///< per shown tip: the mesh element it lies in
    std::vector<std::array<int, 12>> shown_cells;     ///< its 4 triangles: a mesh node, or -1 - k for point k
    std::vector<std::array<Vec3, 3>> shown_rest;      ///< points: the entry on each lip, the tip [m]
    std::vector<std::array<Vec3, 3>> shown_position;  ///< the same placed by the enriched field [m]
    std::vector<std::array<Vec3, 3>> shown_velocity;  ///< the element's linear interpolation [m/s]

    int count() const { return static_cast<int>(point.size()); }
    int functions() const { return 4 * static_cast<int>(node.size()); }
    int zone() const { return static_cast<int>(element.size()); }
};

}  // namespace xcut
