// The visual surface slit inside the whole elements the crack behind a straight front runs through
// (3D; systems/surface/surface_tips.h). A front's elements are not split: the semi-progressive
// front splits an element once the blade has crossed it (paper §3.3), and the element the front
// runs through is never split while it lies there. The front's functions open the crack in them
// all the same (the jump of √r sin(θ/2) across θ = ±π behind the front), so a surface mapped over
// their nodes alone would stretch its triangles over the opening. Each such element shows instead:
//  - its section by the crack: the front's plane behind the front's line inside the element, a
//    convex polygon over where the crack crosses its edges and where the front's line enters and
//    leaves it, once per lip as a wall facing the other lip (the lips meet on the front's line);
//  - its skin faces the crack crosses, fanned from where the front's line pierces them (one vertex
//    for both lips) or from the middle of the crack's chord across them (one per lip, shared with
//    the walls), each triangle on the side of the crack's ray it lies on, counted round the fan.
// The points on the edges are the crack's own where a split element round the edge has one (its
// skin's and its walls' vertex there, held by the whole element until now, is replaced by the two
// lips' vertices in the triangles beside it, each by the side of its split element), else where
// the front's plane crosses the edge. An edge crossing is made once per lip where every element round the edge is split or
// slit, else once (the lips meet there: the zone's end, as in 2D). The slit elements are found from
// those the front's line runs through, across the faces their sections cross, to the split
// elements behind or the zone's end. Every point is placed by the enriched field of its lip
// (front_enrichment). A front whose slit would leave the surface open (an edge of a new vertex not
// used once each way, a wall's edge the surface has already, a triangle without area), or whose
// section touches a corner or an edge of its element or crosses a face once or three times (the
// wound's points and the straight front disagree), is not slit that step, and is counted
// (SurfaceMesh::front_slits_refused): its vertices keep the field, the surface its pieces.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>

#include "engine/fragment_geometry.h"
#include "systems/kernels/front_enrichment.h"
#include "systems/surface/surface_arrays.h"
#include "systems/surface/surface_cut_parts.h"
#include "systems/xfem_queries.h"

namespace xcut::surface_cut_detail {
namespace {

/// Where the crack crosses a mesh edge lo < hi: its rest point, the vertex of the surface there
/// (-1: none) and its vertex on each lip (+1, -1; one vertex where the lips meet).
struct EdgePoint {
    int lo, hi, element;
    Vec3 X;
    int replaced = -1;
    std::array<int, 2> lip{-1, -1};
    int on(int lip_sign) const { return lip[lip_sign > 0 ? 0 : 1]; }
};

/// A point on a face (its nodes, sorted): where the front's line pierces it (one vertex for both
/// lips), or the middle of the crack's chord across a skin face (`parted`: one vertex per lip),
/// which the skin's fan and the walls share.
struct FacePoint {
    std::array<int, 3> face;
    int element;
    Vec3 X;
    bool parted = false;
    std::array<int, 2> vertex{-1, -1};
    int on(int lip_sign) const { return vertex[lip_sign > 0 ? 0 : 1]; }
};

/// A slit element: its section's corners in order round it (an edge point k, or -1 - k for face
/// point k).
struct Section {
    int e;
    std::vector<int> corners;
};

constexpr double kDegenerate = 1e-6;  // [-] of an element's size: a section this near a corner or an edge is not slit

class FrontSlit {
public:
    FrontSlit(World& w, SurfaceMesh& s, const ZoneIndex& zi, int tip) : w_(w), s_(s), zi_(zi), tip_(tip) {
        const CrackTips& ct = w.tips;
        f_ = FrontFrame{ct.point[tip], ct.direction[tip], ct.tangent[tip]};
        n_ = f_.normal();
    }

