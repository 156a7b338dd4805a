#pragma once
// Several cuts per element (docs/xfem.md, Several cuts per element): a triangle already cut is cut
// again along another line, a tetrahedron along another plane (CutLine: a point and a normal). It
// keeps its nodes; its material is divided into fragments, the parts of it on one side of each of
// its lines, each a virtual element with its own rotation and its exact area (volume) over the
// element's as weight (a linear element's strain is constant, so that is the exact integral;
// Molino, Bao & Fedkiw 2004, the virtual node algorithm). A new fragment starts
// from the vertices of the one it was cut from; the node copies (systems/cut/node_copies.h) then
// give each its own where material connectivity parts them.
#include <algorithm>
#include <span>
#include <vector>

#include "engine/world.h"
#include "systems/xfem_queries.h"  // first_edge_params, line_edge_params

namespace xcut {

/// Cosine of the angle [-] within which (and 1e-3 of the element's size apart) a further cut's line
/// is one of the element's lines: cos 1 degree.
inline constexpr double kSameLineCos = 0.9998476951563913;

/// The line of cut element c's first cut: through its edge points (2D: two; 3D: the plane through
/// three or four), its normal toward the side H = +1 of the element's nodes.
CutLine first_cut_line(const World& world, int c);

/// Cut element c's lines: those it keeps once cut again, else its first cut's line alone.
std::vector<CutLine> lines_of(const World& world, int c);
/// lines_of without a copy: a view of the element's lines, or of its first cut's line, kept in
/// `first` (valid while `first` and the cut's lines are).
std::span<const CutLine> lines_in(const World& world, int c, CutLine& first);

/// Cuts element ev.element again along the line (plane) of ev's levels (linear, already cut): its
/// fragments crossed by the line are split, each into the part on the line's side +1 (the old
/// virtual element, new weight) and a new virtual element for the rest. Along one of its lines
/// already (a bounded cut on that line goes on), it divides the fragments that line does not bound
/// yet and adds no line; not where that line would cross an edge more than kEdgeOverlap2d from a
/// point the event took from an earlier crack there (join_earlier_points): the element beside,
/// whose line goes through that point, would hold a wedge of the material on both sides. Returns
/// false (and changes nothing) if the element is not cut, it already holds kMaxElementLines and the
/// line is a new one, or it divides no fragment.
bool record_recut(World& world, const CutEvent& ev);

/// Whether rest point x lies in fragment (virtual element) v of cut element c with lines (on or
/// inside its boundary).
bool fragment_holds(const World& world, int c, int v, const Vec3& x);

}  // namespace xcut

