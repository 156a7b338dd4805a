#pragma once
// The visual surface opened inside the crack tips' elements (2D; the tips: systems/cut/
// crack_tip_system.h). A tip's element is not split, so its nodes alone show no opening inside it,
// and a surface mapped with the linear shape functions shows the crack stopping at the element's
// edge. The surface is mapped with the enriched shape functions instead, as the volume output is:
//  - every vertex bound to an element of a tip's zone is placed by the enriched field
//    x(X) = Σ_k N_k x_k + Σ_k N_k Σ_l (F_l(X) - F_l(X_k)) b_kl on its element's lip
//    (systems/xfem_queries.h, tip_enrichment);
//  - the crack's elements are slit: from the tip back along the crack, each whole element it runs
//    through shows, in place of its pieces, a fan (from the tip in the tip's element, else from the
//    middle of its chord) over the vertices on its edges, each crossing of the crack with an edge
//    made once per lip. The walk ends where the surface already shows the crack (the cut point of
//    a split element behind, whose pieces then take the crossing of their own lip), at the sheet's
//    border, or where the zone ends (no functions beyond: the lips meet, one vertex).
// The tip's functions open the crack in every zone element behind the tip, also in the one or two
// the semi-progressive front has not split yet (it splits when the blade has moved an edge length,
// paper §3.3), so a surface slit only in the tip's element would show the crack there, and not
// behind it, for most steps of a moving blade.
// It is an overlay: laid over the surface after the MappingSystem has placed it, taken off before
// the surface is cut or placed again (SurfaceMesh::tip_*), so the surface's own pieces, points and
// bindings are those of a surface without tips. A crack that meets a corner of an element it runs
// through (within 1e-6 of its edge) is not slit for that tip.
// 3D (straight fronts, systems/kernels/front_enrichment.h): every vertex bound to a zone element is
// placed by the enriched field of its lip, x(X) + Σ_k N_k Σ_l (F_l(X) - F_l(X_k)) b_kl, so the
// lips of the split elements near the front open as the √r field says, not linearly; and the whole
// elements the crack behind a front runs through are slit (systems/surface/surface_fronts.cpp).
#include "engine/world.h"

namespace xcut {

/// Lays the tips' opening over `surface` (needs CrackTips::amplitude of this step, and 2D's
/// CrackTips::shown_*); takes off the one laid before first. Nothing when the world has no tips.
/// In 3D, SurfaceMesh::front_slit_elements says how many elements it slit.
void open_tips_on_surface(World& world, SurfaceMesh& surface);

/// Takes the overlay off: the surface's triangles and vertices as they were before it.
void take_off_tip_opening(SurfaceMesh& surface);

}  // namespace xcut