    /// Finds the slit elements and their sections: 1, 0 where the front runs through no whole
    /// element, -1 where a section touches a corner or an edge or is not a polygon over faces.
    int find() {
        std::vector<int> queue;
        for (int z = 0; z < w_.tips.zone(); ++z) {
            const int e = w_.tips.element[z];
            if (tip_of(z) != tip_ || e >= w_.mesh_elements || is_cut(w_, e) || in_set(e)) continue;
            std::array<double, 2> s{};
            std::array<int, 2> face{};
            const int pierced = pierce(e, s, face);
            if (pierced < 0) return -1;
            if (pierced == 0) continue;
            slit_.emplace(e, -1);
            queue.push_back(e);
        }
        for (size_t q = 0; q < queue.size(); ++q) {
            const int e = queue[q];
            Section sec{e, {}};
            if (!section(e, sec.corners)) return -1;
            slit_[e] = static_cast<int>(sections_.size());
            sections_.push_back(sec);
            for (int o = 0; o < 4; ++o) {  // across the faces the section crosses
                if (on_face_count(sec, e, o) == 0) continue;
                const int g = element_across(w_, e, o);
                if (g >= 0 && !is_cut(w_, g) && !in_set(g) && in_zone(g)) slit_.emplace(g, -1), queue.push_back(g);
            }
        }
        return sections_.empty() ? 0 : 1;
    }

    /// Makes the vertices and triangles into `tris`/`owner`, the rewired triangles into `rewire`
    /// ((triangle, slot, vertex)), and the hidden pieces into `hidden`; false where the result
    /// would leave the surface open.
    bool build(const std::vector<uint8_t>& hidden_before, std::vector<std::array<int, 3>>& tris, std::vector<int>& owner,
               std::vector<uint8_t>& walls, std::vector<std::array<int, 3>>& rewire, std::vector<int>& hide) {
        first_vertex_ = s_.vertex_count();
        for (EdgePoint& p : edges_) {
            bool parted = true;
            for_elements_around(w_, p.lo, p.hi, [&](int f) { parted = parted && (is_cut(w_, f) || in_set(f)); });
            if (parted) {
                for (int lip : {1, -1}) p.lip[lip > 0 ? 0 : 1] = place(p.element, p.X, lip);
            } else {
                p.lip.fill(p.replaced >= 0 ? p.replaced : place(p.element, p.X, 0));
                p.replaced = -1;
            }
        }
        for (FacePoint& p : faces_) {
            if (p.parted) for (int lip : {1, -1}) p.vertex[lip > 0 ? 0 : 1] = place(p.element, p.X, lip);
            else p.vertex.fill(place(p.element, p.X, 0));
        }
        for (const EdgePoint& p : edges_)
            if (p.lip[0] == p.lip[1] && p.lip[0] >= first_vertex_) split_beside(p, hidden_before, tris, owner, walls, hide);
        for (const Section& sec : sections_) {
            add_walls(sec, tris, owner, walls);
            for (int o = 0; o < 4; ++o)
                if (element_across(w_, sec.e, o) < 0 && on_face_count(sec, sec.e, o) > 0 &&
                    !fan_skin_face(sec, o, tris, owner, walls, hide))
                    return false;
        }
        // The triangles beside a replaced vertex take its lip's vertex: pieces of the elements
        // round its edge (a point inside an edge lies in no other element).
        std::vector<uint8_t> hidden = hidden_before;
        hidden.resize(s_.triangles.size(), 0);
        for (int t : hide) hidden[t] = 1;
        for (const EdgePoint& p : edges_) {
            if (p.replaced < 0) continue;
            for_elements_around(w_, p.lo, p.hi, [&](int f) {
                for (int t : s_.pieces_of[f]) {
                    if (hidden[t]) continue;
                    for (int slot = 0; slot < 3; ++slot)
                        if (s_.triangles[t][slot] == p.replaced) rewire.push_back({t, slot, p.on(lip_of_triangle(t))});
                }
            });
        }
        return closed(tris, walls, rewire, hidden);
    }