namespace xcut {

/// The rest corners of triangle e.
std::array<Vec3, 3> corners(const World& world, int e);

/// The mesh triangle other than e with edge (a, b), or -1 (a border edge).
int across_edge(const World& world, int e, int a, int b);

/// The rest corners of tetrahedron e.
std::array<Vec3, 4> tet_corners(const World& world, int e);

/// The longest edge of the element with corners X[0..N) [m].
template <size_t N>
double longest_edge(const std::array<Vec3, N>& X) {
    double size = 0.0;
    for (size_t a = 0; a < N; ++a)
        for (size_t b = a + 1; b < N; ++b) size = std::max(size, (X[b] - X[a]).norm());
    return size;
}

// recut_allowed (whether this world cuts an element again, by scalpels and scripted cuts alike;
// an event then takes the sides and parts of its own line where the element's nodes have theirs
// from another incision): systems/xfem_queries.h.

/// Whether a cut with normal `normal` through cut element e runs along another line than each
/// of its cuts (more than 30 degrees from it: kRecutCos), or along one that bounds only part of it
/// (a stem that stopped inside it, which goes on), and e can hold one more line.
bool cuts_across(const World& world, int e, const Vec3& normal);

/// Fraction of an edge [-] within which a blade passing along a cut element's cut crosses the edge
/// at the cut (its own wound retraced, the tissue moved under it): such a crossing is not a new one.
inline constexpr double kAlongFraction = 0.2;

/// Whether local edge k of cut element e, crossed at parameter t, is crossed within
/// kAlongFraction of where one of e's lines meets it. A blade along the cut that crosses an edge
/// away from it (a loop closing beside its first pass, a path grazing a mesh line) cuts again.
bool crosses_near_its_cut(const World& world, int e, int k, double t);

/// Whether a node of element e has its side from a cut more than 30 degrees from a cut with normal
/// `normal` (another incision's), or more than the angle whose cosine is `cos_limit`.
bool signed_by_other_incision(const World& world, int e, const Vec3& normal, double cos_limit = kRecutCos);

/// cos 5 degrees: in 3D a scripted cut's polygon is a plane of its own, so a node whose side a cut
/// more than 5 degrees from it gave has it from another incision (a polyline of polygons, such as an
/// arc drawn in chords 12-25 degrees apart, is one polygon per incision: past a joint, the sides the
/// previous polygon gave are not this one's). A cut made on moved tissue turns its elements' rest
/// normals by the tissue's rotation, alike for neighbours, far less than this.
inline constexpr double kScriptedRecutCos = 0.9961946980917455;

/// The cosine under which event ev's cut is another incision than a node's (kRecutCos, or
/// kScriptedRecutCos for a scripted cut in 3D).
double incision_cos(const World& world, const CutEvent& ev);

/// Fraction of an edge [-] within which a later crossing of it (another incision's, or the same
/// blade's later pass) is the point an earlier crack put there: a scalpel closing a loop meets its
/// own wound where the tissue has moved since (0.05-0.4 mm on 2 mm skin), and two points apart on
/// one edge leave the wedge between them joining both sides (a bridge: docs/xfem.md, Limits). The
/// same as kAlongFraction: a crossing the element beside takes as its own wound retraced (and does
/// not cut again) is joined to that wound here; at 0.1 the closing pass of a loop 0.35 mm inside
/// its first crossed one edge 0.17 of it from the first's point, the element beside was not cut
/// again and this one's crack ended on that edge apart from the first's (2 of 36 ellipses joined).
inline constexpr double kJoinFraction = kAlongFraction;

/// Two fragments of neighbouring elements hold one material across their common edge (2D) when
/// their parts of it overlap by more than this fraction of the edge [-] (systems/cut/node_copies.cpp).
/// Each element's lines are its own, fitted through its own points, and two incisions that nearly
/// meet give two elements across an edge crossings of it that differ: a loop's first pass began
/// beside a cross-cut's wound and its line in that element, run across it, crossed the edge 2.1e-4
/// of it (0.6 um) from where the closing pass crossed it into the element beside; the parts below
/// and above the loop then overlapped by that much, and the lens half they bound was one material
/// with the skin (loop stress trajectory 781, docs/BENCHMARKS.md). Material is a thousandth of the
/// edge (2 um on the skin's 2 mm cells) or more: the strips between two passes the stress suite
/// counts are 0.1 mm and wider. record_recut keeps a line from missing an earlier point by more.
inline constexpr double kEdgeOverlap2d = 1e-3;

/// An event of another incision or a later pass (2D): each edge it crosses within kJoinFraction of
/// an earlier crack's point there takes that point (a blade's, the nearest of the edge's points,
/// each incision's; a scripted cut's, the first, crack_edge_param), so its crack meets the
/// earlier one. So does, wherever on the edge, a blade's cut again of an element its own crack ends
/// on an edge of, where the blade went through that edge into the uncut element beyond and comes
/// back out through it (a path that grazes a mesh line). A blade that comes back out of the element
/// beyond (cut or not) through the edge it went in by, more than kJoinFraction from where it went
/// in, takes the point where it went in, or e's line within kJoinFraction of it: a path that dips
/// into an element and leaves it where another wound meets the edge would otherwise leave the
/// edge's part between the two points joining both sides of it. A bounded cut (a stem) keeps its
/// points.
/// In 3D (a scalpel's event): each edge it crosses takes the point its own incision (a cut within
/// 30 degrees of it) already put there in a neighbour, and a cut through four edges is then made
/// planar (its one point no neighbour fixed moves onto the plane of the other three): a blade's
/// crossings of one element are measured over several steps of moving tissue.
void join_earlier_points(const World& world, CutEvent& ev);

/// The plane of a cut event's levels through a tetrahedron with rest corners X (through the points
/// where they change sign on its edges, ev.edge_t where given), its normal toward positive levels;
/// false if they cross fewer than three edges or the points span no plane.
bool event_plane(const CutEvent& ev, const std::array<Vec3, 4>& X, CutLine& plane);

/// The line (2D) or plane (3D) of a cut event's levels through its element at rest.
bool event_cut_line(const World& world, const CutEvent& ev, CutLine& line);

/// The line of a cut event's levels through a triangle with rest corners X (the points where they
/// change sign on its edges, ev.edge_t where given), its normal toward positive levels; false if
/// the levels cross fewer than two edges at distinct points.
bool event_line(const CutEvent& ev, const std::array<Vec3, 3>& X, CutLine& line);

}  // namespace xcut
