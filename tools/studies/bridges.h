#pragma once
// The stress suite's "no bridge" invariant: an element a blade crosses through and through is split,
// and with "cutter.recut" the nodes its sweep separates end in different fragments of it.
//
// Which elements were crossed is decided here apart from the CutSystem (none of its code, lists or
// thresholds): each step, the surface each blade's edge sweeps between its poses at the step's
// start and end (its trajectory sampled kSweepSamples times: triangles), and that surface's rim
// (the paths of the edge's two ends, the edge where the blade began and where it is at the end),
// are carried into the rest frame of every element near them by the element's own affine map at
// the step's start, the positions the cut is made on (exact for a linear element, however it
// moved). At the end, an element is crossed through when no rim comes within a margin of it (the
// sweep then divides it), and two of its nodes farther than a tolerance from the sweep, joined by
// an edge the sweep crosses, must lie in different fragments (elements cut once: on different
// sides of its cut; without recut: the element must be cut at all).
//
// Tolerance and margin (rest [m]): the element's shortest edge h times 0.02 (a node's distance to
// the sweep) and 0.1 (the rim's to the element), plus how far the element moved, off the piece or
// across the rim segment, from the step the piece was swept in over the steps the blade takes to
// travel a mean edge length. A cut is made on quads of about that travel, tested on the positions
// of the step that makes them, and tissue sagging a millimetre a step moves under the blade.
// Left out (counted as such, never as held): blades with a face (blade.back: the face's rim is not
// traced) and the elements near them, elements inverted or flat in some step; 2D bodies and
// quadratic tetrahedra (not mapped affinely) are not checked.
#include <array>
#include <map>
#include <unordered_map>
#include <vector>

#include "engine/world.h"

namespace xcut {

constexpr int kSweepSamples = 8;  ///< blade poses per step the sweep is traced through

struct BridgeTally {
    int crossed = 0;   ///< mesh elements crossed through by some blade's sweep
    int bridged = 0;   ///< of those, left whole or with two nodes the sweep separates joined
    int left_out = 0;  ///< elements near a blade with a face, or inverted in some step
};

class BridgeCheck {
public:
    /// Records the blades' sweep over the coming step [w.time, w.time + w.dt]; call before stepping.
    void before_step(const World& w);
    /// The verdict on the world as it is now (after the last step).
    BridgeTally tally(const World& w) const;

    /// Where in a cut element a sweep carried by one fragment's own map is that fragment's: within
    /// the rest half-spaces bounding it (plane, the side its normal points to or not), and farther
    /// than `open` from the element's cuts (the wound's lips had parted by up to that, so a sweep
    /// nearer lies in the wound: the blade that made it, going on along it) [m].
    struct Region {
        std::vector<std::pair<CutLine, bool>> bounds;
        std::vector<CutLine> cuts;
        double open = 0.0;
    };
    /// When a piece of the sweep or its rim was carried into an element, and how far the element's
    /// motion from then could shift it: the steps within which a cut could test it (the blade's
    /// travel of a mean edge length), and the direction that counts (a piece's normal; a rim
    /// segment's direction, whose own motion does not count), world [-].
    struct Taken {
        int step = 0, window = 1;
        Vec3 direction = Vec3::Zero();
    };
    struct Piece {
        std::array<Vec3, 3> tri;  ///< rest [m]
        int region = 0;           ///< index into Seen::regions
        Taken taken;
    };
    struct Rim {
        std::array<Vec3, 2> seg;  ///< rest [m]
        Taken taken;
    };
    struct Seen {
        std::vector<Piece> sweep;
        std::vector<Region> regions;
        std::vector<Rim> rim;
        std::map<int, std::vector<Rim>> end;  ///< per blade: its edge after the last step it moved in
        bool left_out = false;
    };
private:
    std::unordered_map<int, Seen> seen_;
    std::vector<std::vector<Vec3>> drift_;  ///< per step, per mesh element: its centroid's travel [m]
    std::vector<Vec3> last_;                ///< mesh node positions at the last step's start [m]
    double mean_edge_ = 0.0;                ///< rest [m]
    bool started_ = false;
};

/// Whether the world's cut keeps mesh element e's nodes a and b (local 0-3) apart: in different
/// fragments (elements cut again), on different sides of its cut (cut once).
bool nodes_apart(const World& w, int e, int a, int b);

}  // namespace xcut