    int elements() const { return static_cast<int>(sections_.size()); }

private:
    int tip_of(int z) const { return w_.tips.tip[w_.tips.function[w_.tips.first[z]] / 4]; }
    bool in_set(int e) const { return slit_.count(e) > 0; }
    bool in_zone(int e) const {
        for (int z = zi_.head[e]; z >= 0; z = zi_.next[z])
            if (tip_of(z) == tip_) return true;
        return false;
    }
    Vec3 corner(int e, int a) const { return w_.nodes.rest[w_.elements.nodes[e][a]]; }
    double size(int e) const {
        double h = 0.0;
        for (int a = 0; a < 4; ++a)
            for (int b = a + 1; b < 4; ++b) h = std::max(h, (corner(e, a) - corner(e, b)).norm());
        return h;
    }
    std::array<int, 3> face_nodes(int e, int o) const {
        std::array<int, 3> f{};
        for (int a = 0, m = 0; a < 4; ++a)
            if (a != o) f[m++] = w_.elements.nodes[e][a];
        std::sort(f.begin(), f.end());
        return f;
    }
    int lip_of(const Vec3& X) const { return (X - f_.point).dot(n_) >= 0.0 ? 1 : -1; }

    /// Where the front's line runs through e: 1 (parameters s and faces of its entry and exit), 0
    /// (it does not), -1 (through an edge or a corner: not slit).
    int pierce(int e, std::array<double, 2>& s, std::array<int, 2>& face) const {
        const double h = size(e);
        std::array<Vec3, 4> in;  // each face's unit normal toward the element's inside
        for (int o = 0; o < 4; ++o) {
            const Vec3 a = corner(e, (o + 1) % 4), b = corner(e, (o + 2) % 4), c = corner(e, (o + 3) % 4);
            in[o] = (b - a).cross(c - a).normalized();
            if (in[o].dot(corner(e, o) - a) < 0.0) in[o] = -in[o];
        }
        const auto height = [&](int o, const Vec3& X) { return in[o].dot(X - corner(e, (o + 1) % 4)); };
        double lo = -1e300, hi = 1e300;
        for (int o = 0; o < 4; ++o) {
            const double at = height(o, f_.point), rate = in[o].dot(f_.tangent);
            if (std::abs(rate) < 1e-12) {
                if (at < 0.0) return 0;
                continue;
            }
            const double t = -at / rate;
            if (rate > 0.0 && t > lo) lo = t, face[0] = o;
            if (rate < 0.0 && t < hi) hi = t, face[1] = o;
        }
        if (hi - lo <= kDegenerate * h) return hi - lo < -kDegenerate * h ? 0 : -1;
        s = {lo, hi};
        for (int k = 0; k < 2; ++k)  // the line meets another face there too: an edge or a corner
            for (int o = 0; o < 4; ++o)
                if (o != face[k] && std::abs(height(o, f_.point + s[k] * f_.tangent)) < kDegenerate * h) return -1;
        return 1;
    }

    /// The edge point of mesh edge a-b (index), -1 if the crack behind the front does not cross it,
    /// -2 if it crosses it at a node or on the front's line (not slit).
    int edge_point(int e, int a, int b) {
        const int lo = std::min(a, b), hi = std::max(a, b);
        if (const auto it = edge_index_.find({lo, hi}); it != edge_index_.end()) return it->second;
        const Vec3 &Xl = w_.nodes.rest[lo], &Xh = w_.nodes.rest[hi];
        const double h = (Xh - Xl).norm();
        int index = -1, replaced = -1;
        Vec3 X;
        if (const double t = edge_crossing(w_, lo, hi); t > 0.0 && t < 1.0) {  // a split element's crack point
            X = Xl + t * (Xh - Xl);
            if (const auto v = s_.cut_point.find({0, lo, hi, 0}); v != s_.cut_point.end()) replaced = v->second;
            index = 0;
        } else {
            const double dl = n_.dot(Xl - f_.point), dh = n_.dot(Xh - f_.point);
            if (std::abs(dl) < kDegenerate * h || std::abs(dh) < kDegenerate * h) {  // a node on the plane: on the crack, not slit
                const Vec3& Xn = std::abs(dl) < kDegenerate * h ? Xl : Xh;
                index = (Xn - f_.point).dot(f_.direction) < 0.0 ? -2 : -1;
            } else if ((dl < 0.0) != (dh < 0.0)) {
                X = Xl + dl / (dl - dh) * (Xh - Xl), index = 0;
            }
        }
        if (index == 0) {
            const double ahead = (X - f_.point).dot(f_.direction);
            if (std::abs(ahead) < kDegenerate * h) index = -2;
            else if (ahead > 0.0) index = -1;
            else index = static_cast<int>(edges_.size()), edges_.push_back({lo, hi, e, X, replaced, {}});
        }
        edge_index_.emplace(std::make_pair(lo, hi), index);
        return index;
    }

