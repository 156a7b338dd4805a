#include "systems/cut/node_copies.h"

#include <algorithm>
#include <array>
#include <fmt/format.h>
#include <span>
#include <stdexcept>
#include <unordered_map>

#include "systems/cut/quadratic_enrichment.h"
#include "systems/cut/recut.h"
#include "engine/fragment_geometry.h"
#include "systems/kernels/disjoint_sets.h"
#include "systems/xfem_queries.h"

namespace xcut {
namespace {

/// Two fragments of neighbouring elements, one of them cut again, hold one material across their
/// common edge (3D: face) when their parts of it overlap by more than this fraction of the edge's
/// length (the face's area) [-]: two lines crossing it at one point (each element computes it)
/// leave a few ulps, not an overlap.
constexpr double kFaceOverlap = 1e-9;
// In 2D, by more than kEdgeOverlap2d of the edge (systems/cut/recut.h).

/// Material of one element around the node: side 0 a whole element, else a cut element's side or,
/// once it is cut again, one of its fragments (systems/cut/recut.h).
struct Fragment {
    int element;
    int8_t side;
    int8_t slot;  ///< the node's local index in the element (a quadratic one's mid-edge node: 4..9)
    int ve;       ///< its virtual element (-1: a whole element)
    int count;    ///< the element's first fragment: how many it has; 0 for the others
};

/// The corners a node of local index `slot` lies on: itself, or a mid-edge node's two; returns how many.
int corners_of(int slot, std::array<int, 2>& corners) {
    if (slot < 4) return corners[0] = slot, 1;
    corners = {kTet10Edges[slot - 4][0], kTet10Edges[slot - 4][1]};
    return 2;
}

/// A face through the node (its nodes sorted) and the first fragment of an element holding it.
struct FaceOf {
    std::array<int, 3> nodes;
    int fragment;
    bool operator<(const FaceOf& o) const { return nodes != o.nodes ? nodes < o.nodes : fragment < o.fragment; }
};

/// Whether fragment f has material on a face (its nodes; -1 for none: a 2D face has two): a whole
/// element everywhere, a side where one of the face's nodes is on it.
bool on_face(const World& w, const Fragment& f, const std::array<int, 3>& face) {
    if (f.side == 0) return true;
    for (int n : face)
        if (n >= 0 && w.enriched.sign[n] == f.side) return true;
    return false;
}

/// The force element of fragment f's virtual element (f a cut element's side).
int virtual_of(const World& w, const Fragment& f) { return w.virtual_elements.element[f.ve]; }

/// Whether fragment f's element holds cut lines (it was cut again): its parts are then geometric.
bool has_lines(const World& w, const Fragment& f) {
    return f.side != 0 && !w.cuts.lines[w.cuts.cut_of_element[f.element]].empty();
}

/// The first cut's line of each cut element asked for over one batch of nodes (first_cut_line fits
/// it to the cut's points each time; nothing it reads changes while node copies are assigned).
class FirstLines {
public:
    const CutLine& of(const World& w, int c) {
        const auto [it, fresh] = lines_.try_emplace(c);
        if (fresh) it->second = first_cut_line(w, c);
        return it->second;
    }

private:
    std::unordered_map<int, CutLine> lines_;  // node-based: references stay valid
};

/// The lines (planes) that bound fragment f of a cut element, and its mask over them (a side of an
/// element cut once: its first cut's line, bit 0 its side).
std::span<const CutLine> bounds_of(const World& w, const Fragment& f, uint32_t& mask, FirstLines& firsts) {
    const int c = w.cuts.cut_of_element[f.element];
    if (w.cuts.lines[c].empty()) {
        mask = (f.side > 0 ? 1u : 0u) | bound_by(0);
        return {&firsts.of(w, c), 1};
    }
    mask = w.virtual_elements.mask[f.ve];
    return w.cuts.lines[c];
}

/// The part [s0, s1] of the segment from mesh node p to mesh node q that fragment f holds (2D).
std::array<double, 2> part_of_edge(const World& w, const Fragment& f, int p, int q, FirstLines& firsts) {
    if (f.side == 0) return {0.0, 1.0};
    uint32_t mask = 0;
    const std::span<const CutLine> lines = bounds_of(w, f, mask, firsts);
    return segment_part(w.nodes.rest[p], w.nodes.rest[q], lines.data(), static_cast<int>(lines.size()), mask);
}

/// Where plane l bounding fragment f crosses its element's mesh edge p -> q, as a parameter from p:
/// where the cut's own points put it (CutElements::line_edge_t, or the first cut's points); -1
/// where they record none (or the element has no such edge).
double plane_edge_param(const World& w, const Fragment& f, int l, int p, int q) {
    const int c = w.cuts.cut_of_element[f.element];
    const auto& n = w.elements.nodes[f.element];
    for (int e = 0; e < 6; ++e) {
        const int i = n[kTetEdges[e][0]], j = n[kTetEdges[e][1]];
        if (!((i == p && j == q) || (i == q && j == p))) continue;
        const double t = line_edge_params(w, c, static_cast<size_t>(l))[e];
        return t >= 0.0 && i == q ? 1.0 - t : t;
    }
    return -1.0;
}

/// The part [s0, s1] of mesh edge p -> q that fragment f holds (3D): each plane that bounds it
/// cuts the edge where the cut's own points put it (plane_edge_param; else where the plane does),
/// and a plane that does not cross the edge keeps it or not by the side of its end farther from it.
std::array<double, 2> part_of_edge_3d(const World& w, const Fragment& f, int p, int q, FirstLines& firsts) {
    if (f.side == 0) return {0.0, 1.0};
    uint32_t mask = 0;
    const std::span<const CutLine> planes = bounds_of(w, f, mask, firsts);
    const Vec3 &a = w.nodes.rest[p], &b = w.nodes.rest[q];
    double s0 = 0.0, s1 = 1.0;
    const auto& n = w.elements.nodes[f.element];
    const bool has_edge = std::find(n.begin(), n.begin() + 4, p) != n.begin() + 4 && std::find(n.begin(), n.begin() + 4, q) != n.begin() + 4;
    for (int l = 0; l < static_cast<int>(planes.size()) && has_edge; ++l) {
        if (!(mask & bound_by(l))) continue;
        const bool bit = mask >> l & 1u;
        const double la = planes[l].normal.dot(a - planes[l].origin), lb = planes[l].normal.dot(b - planes[l].origin);
        const double t = plane_edge_param(w, f, l, p, q);
        if (t > 0.0 && t < 1.0) {
            const bool a_side = std::abs(la) >= std::abs(lb) ? la >= 0.0 : lb < 0.0;  // a's side of the plane
            if (a_side == bit) s1 = std::min(s1, t);
            else s0 = std::max(s0, t);
        } else if (((std::abs(la) >= std::abs(lb) ? la : lb) >= 0.0) != bit) {
            s0 = 1.0, s1 = 0.0;
        }
    }
    return {s0, s1};
}

/// A convex polygon on a face, held in place (node copies clip hundreds a step): a triangle clipped
/// by the planes of two fragments, each clip adding at most one vertex, with room to spare.
struct FacePolygon {
    std::array<Vec3, 4 * kMaxElementLines + 8> v;
    int n = 0;
};

/// `poly` (on the face `face` of fragment f's element, 3D; rest) clipped to f's part of the face:
/// by the trace of each plane bounding f, the line through its crossings of the face's edges
/// where the cut's own points put them (plane_edge_param: the element across, cut by the same
/// incision, has the same trace), toward f's side. A plane without two crossings there keeps the
/// face or not by the side of the face's vertex farthest from it.
FacePolygon clip_to_face_part(const World& w, const Fragment& f, const std::array<int, 3>& face, FacePolygon poly,
                              FirstLines& firsts) {
    if (f.side == 0) return poly;
    uint32_t mask = 0;
    const std::span<const CutLine> planes = bounds_of(w, f, mask, firsts);
    const std::array<Vec3, 3> X{w.nodes.rest[face[0]], w.nodes.rest[face[1]], w.nodes.rest[face[2]]};
    const Vec3 normal = (X[1] - X[0]).cross(X[2] - X[0]);
    for (int l = 0; l < static_cast<int>(planes.size()) && poly.n >= 3; ++l) {
        if (!(mask & bound_by(l))) continue;
        std::array<Vec3, 3> ends;
        int n_ends = 0;
        for (int e = 0; e < 3; ++e)
            if (const double t = plane_edge_param(w, f, l, face[e], face[(e + 1) % 3]); t > 0.0 && t < 1.0)
                ends[n_ends++] = X[e] + t * (X[(e + 1) % 3] - X[e]);
        int far = 0;
        for (int v = 1; v < 3; ++v)
            if (std::abs(planes[l].normal.dot(X[v] - planes[l].origin)) > std::abs(planes[l].normal.dot(X[far] - planes[l].origin))) far = v;
        const bool far_kept = (planes[l].normal.dot(X[far] - planes[l].origin) >= 0.0) == static_cast<bool>(mask >> l & 1u);
        if (n_ends != 2) {
            if (!far_kept) poly.n = 0;
            continue;
        }
        const CutLine trace{ends[0], (ends[1] - ends[0]).cross(normal)};
        FacePolygon out;
        out.n = clip_to_side(poly.v.data(), poly.n, trace, (trace.normal.dot(X[far] - ends[0]) >= 0.0) == far_kept, out.v.data(),
                             static_cast<int>(out.v.size()));
        poly = out;
    }
    return poly;
}

/// The parts of mesh edges the fragments around one node hold, each computed once (part_of_edge,
/// part_of_edge_3d): a fragment meets the fragments across each of its faces through the node, and
/// each such face's edges are asked for by every pair across it. Keyed by the fragment's index and
/// the edge's ordered ends (p -> q and q -> p are different parameters).
class EdgeParts {
public:
    EdgeParts(const World& w, const std::vector<Fragment>& frags, FirstLines& firsts)
        : w_(w), frags_(frags), firsts_(firsts), memo_(frags.size()) {}
    FirstLines& firsts() { return firsts_; }
    std::array<double, 2> operator()(int f, int p, int q) {
        for (const Entry& m : memo_[f])
            if (m.p == p && m.q == q) return m.part;
        const Fragment& fr = frags_[f];
        const auto part = w_.elements.dim == 2 ? part_of_edge(w_, fr, p, q, firsts_) : part_of_edge_3d(w_, fr, p, q, firsts_);
        memo_[f].push_back({p, q, part});
        return part;
    }

private:
    struct Entry {
        int p, q;
        std::array<double, 2> part;
    };
    const World& w_;
    const std::vector<Fragment>& frags_;
    FirstLines& firsts_;
    std::vector<std::vector<Entry>> memo_;
};

/// Whether fragments a and b (indices into `frags`) hold overlapping parts of their elements'
/// common face (its mesh nodes; 2D: an edge, face[0] = -1): parts of it that overlap by more than
/// kFaceOverlap of its length (area) hold one material there. In 3D first the parts of the face's
/// three edges (the edges' crossings are the cuts' own points, one value for both elements); parts
/// that meet the edges at most at points may still overlap inside the face (three traces closing a
/// triangle there), so then the area of both parts (clip_to_face_part).
bool share_face(const World& w, const std::vector<Fragment>& frags, EdgeParts& parts, int a, int b,
                const std::array<int, 3>& face) {
    if (w.elements.dim == 2) {
        const auto pa = parts(a, face[1], face[2]), pb = parts(b, face[1], face[2]);
        return std::min(pa[1], pb[1]) - std::max(pa[0], pb[0]) > kEdgeOverlap2d;
    }
    for (int e = 0; e < 3; ++e) {
        const int p = face[e], q = face[(e + 1) % 3];
        const auto pa = parts(a, p, q), pb = parts(b, p, q);
        if (std::min(pa[1], pb[1]) - std::max(pa[0], pb[0]) > kFaceOverlap) return true;
    }
    FacePolygon whole;
    whole.v[0] = w.nodes.rest[face[0]], whole.v[1] = w.nodes.rest[face[1]], whole.v[2] = w.nodes.rest[face[2]], whole.n = 3;
    const FacePolygon both =
        clip_to_face_part(w, frags[b], face, clip_to_face_part(w, frags[a], face, whole, parts.firsts()), parts.firsts());
    return both.n >= 3 && polygon_area_3d(both.v.data(), both.n) > kFaceOverlap * polygon_area_3d(whole.v.data(), whole.n);
}

/// share_face's answers, kept in the world between batches (CutElements::face_shares): a face's
/// pair of fragments is met again at each of the face's nodes and in every later batch whose nodes
/// it touches, and nothing it reads (the lines a fragment's mask names, their recorded crossings,
/// rest positions) changes once made: a fragment divided again has a new mask, an element cut
/// once that is cut again keeps the first line it was fitted to (ensure_lines). Keyed by the two
/// fragments in the order asked and the face's nodes.
class SharedFaces {
public:
    explicit SharedFaces(World& w) : memo_(w.cuts.face_shares) {
        if (memo_.size() > kFaceShareMemoEntries) memo_.clear();
    }

