#pragma once
// CutSystem: the paper's semi-progressive cut (§3.3, Fig. 14).
//  - The blade's cutting edge sweeps a *collision quad* from where it was when the last quad was
//    made (the anchor) to where it is now; a new quad is made only once the blade has moved more
//    than a threshold (default: the mean edge length; a quarter of it where blades carry crack
//    fronts in 3D, kFrontQuadFraction).
//  - Candidates: on first contact, an Embree query over element boxes around the quad; afterwards
//    the elements sharing a vertex with the last crossed ones, as many levels deep as the quad is
//    long in elements (a fast blade skips no element).
//  - Every candidate edge is tested against the quad's two triangles in double precision; an edge
//    counts once however often a trembling blade re-crosses it. Elements move through the lists
//    L1 -> L2 -> L3 by their count of distinct crossed edges, and are split (a CutEvent) once fully
//    crossed: three distinct edges or four in 3D, two in 2D. Elements the search no longer reaches
//    are dropped from the lists.
//  - `cutter.front: "progressive"` (CutState::progressive; docs/xfem.md): an element is split as soon
//    as the blade enters it, on the blade's plane extended through it (a *tip element*), and stays a
//    candidate: each later crossing of its edges is queued as an event that tells the enrichment
//    which edges are crossed now, until it is fully crossed.
//  - Each bladed tool has its own lists and front (CutState::blade): several scalpels cut
//    independently; an element queued by one is not tested again by any.
//  - A blade with a face (`blade.back`, ToolBodies::blade_back) also cuts what its face passes
//    through: each quad is tested with the face where the quad ends, so a stab (the blade pushed
//    along its own edge, whose edge sweeps no surface) makes an incision the shape of the face.
// 2D: the blade is a point (its tip) moving in the plane; the quad is the segment it swept.
#include <memory>

#include "systems/kernels/element_bvh.h"
#include "engine/scheduler.h"
#include "engine/world.h"

namespace xcut {

/// The default quad threshold where blades carry crack fronts (3D `cutter.tip`), as a fraction of
/// the mean edge. The front's functions reach the elements round the blade's edge (radius 0); the
/// crossed elements behind it open only once split, and at a whole mean edge a quad registers
/// their crossings up to an edge behind the blade: on the default skin the lips met over about a
/// millimetre between the wound and the front's opening (docs/xfem.md, The slit inside the front's
/// elements). At a quarter the wound reaches the front's elements.
inline constexpr double kFrontQuadFraction = 0.25;

/// Processes one quad of bladed tool `tool` (corners: tip0, heel0, heel1, tip1; 2D uses tip0 ->
/// tip1) against that tool's own lists and front, and with `face` the blade's face where the quad
/// ends (tip1, heel1, heel1 + back, tip1 + back): an edge crossed by either counts. Queues splits.
void process_cut_quad(World& world, ElementBvh& bvh, const CutQuad& quad, int tool = 0, const CutQuad* face = nullptr);

/// 2D, a blade that stops: if it stops inside the element its path began in (BladeCut::
/// start_element, still whole), having come back into it across another edge than it first left it
/// by, that element is split from where it came back in to where it first went out
/// (BladeCut::start_exit): a loop that closes inside the element it began in frees its piece.
void close_at_start(World& world, int tool);
/// 2D: once the element a blade's path began inside (BladeCut::start_element) has been split by
/// the same blade coming back across it, that element is cut again from where the path began to
/// where it first went out (BladeCut::start_exit; stem_event: a start within the join distance of
/// the split's line meets it): a loop whose closing pass runs past its start, beside it in the
/// material, meets it there and frees its piece.
void stem_at_start(World& world, int tool);
/// The mesh elements and nodes the cut searches (the element BVH's view of the world).
MeshView mesh_view(const World& world);
/// One step of the cutter for every bladed tool.
void run_cut_system(World& world, ElementBvh& bvh);
/// Builds the first-contact BVH (boxes grown by one mean edge) before the first step, so the
/// cut loop does not pay for it.
void prepare_cut_search(World& world, ElementBvh& bvh);

SystemDesc cut_system(std::shared_ptr<ElementBvh> bvh);

}  // namespace xcut