    /// The face point on face o of e (index): where the front's line pierces it, or (`parted`) the
    /// middle of the crack's chord across it.
    int face_point(int e, int o, const Vec3& X, bool parted) {
        const std::array<int, 3> key = face_nodes(e, o);
        for (size_t k = 0; k < faces_.size(); ++k)
            if (faces_[k].face == key) return static_cast<int>(k);
        faces_.push_back({key, e, X, parted, {-1, -1}});
        return static_cast<int>(faces_.size()) - 1;
    }

    Vec3 point_of(int c) const { return c >= 0 ? edges_[c].X : faces_[-1 - c].X; }
    /// Whether section corner c lies on face o of e.
    bool on_face(int c, int e, int o) const {
        const int node = w_.elements.nodes[e][o];
        if (c >= 0) return edges_[c].lo != node && edges_[c].hi != node;
        return faces_[-1 - c].face == face_nodes(e, o);
    }
    int on_face_count(const Section& sec, int e, int o) const {
        return static_cast<int>(std::count_if(sec.corners.begin(), sec.corners.end(), [&](int c) { return on_face(c, e, o); }));
    }

    /// E's section by the crack behind the front, ordered round it; false where it touches a
    /// corner or an edge, or is not a polygon whose sides each lie on one face.
    bool section(int e, std::vector<int>& corners) {
        std::array<double, 2> s{};
        std::array<int, 2> face{};
        const int pierced = pierce(e, s, face);
        if (pierced < 0) return false;
        for (int k = 0; k < 6; ++k) {
            const int p = edge_point(e, w_.elements.nodes[e][kTetEdges[k][0]], w_.elements.nodes[e][kTetEdges[k][1]]);
            if (p == -2) return false;
            if (p >= 0) corners.push_back(p);
        }
        for (int k = 0; k < 2 && pierced == 1; ++k) corners.push_back(-1 - face_point(e, face[k], f_.point + s[k] * f_.tangent, false));
        if (corners.size() < 3) return false;
        Vec3 centre = Vec3::Zero();
        for (int c : corners) centre += point_of(c) / static_cast<double>(corners.size());
        const auto angle = [&](int c) {
            const Vec3 r = point_of(c) - centre;
            return std::atan2(r.dot(f_.tangent), r.dot(f_.direction));
        };
        std::sort(corners.begin(), corners.end(), [&](int a, int b) { return angle(a) < angle(b); });
        for (int o = 0; o < 4; ++o) {
            const int on = on_face_count({e, corners}, e, o);
            if (on != 0 && on != 2) return false;
        }
        for (size_t k = 0; k < corners.size(); ++k) {
            bool shared = corners[k] < 0 && corners[(k + 1) % corners.size()] < 0;  // the front's line, inside e
            for (int o = 0; o < 4; ++o) shared = shared || (on_face(corners[k], e, o) && on_face(corners[(k + 1) % corners.size()], e, o));
            if (!shared) return false;
        }
        // A skin face the crack crosses from edge to edge: the chord's middle, on both the skin's
        // fan and the walls (so the walls' side there is the skin's two halves of it).
        for (size_t k = 0; k < corners.size(); ++k) {
            const int a = corners[k], b = corners[(k + 1) % corners.size()];
            for (int o = 0; o < 4 && a >= 0 && b >= 0; ++o)
                if (on_face(a, e, o) && on_face(b, e, o) && element_across(w_, e, o) < 0) {
                    corners.insert(corners.begin() + static_cast<std::ptrdiff_t>(k) + 1, -1 - face_point(e, o, 0.5 * (edges_[a].X + edges_[b].X), true));
                    ++k;
                    break;
                }
        }
        return true;
    }