    bool share(const World& w, const std::vector<Fragment>& frags, EdgeParts& parts, int a, int b,
               const std::array<int, 3>& face) {
        const FaceShareKey key{id(frags[a]), mask(w, frags[a]), id(frags[b]), mask(w, frags[b]), face[0], face[1], face[2]};
        const auto [it, fresh] = memo_.try_emplace(key, 0);
        if (fresh) it->second = share_face(w, frags, parts, a, b, face) ? 1 : 0;  // share_face reads no memo
        return it->second != 0;
    }

    FirstLines& firsts() { return firsts_; }

private:
    static int id(const Fragment& f) { return f.ve >= 0 ? f.ve : -1 - f.element; }
    static int mask(const World& w, const Fragment& f) { return f.ve >= 0 ? static_cast<int>(w.virtual_elements.mask[f.ve]) : 0; }
    std::unordered_map<FaceShareKey, uint8_t, FaceShareHash>& memo_;
    FirstLines firsts_;
};

/// Whether fragment f holds mesh node j's own material: a whole element, the side j is on, or the
/// fragment of an element cut again that j lies in.
bool holds_node(const World& w, const Fragment& f, int j) {
    if (f.side == 0) return true;
    if (!has_lines(w, f)) return f.side == w.enriched.sign[j];
    return fragment_holds(w, w.cuts.cut_of_element[f.element], f.ve, w.nodes.rest[j]);
}

/// Where fragment f's virtual element keeps its vertex for the node: its force element's corner, or
/// a mid-edge node in its quadratic entry (systems/cut/quadratic_enrichment.h).
template <class W>
auto& vertex_of(W& w, const Fragment& f) {
    const int ve = virtual_of(w, f);
    return f.slot < 4 ? w.elements.nodes[ve][f.slot] : w.quadratic.nodes[w.quadratic.of_element[ve]][f.slot];
}

/// The DOF node fragment f uses for the node now.
int dof_of(const World& w, const Fragment& f, int j) { return f.side == 0 ? j : vertex_of(w, f); }

/// A phantom of mesh node j, starting from DOF node `from`'s position and velocity (its last
/// velocity increment, the solver's warm start, follows once per batch: extend_warm_start): the
/// material it holds was at `from` until now.
int add_phantom(World& w, int j, int from) {
    Nodes& n = w.nodes;
    const int p = n.count();
    n.rest.push_back(n.rest[j]);
    n.position.push_back(n.position[from]);
    n.velocity.push_back(n.velocity[from]);
    n.mass.push_back(0.0);
    n.fixed.push_back(n.fixed[j]);
    if (w.enriched.phantom[j] < 0) w.enriched.phantom[j] = p;
    w.enriched.node_of_phantom.push_back(j);
    w.enriched.phantom_from.push_back(from);
    return p;
}

/// The solver's warm start (ForceState::last_dv) for the phantoms from DOF node `first` on, each
/// its source's, once for a batch: resized per phantom, it was copied whole each time (a megabyte
/// at 200k tets). Only where it held every node before them, as the solver then reads it.
void extend_warm_start(World& w, int first) {
    Eigen::VectorXd& dv = w.forces.last_dv;
    const int count = w.nodes.count();
    if (count == first || dv.size() != 3 * first) return;
    dv.conservativeResize(3 * count);
    for (int p = first; p < count; ++p) dv.segment<3>(3 * p) = dv.segment<3>(3 * w.enriched.phantom_from[p - w.mesh_nodes]);
}

/// The fragments around mesh node j, in incidence order (a cut element's side +1 before -1).
/// A mid-edge node's fragments come from the quadratic incidence (its mesh entries; entry: element
/// * 16 + local node), a corner's from the mesh incidence (element * 4 + local node).
std::vector<Fragment> fragments_around(const World& w, int j) {
    std::vector<Fragment> frags;
    const bool mid = is_edge_node(w, j);
    const Incidence& inc = mid ? w.quadratic.incidence : w.incidence;
    for (int p = inc.offset[j]; p < inc.offset[j + 1]; ++p) {
        const int e = mid ? w.quadratic.element[inc.entry[p] >> 4] : inc.entry[p] >> 2;
        const auto slot = static_cast<int8_t>(mid ? inc.entry[p] & 15 : inc.entry[p] & 3);
        if (e >= w.mesh_elements) continue;
        const int c = w.cuts.cut_of_element[e];
        if (c < 0) {
            frags.push_back({e, 0, slot, -1, 1});
            continue;
        }
        const std::span<const int> parts = fragments_of(w, c);
        for (size_t k = 0; k < parts.size(); ++k)
            frags.push_back({e, w.virtual_elements.side[parts[k]], slot, parts[k], k == 0 ? static_cast<int>(parts.size()) : 0});
    }
    return frags;
}

/// The union of fragments over the faces through the node their elements share, and the progressive
/// front's clause; returns each fragment's class (its smallest fragment index).
std::vector<int> material_classes(const World& w, const std::vector<Fragment>& frags, SharedFaces& shared) {
    const Elements& el = w.elements;
    const int npe = el.nodes_per_element();
    DisjointSets sets(static_cast<int>(frags.size()));
    EdgeParts parts(w, frags, shared.firsts());
    std::vector<FaceOf> faces;
    faces.reserve(frags.size() * 3);
    for (size_t f = 0; f < frags.size(); ++f) {
        if (frags[f].count == 0) continue;  // an element's first fragment stands for it
        const auto& nodes = el.nodes[frags[f].element];
        std::array<int, 2> on{};
        const int n_on = corners_of(frags[f].slot, on);
        for (int skip = 0; skip < npe; ++skip) {
            if (std::find(on.begin(), on.begin() + n_on, skip) != on.begin() + n_on) continue;  // faces through the node
            FaceOf face{{-1, -1, -1}, static_cast<int>(f)};
            for (int a = 0, n = 0; a < npe && n < 3; ++a)
                if (a != skip) face.nodes[n++] = nodes[a];
            std::sort(face.nodes.begin(), face.nodes.end());  // in 2D the third stays -1, first
            faces.push_back(face);
        }
    }
    std::sort(faces.begin(), faces.end());
    for (size_t k = 0; k + 1 < faces.size(); ++k) {
        if (faces[k].nodes != faces[k + 1].nodes) continue;
        const int fa = faces[k].fragment, fb = faces[k + 1].fragment;
        for (int a = fa; a < fa + frags[fa].count; ++a)
            for (int b = fb; b < fb + frags[fb].count; ++b) {
                const Fragment &A = frags[a], &B = frags[b];
                if (has_lines(w, A) || has_lines(w, B)) {  // an element cut again: by the parts of the face they hold
                    // (pairs already one material are not looked at: a union is the same in any order)
                    if (sets.find(a) != sets.find(b) && shared.share(w, frags, parts, a, b, faces[k].nodes)) sets.join(a, b);
                    continue;
                }
                if (A.side != 0 && B.side != 0 && A.side != B.side) continue;  // the cut's two sides
                if (on_face(w, A, faces[k].nodes) && on_face(w, B, faces[k].nodes)) sets.join(a, b);
            }
    }
    // The progressive front's clause: material joins across an element's split edge at a corner of
    // the node's that the blade has not crossed yet (a mid-edge node: at either of its corners).
    for (size_t f = 0; f + 1 < frags.size(); ++f) {
        if (frags[f].side != 1 || has_lines(w, frags[f])) continue;
        const auto& nodes = el.nodes[frags[f].element];
        std::array<int, 2> on{};
        const int n_on = corners_of(frags[f].slot, on);
        bool held = false;
        for (int k = 0; k < n_on && !held; ++k) {
            const int c = nodes[on[k]];
            for (int a = 0; a < npe && !held; ++a)
                held = nodes[a] != c && w.enriched.sign[nodes[a]] != w.enriched.sign[c] && !edge_crossed(w, c, nodes[a]);
        }
        if (held) sets.join(static_cast<int>(f), static_cast<int>(f + 1));
    }
    std::vector<int> cls(frags.size());
    for (size_t f = 0; f < frags.size(); ++f) cls[f] = sets.find(static_cast<int>(f));
    return cls;
}

/// assign_node_copies for one node.
void assign_copies_of(World& w, int j, SharedFaces& shared, std::vector<int>& changed) {
    const std::vector<Fragment> frags = fragments_around(w, j);
    const std::vector<int> cls = material_classes(w, frags, shared);
    int real = -1;  // the class of j's own material
    for (size_t f = 0; f < frags.size() && real < 0; ++f)
        if (holds_node(w, frags[f], j)) real = cls[f];
    std::vector<int> copy(frags.size(), -1);  // per class (its root): its DOF node
    std::vector<int> claimed;
    const int phantoms_before = w.nodes.count();
    if (real >= 0) copy[real] = j;
    uint8_t held = 0;
    for (size_t r = 0; r < frags.size(); ++r) {
        if (cls[r] != static_cast<int>(r) || copy[r] >= 0) continue;
        int keep = -1, from = j;  // the smallest phantom its fragments used, unclaimed; else the state's source
        for (size_t f = r; f < frags.size(); ++f) {
            if (cls[f] != static_cast<int>(r)) continue;
            const int d = dof_of(w, frags[f], j);
            if (d < w.mesh_nodes) continue;
            const bool taken = std::find(claimed.begin(), claimed.end(), d) != claimed.end();
            if (!taken && (keep < 0 || d < keep)) keep = d;
            if (from == j || d < from) from = d;
        }
        copy[r] = keep >= 0 ? keep : add_phantom(w, j, from);
        claimed.push_back(copy[r]);
    }
    // Material only divides as cuts are added (a split or a crossing never joins two classes), so no
    // phantom a fragment used is left without one: it would keep no mass and no stiffness.
    for (size_t f = 0; f < frags.size(); ++f) {
        const int d = dof_of(w, frags[f], j);
        if (d >= w.mesh_nodes && std::find(claimed.begin(), claimed.end(), d) == claimed.end())
            throw std::logic_error(fmt::format("node copies: phantom {} of node {} would hold no material (two parts "
                                               "of the material around the node joined)", d, j));
    }
    const bool grew = w.nodes.count() > phantoms_before;
    for (size_t f = 0; f < frags.size(); ++f) {
        if (frags[f].side == 0) continue;
        held |= cls[f] == real && !holds_node(w, frags[f], j);
        if (grew) changed.push_back(w.cuts.cut_of_element[frags[f].element]);
        int& vertex = vertex_of(w, frags[f]);
        if (vertex == copy[cls[f]]) continue;
        vertex = copy[cls[f]];
        changed.push_back(w.cuts.cut_of_element[frags[f].element]);
    }
    w.enriched.front_fixed[j] = held;
}

}  // namespace

void assign_node_copies(World& w, const std::vector<int>& nodes, std::vector<int>& changed) {
    SharedFaces shared(w);
    const int first = w.nodes.count();
    for (int j : nodes) assign_copies_of(w, j, shared, changed);
    extend_warm_start(w, first);
}

}  // namespace xcut
