#pragma once
// State of the semi-progressive cut (paper §3.3, Fig. 14): the current collision quad, the blade
// edge when the last quad was made, and per partly crossed element the edges crossed so far, kept
// in the paper's lists L1, L2, L3 by how many distinct edges are crossed.
#include <array>
#include <cstdint>
#include <map>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "components/nodes.h"

namespace xcut {

inline std::array<Vec3, 6> filled(const Vec3& v) { return {v, v, v, v, v, v}; }

/// A point of the tissue (2D): a mesh triangle (whole, or cut: the fragment holding it) when it was
/// found, and the point's barycentric coordinates in it; element -1: none (the point lies outside
/// the tissue, or in 3D).
struct MaterialPoint {
    int element = -1;
    Vec3 bary = Vec3::Zero();
    /// The element was cut when the point was found: the virtual element (its fragment, or side)
    /// whose material holds the point; bary are then its node copies' weights. -1: whole.
    int fragment = -1;
};

struct ElementCrossings {
    uint8_t mask = 0;                 ///< bit k: local edge k crossed (distinct edges only)
    std::array<double, 6> t{};        ///< crossing parameter along each crossed edge [-]
    std::array<Vec3, 6> normal = filled(Vec3::Zero());  ///< normal of the quad triangle that crossed the edge
    double first_time = 0.0;          ///< simulated time of the first crossing [s]
    double first_wall = 0.0;          ///< wall time of the first crossing [s]
    int list = 0;                     ///< 1, 2 or 3: which of L1, L2, L3 holds it
    bool split = false;               ///< progressive front: already split as a tip element
    /// 2D, an element already cut that the blade left through the edge it came in by, having turned
    /// beside one of its lines (a dip: systems/cut/cut_system.cpp, note_dip): where it turned, as a
    /// point of the tissue. Crossed nowhere else by the time the blade leaves it, it is cut from
    /// where the blade came in to there. Element -1: no dip.
    MaterialPoint turn;
};

struct CutQuad {
    std::array<Vec3, 4> corner;       ///< tip0, heel0, heel1, tip1 [m]
};

/// One bladed tool's cut in progress: its own partly crossed elements, lists and search front, so
/// several scalpels cut independently (one's front never steers the other's search).
struct BladeCut {
    std::unordered_map<int, ElementCrossings> crossing;  ///< partly crossed elements
    std::array<std::vector<int>, 3> lists;  ///< L1, L2, L3 (element ids)
    std::vector<int> front;           ///< elements the last quad crossed: seeds of the next search
    /// 3D, elements already cut that the blade's edge passed through where it began to cut (its
    /// first quad after cutting nothing): that edge, tip and heel [m], current positions. Where a
    /// T's stem starts (systems/cut/stem_3d.h); dropped with the partly crossed elements.
    std::map<int, std::array<Vec3, 2>> began_in;
    /// 3D, elements already cut that the blade is partly through: its edge where the last quad that
    /// ended inside one ended (tip, heel [m], current positions) and that quad's travel (its tip's).
    /// Where a stem drawn to a wound ends: once the blade leaves the element, it is cut behind that
    /// edge (systems/cut/stem_3d.h).
    std::map<int, std::array<Vec3, 3>> ended_in;
    /// 2D: the mesh triangle the blade's path began inside (uncut then; -1: none, or the path began
    /// outside the tissue) and, once the blade has left it crossed once, that crossing out of it
    /// (mask 0 before). A path that comes back into it and stops there takes that crossing as its
    /// own (close_at_start, systems/cut/cut_system.h): a loop closing inside the element it began in
    /// splits it from where it came back in to where it first went out, and its piece is freed.
    int start_element = -1;
    ElementCrossings start_exit;
    /// 2D: where the path began inside start_element, as a point of the tissue. When the blade
    /// comes back across that element and splits it (a loop closing past its start: start_stem),
    /// the stretch from there to start_exit is cut too, once the split is made (stem_at_start).
    MaterialPoint start_point;
    bool start_stem = false;
    /// Elements already cut that the blade passes along their cut (test_element's `beside`), and
    /// the crossings it made there near that cut, not counted yet: once it crosses one of them away
    /// from the cut, they count with that crossing (a blade that met a wound at a slant and went on
    /// beside it: it went in near the cut's point on the edge); dropped with the partly crossed
    /// elements.
    std::map<int, ElementCrossings> near;
};

struct CutState {
    double threshold = 0.0;           ///< blade travel that makes a new quad [m]; 0: mean edge length
    int min_depth = 1;                ///< neighbourhood levels searched around the last crossings
    bool bvh_every_quad = false;      ///< candidates from the Embree BVH for every quad (measured alternative)
    /// "cutter.front": false: semi-progressive (an element is split once fully crossed, paper §3.3);
    /// true: progressive (split when the blade enters it; its uncrossed edges are held, docs/xfem.md).
    bool progressive = false;
    /// "cutter.recut": whether an element already cut is cut again (docs/xfem.md, Several cuts per
    /// element): -1 as the dimension has it (2D on; 3D off: a cut that ends inside a 3D body can
    /// leave its surface open where it meets an element cut again), 0 off, 1 on.
    int8_t recut = -1;
    double mean_edge = 0.0;           ///< mean mesh edge length, rest [m]
    std::vector<uint8_t> anchored;    ///< per tool: the blade has an anchor (quad start)
    std::vector<Vec3> anchor_tip, anchor_heel;  ///< per tool: blade edge in world at the last quad [m]
    /// Per tool: the tissue at the blade edge's ends (tip, heel) at the last quad. The next quad
    /// starts where that tissue is now (systems/cut/material_anchor.h), so the blade's path through
    /// the tissue has no gap and no overlap where the tissue moves under it between steps.
    std::vector<std::array<MaterialPoint, 2>> anchor_material;
    std::vector<Vec3> last_tip, last_heel;      ///< per tool: blade edge at the previous step [m]
    /// Per tool: the edge's ends (tip, heel) at the sweep's samples passed since the last quad, in
    /// world [m]: where one lies off the straight sweep to the next, the blade turned (kTurnFraction).
    std::vector<std::vector<std::array<Vec3, 2>>> since_anchor;
    /// per tool: the blade's path has been ended where it stopped (its last stretch cut, its stems
    /// made: end_stems); cleared when it moves again
    std::vector<uint8_t> ended;
    std::vector<CutQuad> quads;       ///< quads made this step (all tools)
    std::vector<BladeCut> blade;      ///< per tool
    /// Per mesh element: a split was queued for it; it is not tested again. The decision is the
    /// CutSystem's, whichever cutter (XFEM or snapping) applies the split.
    std::vector<uint8_t> queued;