    /// A vertex at rest point X of whole element e, placed by the enriched field on lip `lip` (0:
    /// on the front's line, where the lips meet).
    int place(int e, const Vec3& X, int lip) {
        const Eigen::Vector4d L = tet_barycentric(rest_corners(w_, e), X);
        Vec3 x = Vec3::Zero();
        for (int a = 0; a < 4; ++a) x += L[a] * w_.nodes.position[w_.elements.nodes[e][a]];
        for (int z = zi_.head[e]; z >= 0; z = zi_.next[z]) x += front_enrichment(w_, w_.tips.amplitude, z, X, L, tip_of(z) == tip_ ? lip : 0);
        s_.position.push_back(x);
        s_.element.push_back(e);
        s_.bary.push_back(L);
        s_.side.push_back(0);
        return s_.vertex_count() - 1;
    }

    /// The section's two walls: the + lip's facing -n (toward the other lip), the - lip's facing n,
    /// fanned from a point on the front's line where there is one.
    void add_walls(const Section& sec, std::vector<std::array<int, 3>>& tris, std::vector<int>& owner, std::vector<uint8_t>& walls) {
        std::vector<int> c = sec.corners;
        const auto front = std::find_if(c.begin(), c.end(), [&](int k) { return k < 0 && !faces_[-1 - k].parted; });
        Vec3 area = Vec3::Zero(), centre = Vec3::Zero();
        for (size_t k = 0; k < c.size(); ++k) {
            area += point_of(c[k]).cross(point_of(c[(k + 1) % c.size()]));
            centre += point_of(c[k]) / static_cast<double>(c.size());
        }
        std::array<int, 2> hub{-1, -1};  // no point on the front's line: a fan from the centre, one per lip
        if (front != c.end()) std::rotate(c.begin(), front, c.end());
        else for (int lip : {1, -1}) hub[lip > 0 ? 0 : 1] = place(sec.e, centre, lip);
        const auto shared = [&](int k) { return k >= 0 ? edges_[k].lip[0] == edges_[k].lip[1] : !faces_[-1 - k].parted; };
        for (int lip : {1, -1}) {
            const auto v = [&](int k) { return k >= 0 ? edges_[k].on(lip) : faces_[-1 - k].on(lip); };
            const bool flip = (area.dot(n_) > 0.0) == (lip > 0);  // the + lip's wall faces -n
            const auto add = [&](int a, int b, int d) {
                tris.push_back(flip ? std::array<int, 3>{a, d, b} : std::array<int, 3>{a, b, d});
                owner.push_back(sec.e), walls.push_back(1);
            };
            const int h = hub[lip > 0 ? 0 : 1];
            if (h >= 0) {
                for (size_t k = 0; k < c.size(); ++k) add(h, v(c[k]), v(c[(k + 1) % c.size()]));
            } else {
                for (size_t k = 1; k + 1 < c.size(); ++k)  // a triangle whose corners are each one vertex of both lips: none
                    if (!(shared(c[0]) && shared(c[k]) && shared(c[k + 1]))) add(v(c[0]), v(c[k]), v(c[k + 1]));
            }
        }
    }

