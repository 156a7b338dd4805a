#pragma once
// The pieces of tissue: the connected parts of the simulated material. Two force elements (mesh
// elements, the virtual elements of cut elements, the snapping cutter's pieces) belong to one piece
// when they share a DOF node, real or phantom: a cut that runs through a body frees the part it
// closes off, and the two parts then share no DOF (systems/cut/pieces_system.h counts them).
#include <array>
#include <cstdint>
#include <vector>

namespace xcut {

/// A piece a cut made, logged when it is first counted.
struct PieceEvent {
    int step = 0;
    double time = 0.0;     ///< simulated [s]
    double volume = 0.0;   ///< rest volume [m^3]
    int body = 0;          ///< World::body_names index of its first element
    bool anchored = false; ///< it holds a fixed node
};

struct Pieces {
    /// What the count was made for: cut elements, enriched DOF nodes, the snapping cutter's splits
    /// and copies, force elements. A step that changes none of them cannot change the pieces.
    std::array<long long, 6> topology{-1, -1, -1, -1, -1, -1};
    /// Per force element: its piece; -1 if it carries no volume (a cut mesh element, weight 0, or a
    /// side floored at kMinSideFraction, which joins nothing)
    std::vector<int> of_element;
    /// Per piece, in the order of their first force element (deterministic):
    std::vector<double> volume;    ///< rest volume, sum of V weight [m^3]
    std::vector<uint8_t> anchored; ///< holds a fixed node (a constraint holds it in place)
    std::vector<int> body;         ///< the body of its first force element
    std::vector<uint8_t> sliver;   ///< below kSliverPiece of its body's mean element volume: no piece
    int count = 0;                 ///< pieces, slivers left out
    int initial = -1;              ///< the count at the first step (-1: not counted yet)
    std::vector<PieceEvent> log;   ///< pieces cuts have made, in order
};

/// A connected part smaller than this fraction of its body's mean element volume is a *sliver*: a
/// node nicked off by a cut through all its elements close to it. It is simulated like any part (its
/// nodes keep their floored mass) but is not counted or reported as a piece [-].
inline constexpr double kSliverPiece = 1e-3;

}  // namespace xcut
