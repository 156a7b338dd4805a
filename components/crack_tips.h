#pragma once
// Crack tips enriched with branch functions (2D; systems/cut/crack_tip_system.h,
// systems/kernels/branch_enrichment.h). Each enriched node carries, per tip, four branch functions
// times a 2D amplitude; the amplitudes are condensed out of the step (they have no mass), so this
// holds only what the condensation needs: which force elements the enrichment reaches and the
// integrals of its shape functions' gradients over each, at rest (SI units).
#include <Eigen/Core>
#include <vector>

#include "components/nodes.h"

namespace xcut {

struct CrackTips {
    // ---- per tip (rest configuration)
    std::vector<Vec3> point;       ///< where the crack ends [m]
    std::vector<Vec3> direction;   ///< the crack's unit direction at the tip, pointing ahead of it [-]
    // ---- per enriched (tip, node) pair: functions 4 pair + l, 2 amplitudes each
    std::vector<int> node;         ///< the mesh node
    std::vector<int> tip;          ///< the tip
    // ---- per zone element: a force element whose mesh element holds an enriched node
    std::vector<int> element;      ///< force element (a mesh element, or a virtual element of a cut one)
    std::vector<int> first;        ///< its functions: [first[z], first[z + 1]) in `function`; size zone + 1
    std::vector<int> moment_first; ///< its n_z^2 gradient moments start here in `moment`
    // ---- per zone element and function a (its own order)
    std::vector<int> function;     ///< global function: 4 pair + l
    std::vector<Vec3> gradient;    ///< G_a = t ∫ ∇φ_a over the element's part [m^2.5]; z = 0
    std::vector<Mat3> moment;      ///< M_ab = t ∫ ∇φ_a ∇φ_b^T, row-major by (a, b) [m^2]; z row, column 0

    // ---- blades that carry tips (scene cutter.tip; systems/cut/crack_tip_system.h, follow_blades)
    double follow_radius = -1.0;     ///< [m] each blade's tip enriched within this radius; < 0: off
    std::vector<Vec3> blade_point;   ///< per tool: its blade's last rest point in uncut tissue [m]
    std::vector<uint8_t> blade_seen; ///< per tool: blade_point holds one
    int cuts_seen = 0;               ///< cut elements when the zones were last built
    int phantoms_seen = 0;           ///< phantoms then: later ones take the tips' field (transfer)
    int version = 0;                 ///< counts the zones built (a factor knows which it was made for)

    int count() const { return static_cast<int>(point.size()); }
    int functions() const { return 4 * static_cast<int>(node.size()); }
    int zone() const { return static_cast<int>(element.size()); }
};

}  // namespace xcut