    /// Skin face o of the section's element as a fan over its vertices on the face's edges and the
    /// crack's points there; its pieces hidden. False where the face's pieces cannot be fanned.
    bool fan_skin_face(const Section& sec, int o, std::vector<std::array<int, 3>>& tris, std::vector<int>& owner,
                       std::vector<uint8_t>& walls, std::vector<int>& hide) {
        const int e = sec.e;
        std::vector<int> pieces, rim;
        Vec3 normal = Vec3::Zero();
        for (int t : s_.pieces_of[e]) {
            const auto& tri = s_.tip_saved_triangles[t];
            std::array<Eigen::Vector4d, 3> L;
            bool on = true;
            for (int k = 0; k < 3; ++k) {
                L[k] = local_bary(w_, s_, e, tri[k]);
                on = on && std::abs(L[k][o]) < 1e-9;
            }
            if (!on) continue;
            pieces.push_back(t);
            const Vec3 a = vertex_rest(w_, s_, tri[0]);
            normal += (vertex_rest(w_, s_, tri[1]) - a).cross(vertex_rest(w_, s_, tri[2]) - a);
            for (int k = 0; k < 3; ++k)
                if ((L[k].array().abs() < 1e-9).count() >= 2) rim.push_back(tri[k]);
        }
        if (pieces.empty()) return true;  // no skin drawn there
        std::sort(rim.begin(), rim.end());
        rim.erase(std::unique(rim.begin(), rim.end()), rim.end());
        int centre = 0;  // the face point (-1 - k): where the front pierces the face, or the chord's middle
        std::vector<int> chord;
        for (int c : sec.corners) {
            if (!on_face(c, e, o)) continue;
            if (c < 0) {
                centre = c;
                continue;
            }
            chord.push_back(c);
            const double h = size(e);
            rim.erase(std::remove_if(rim.begin(), rim.end(), [&](int v) { return v == edges_[c].replaced || (vertex_rest(w_, s_, v) - edges_[c].X).norm() < 1e-9 * h; }),
                      rim.end());
        }
        if (centre == 0 || chord.size() != (faces_[-1 - centre].parted ? 2u : 1u)) return false;
        std::vector<int> items;  // surface vertices, or -1 - k for edge point k
        for (int v : rim) items.push_back(v);
        for (int c : chord) items.push_back(-1 - c);
        const auto at = [&](int q) { return q >= 0 ? vertex_rest(w_, s_, q) : edges_[-1 - q].X; };
        const Vec3 middle = faces_[-1 - centre].X;
        const std::array<int, 2> hub = faces_[-1 - centre].vertex;
        const Vec3 ex = (at(items[0]) - middle).normalized(), ey = normal.normalized().cross(ex);
        const auto angle = [&](int q) {
            const Vec3 r = at(q) - middle;
            return std::atan2(r.dot(ey), r.dot(ex));
        };
        std::sort(items.begin(), items.end(), [&](int a, int b) { return angle(a) < angle(b); });
        // Each triangle's lip: the rim runs counter-clockwise from a crossing; a triangle starting
        // at a crossing lies on the lip counter-clockwise of the crack's ray to it, one ending at
        // one on the lip clockwise of it, the others on their predecessor's (the hub's lips part
        // only across the crack).
        std::rotate(items.begin(), std::find_if(items.begin(), items.end(), [](int q) { return q < 0; }), items.end());
        const Vec3 up = normal.normalized();
        const auto ccw_lip = [&](int q) { return up.cross(at(q) - middle).dot(n_) >= 0.0 ? 1 : -1; };
        int lip = ccw_lip(items[0]);
        for (size_t k = 0; k < items.size(); ++k) {
            const int u = items[k], v = items[(k + 1) % items.size()];
            if (u < 0) lip = ccw_lip(u);
            else if (v < 0) lip = -ccw_lip(v);
            const auto pick = [&](int q) { return q >= 0 ? q : edges_[-1 - q].on(lip); };
            tris.push_back({hub[lip > 0 ? 0 : 1], pick(u), pick(v)});  // counter-clockwise about the outward normal
            owner.push_back(e), walls.push_back(0);
        }
        hide.insert(hide.end(), pieces.begin(), pieces.end());
        return true;
    }