    // Figures (per step, reset by the CutSystem; delays kept for the whole run).
    int quads_built = 0;
    int elements_tested = 0;
    int crossings_found = 0;
    int elements_split = 0;           ///< splits queued (the cutter may find one needless: the CSV counts applied ones)
    double update_ms = 0.0;
    std::vector<double> delay_sim;    ///< per split element: first crossing to split [s]
    std::vector<double> delay_wall;   ///< [s]
    std::vector<double> quad_ms;      ///< wall time of each quad update [ms]
    std::vector<int> split_by_tool;   ///< per tool: splits its blade queued over the run
    /// Per tool: how far its blade moved along its own edge inside the tissue over the run [m] (a
    /// stab): an edge moving along itself sweeps no surface, so that travel cut nothing
    /// (systems/cut/cutting_force.h measures it; the end of the run says so).
    std::vector<double> stab_travel;
    /// Per element split so far: the unit normal of the blade that split it [-].
    std::unordered_map<int, Vec3> split_normal;
    /// Per tool: the elements already split along another plane (more than 30 degrees from its cut, kRecutCos) that
    /// its blade crossed. xcut splits an element once: they keep their first cut, and the end of
    /// the run says so (an incision that meets a wound stops about an element short of it).
    std::vector<int> recut_ignored;
    std::unordered_set<int64_t> recut_seen;  ///< element * 64 + tool, counted once
    /// Per tool: the elements its blade crossed lying on the skin (kThinFlapFraction): they are not
    /// split (no flap that thin), and the end of the run says so.
    std::vector<int> on_skin_ignored;
    std::unordered_set<int64_t> on_skin_seen;  ///< element * 64 + tool, counted once
    /// Per tool (2D): its blade's path as cut, the quads' tip points in world [m], the simulated
    /// time it began, and the time it first closed a loop (-1: never) [s]: it crossed itself, or
    /// crossed another blade's path a second time (loop_with: that blade, or itself). The end of the
    /// run says when such a loop freed no piece.
    std::vector<std::vector<Vec3>> path;
    std::vector<double> path_time, loop_time;
    std::vector<int> loop_with;
    /// Where two blades' paths cross (tools i < j), distinct points [m].
    std::map<std::pair<int, int>, std::vector<Vec3>> paths_meet;
};

/// A cut whose every point in an element lies closer than this fraction of the element's shortest
/// edge to the plane of one of its boundary faces, and crosses an edge farther than that from its
/// nodes, is a blade lying on the skin, not an incision: it would leave a flap thinner than that,
/// and is not made (lies_on_skin in systems/cut/cut_system.cpp). A cut whose points all lie at nodes
/// is one beside a node layer, and is made [-].
inline constexpr double kThinFlapFraction = 1e-3;

/// The angle between a blade and an element's earlier cut past which crossing it would be a second
/// cut: 30 degrees, as its cosine [-].
inline constexpr double kRecutCos = 0.8660254037844387;

}  // namespace xcut