    /// Where the lips meet at a point the surface did not have (the zone's end), the triangles of
    /// the elements round its edge that are not slit, along that edge across the point, are split
    /// there (as a whole element's skin at a crack-front point: surface_cut.cpp), so no edge ends
    /// at it midway.
    void split_beside(const EdgePoint& p, const std::vector<uint8_t>& hidden_before, std::vector<std::array<int, 3>>& tris,
                      std::vector<int>& owner, std::vector<uint8_t>& walls, std::vector<int>& hide) const {
        const Vec3 &Xl = w_.nodes.rest[p.lo], &Xh = w_.nodes.rest[p.hi];
        const double at = (p.X - Xl).dot(Xh - Xl) / (Xh - Xl).squaredNorm();
        for_elements_around(w_, p.lo, p.hi, [&](int f) {
            if (in_set(f)) return;
            for (int t : s_.pieces_of[f]) {
                if ((t < static_cast<int>(hidden_before.size()) && hidden_before[t]) || std::count(hide.begin(), hide.end(), t)) continue;
                const auto& tri = s_.triangles[t];
                for (int k = 0; k < 3; ++k) {
                    const auto along = [&](int v) {  // the vertex's place along lo -> hi, -1 off the edge
                        const Vec3 X = vertex_rest(w_, s_, v);
                        const double u = (X - Xl).dot(Xh - Xl) / (Xh - Xl).squaredNorm();
                        return (X - Xl - u * (Xh - Xl)).norm() < 1e-9 * (Xh - Xl).norm() ? u : -1.0;
                    };
                    const double ua = along(tri[k]), ub = along(tri[(k + 1) % 3]);
                    if (ua < 0.0 || ub < 0.0 || (ua - at) * (ub - at) >= 0.0) continue;
                    const int a = tri[k], b = tri[(k + 1) % 3], c = tri[(k + 2) % 3], v = p.lip[0];
                    tris.push_back({a, v, c}), tris.push_back({v, b, c});
                    owner.push_back(s_.triangle_owner[t]), owner.push_back(s_.triangle_owner[t]);
                    walls.push_back(s_.cut_face[t]), walls.push_back(s_.cut_face[t]);
                    hide.push_back(t);
                    break;
                }
            }
        });
    }

    /// The lip of visible triangle t of the surface: in a split element, the lip its side of the
    /// cut faces (a vertex bound to a side says which: the crack's points there lie off the front's
    /// plane by more than the skin's vertices beside them may); else a wall's by the way it faces,
    /// a skin piece's by its corner farthest from the crack's plane.
    int lip_of_triangle(int t) const {
        const auto& tri = s_.triangles[t];
        const int owner = s_.triangle_owner[t];
        if (owner >= 0 && owner < w_.mesh_elements && is_cut(w_, owner)) {
            Vec3 plus = Vec3::Zero(), minus = Vec3::Zero();
            int n_plus = 0, n_minus = 0;
            for (int a = 0; a < 4; ++a) {
                const int node = w_.elements.nodes[owner][a], H = w_.enriched.sign[node];
                (H > 0 ? plus : minus) += w_.nodes.rest[node], (H > 0 ? n_plus : n_minus) += H != 0;
            }
            for (int v : tri)
                if (s_.side[v] != 0 && n_plus > 0 && n_minus > 0)
                    return s_.side[v] * ((plus / n_plus - minus / n_minus).dot(n_) >= 0.0 ? 1 : -1);
        }
        const Vec3 a = vertex_rest(w_, s_, tri[0]), b = vertex_rest(w_, s_, tri[1]), c = vertex_rest(w_, s_, tri[2]);
        if (s_.cut_face[t]) return (b - a).cross(c - a).dot(n_) < 0.0 ? 1 : -1;
        Vec3 far = a;
        for (const Vec3* X : {&b, &c})
            if (std::abs((*X - f_.point).dot(n_)) > std::abs((far - f_.point).dot(n_))) far = *X;
        return lip_of(far);
    }

    /// Whether every edge at a new vertex is used once each way by the new and rewired triangles, a
    /// wall's edge between two vertices the surface had (the lips meet at both) is not one of the
    /// surface's already, and no new triangle lacks area.
    bool closed(const std::vector<std::array<int, 3>>& tris, const std::vector<uint8_t>& walls,
                const std::vector<std::array<int, 3>>& rewire, const std::vector<uint8_t>& hidden) const {
        std::vector<std::array<int, 3>> all = tris;
        std::vector<std::array<int, 3>> order(rewire.begin(), rewire.end());  // by triangle
        std::sort(order.begin(), order.end());
        std::vector<int> changed;
        for (size_t k = 0; k < order.size(); ++k) {
            if (k == 0 || order[k][0] != order[k - 1][0]) all.push_back(s_.triangles[order[k][0]]), changed.push_back(order[k][0]);
            all.back()[order[k][1]] = order[k][2];
        }
        // Each directed edge at a new vertex as one key; equal keys are its uses.
        const auto key = [](int a, int b) { return static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32 | static_cast<uint32_t>(b); };
        std::vector<uint64_t> uses;
        std::vector<std::pair<int, int>> old_wall_edges;
        for (size_t q = 0; q < all.size(); ++q) {
            const auto& tri = all[q];
            for (int k = 0; k < 3; ++k) {
                const int a = tri[k], b = tri[(k + 1) % 3];
                if (a == b) return false;
                if (a >= first_vertex_ || b >= first_vertex_) uses.push_back(key(a, b));
                else if (q < walls.size() && walls[q]) old_wall_edges.push_back({std::min(a, b), std::max(a, b)});
            }
        }
        std::sort(uses.begin(), uses.end());
        for (size_t k = 0; k < uses.size(); ++k) {
            const uint64_t back = uses[k] << 32 | uses[k] >> 32;
            const auto range = std::equal_range(uses.begin(), uses.end(), back);
            if ((k + 1 < uses.size() && uses[k + 1] == uses[k]) || range.second - range.first != 1) return false;
        }
        for (const auto& edge : old_wall_edges) {  // a piece using it lies in an element round a's mesh edge
            const int a = edge.first, b = edge.second;
            const auto at = std::find_if(edges_.begin(), edges_.end(), [&](const EdgePoint& p) { return p.lip[0] == a || p.lip[0] == b; });
            if (at == edges_.end()) return false;
            bool used = false;
            for_elements_around(w_, at->lo, at->hi, [&](int f) {
                for (int t : s_.pieces_of[f]) {
                    if (hidden[t] || std::binary_search(changed.begin(), changed.end(), t)) continue;
                    const auto& tri = s_.triangles[t];
                    for (int k = 0; k < 3; ++k) used = used || (std::min(tri[k], tri[(k + 1) % 3]) == a && std::max(tri[k], tri[(k + 1) % 3]) == b);
                }
            });
            if (used) return false;
        }
        for (const auto& tri : tris) {
            const Vec3 a = s_.position[tri[0]], b = s_.position[tri[1]], c = s_.position[tri[2]];
            const double longest = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
            if (!((b - a).cross(c - a).norm() > 1e-12 * longest)) return false;
        }
        return true;
    }

    World& w_;
    SurfaceMesh& s_;
    const ZoneIndex& zi_;
    int tip_;
    FrontFrame f_;
    Vec3 n_;
    int first_vertex_ = 0;
    std::map<int, int> slit_;  // element -> section (-1 while queued)
    std::vector<Section> sections_;
    std::vector<EdgePoint> edges_;
    std::map<std::pair<int, int>, int> edge_index_;
    std::vector<FacePoint> faces_;
};

}  // namespace

int slit_fronts(World& w, SurfaceMesh& s, const ZoneIndex& zi, std::vector<uint8_t>& hidden) {
    int slit = 0;
    for (int tip = 0; tip < w.tips.count(); ++tip) {
        const int first_vertex = s.vertex_count();
        FrontSlit fs(w, s, zi, tip);
        std::vector<std::array<int, 3>> tris, rewire;
        std::vector<int> owner, hide;
        std::vector<uint8_t> walls;
        const int found = fs.find();
        if (found <= 0 || !fs.build(hidden, tris, owner, walls, rewire, hide)) {
            keep_vertices(s, static_cast<size_t>(first_vertex));
            s.front_slits_refused += found != 0;
            continue;
        }
        for (const auto& r : rewire) s.triangles[r[0]][r[1]] = r[2];
        for (int t : hide) hidden[t] = 1;
        for (size_t k = 0; k < tris.size(); ++k) {
            s.triangles.push_back(tris[k]);
            s.triangle_owner.push_back(owner[k]);
            s.cut_face.push_back(walls[k]);
        }
        slit += fs.elements();
    }
    return slit;
}

}  // namespace xcut::surface_cut_detail
