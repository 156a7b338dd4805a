#include "systems/surface/surface_tips.h"

#include <algorithm>
#include <cmath>

#include "engine/parallel.h"
#include "systems/surface/surface_arrays.h"
#include "systems/surface/surface_cut_parts.h"
#include "systems/xfem_queries.h"

namespace xcut {
namespace {

using namespace surface_cut_detail;

/// Barycentric coordinates of rest point X in mesh element e (a triangle).
Vec3 triangle_bary(const World& w, int e, const Vec2& X) { return tip_triangles::barycentric(tip_triangles::rest_triangle(w, e), X); }

/// A vertex of the overlay, bound to mesh element e at rest point X, placed at x.
int add_vertex(World& w, SurfaceMesh& s, int e, const Vec2& X, const Vec3& x) {
    const Vec3 L = triangle_bary(w, e, X);
    s.position.push_back(x);
    s.element.push_back(e);
    s.bary.emplace_back(L[0], L[1], L[2], 0.0);
    s.side.push_back(0);
    return s.vertex_count() - 1;
}

/// Where the crack behind a tip crosses a mesh edge: its rest point, its vertex on each lip (+1,
/// -1; one vertex where the lips meet), and the vertex of the surface it stands for (-1: none).
struct Crossing {
    int a, b;  ///< the edge's mesh nodes
    Vec2 X;
    std::array<int, 2> lip{-1, -1};
    int replaced = -1;
    int on(int lip_sign) const { return lip[lip_sign > 0 ? 0 : 1]; }
};

/// A whole element the crack runs through (or ends in), shown as a fan from `centre` (the tip, or
/// the middle of its chord) over its edges' vertices, the crossings made once per lip.
struct Slit {
    int e;
    Vec2 centre;
    std::array<int, 2> centre_lip{-1, -1};
    std::vector<int> crossings;
};

/// The overlay of one tip: the elements the crack runs through from the tip back to where the
/// surface already shows it (a cut point on the edge: the split elements behind), to the sheet's
/// border, or to the zone's edge (no functions beyond: the lips meet); each crossing on the
/// enriched field of its lip.
class TipOverlay {
public:
    TipOverlay(World& w, SurfaceMesh& s, const ZoneIndex& zi, int shown) : w_(w), s_(s), zi_(zi) {
        const CrackTips& ct = w.tips;
        tip_ = ct.shown_tip[shown];
        T_ = ct.point[tip_].head<2>(), d_ = ct.direction[tip_].head<2>();
        base_vertices_ = static_cast<int>(s.base_vertex_at.size());
    }

    /// Walks back from the tip's element e; false (nothing changed) where the crack meets a corner
    /// or the tip's element is another tip's (`hidden`: the pieces already laid over). Another
    /// tip's slit element ends the walk as the zone's edge does.
    bool walk(int e, const std::vector<uint8_t>& hidden) {
        const auto taken = [&](int f) {
            return std::any_of(s_.pieces_of[f].begin(), s_.pieces_of[f].end(), [&](int t) { return hidden[t] != 0; });
        };
        if (taken(e)) return false;
        Vec2 p = T_;
        int from = -1;
        for (int guard = 0; guard < 64; ++guard) {
            const auto& n = w_.elements.nodes[e];
            const std::array<Vec2, 3> X{w_.nodes.rest[n[0]].head<2>(), w_.nodes.rest[n[1]].head<2>(), w_.nodes.rest[n[2]].head<2>()};
            int edge = -1;
            Vec2 P;
            if (!ray_exit(X, p, -d_, from, edge, P)) return false;
            const int a = n[edge], b = n[(edge + 1) % 3];
            slits_.push_back({e, guard == 0 ? T_ : Vec2(0.5 * (p + P)), {}, {}});
            if (guard > 0) slits_.back().crossings.push_back(static_cast<int>(crossings_.size()) - 1);
            slits_.back().crossings.push_back(static_cast<int>(crossings_.size()));
            crossings_.push_back({a, b, P});
            Crossing& c = crossings_.back();
            // The surface's own point there: the cut point of a split element behind (where its
            // crack crosses the edge: the crossing moves onto it), or a skin vertex at P.
            c.replaced = crack_edge_param(w_, a, b) >= 0.0 ? cut_point_on(e, a, b, P) : -1;
            if (c.replaced >= 0) c.X = rest_2d(c.replaced);
            else c.replaced = vertex_at(e, P);
            int next = -1;
            for_elements_around(w_, a, b, [&](int f) { next = f != e ? f : next; });
            const bool cut_point = c.replaced >= base_vertices_;  // the split elements behind show the rest
            const bool slit_next = !cut_point && next >= 0 && !is_cut(w_, next) && zi_.head[next] >= 0 && !slit(next) && !taken(next);
            if (cut_point || next < 0 || slit_next) {
                for (int lip : {1, -1}) c.lip[lip > 0 ? 0 : 1] = place(e, c.X, lip);
            } else {  // beyond, no functions (or a split element whose crack is elsewhere): the lips meet
                c.lip.fill(c.replaced >= 0 ? c.replaced : place(e, c.X, 0));
                c.replaced = -1;
            }
            if (!slit_next) return true;
            from = -1, p = P, e = next;
            for (int k = 0; k < 3; ++k) {
                const int u = w_.elements.nodes[e][k], v = w_.elements.nodes[e][(k + 1) % 3];
                if ((u == a && v == b) || (u == b && v == a)) from = k;
            }
        }
        return false;
    }

    /// Lays the fans over the surface, hides the slit elements' pieces and gives the pieces beside a
    /// crossing the surface already had the vertex of their own lip.
    void lay(std::vector<uint8_t>& hidden) {
        for (Slit& sl : slits_) {
            if (&sl == &slits_.front()) {
                sl.centre_lip.fill(place(sl.e, sl.centre, 0));  // the tip: r = 0, where the lips meet
            } else {
                for (int lip : {1, -1}) sl.centre_lip[lip > 0 ? 0 : 1] = place(sl.e, sl.centre, lip);
            }
            fan(sl);
            for (int t : s_.pieces_of[sl.e]) hidden[t] = 1;
        }
        const Crossing& entry = crossings_.front();
        s_.tip_vertices.push_back({slits_.front().centre_lip[0], entry.on(1), entry.on(-1)});
        for (const Crossing& c : crossings_) {
            if (c.replaced < 0) continue;
            for (size_t t = 0; t < s_.triangles.size(); ++t) {
                if (t < hidden.size() && hidden[t]) continue;
                for (int& v : s_.triangles[t])
                    if (v == c.replaced) v = c.on(lip_of(rest_centre(s_.triangles[t])));
            }
        }
    }

private:
    int lip_of(const Vec2& X) const { return cross2(d_, X - T_) > 0.0 ? 1 : -1; }
    bool slit(int e) const {
        return std::any_of(slits_.begin(), slits_.end(), [&](const Slit& sl) { return sl.e == e; });
    }
    Vec2 rest_2d(int v) const { return vertex_rest(w_, s_, v).head<2>(); }
    Vec2 rest_centre(const std::array<int, 3>& t) const { return (rest_2d(t[0]) + rest_2d(t[1]) + rest_2d(t[2])) / 3.0; }
    /// A vertex at rest point X of element e, placed by the enriched field on lip `lip` (0: atan2).
    int place(int e, const Vec2& X, int lip) {
        return add_vertex(w_, s_, e, X, tip_field(w_, w_.tips.amplitude, e, X, triangle_bary(w_, e, X), tip_, lip));
    }
    /// Whether rest points X and Y of element e are one place (within 1e-9 of its size).
    bool same_place(int e, const Vec2& X, const Vec2& Y) const {
        return (X - Y).norm() <= 1e-9 * (w_.nodes.rest[w_.elements.nodes[e][1]] - w_.nodes.rest[w_.elements.nodes[e][0]]).norm();
    }
    /// The vertex of e's pieces at X, -1 if none.
    int vertex_at(int e, const Vec2& X) const {
        for (int t : s_.pieces_of[e])
            for (int v : s_.tip_saved_triangles[t])
                if (same_place(e, rest_2d(v), X)) return v;
        return -1;
    }
    /// The cut point (a vertex made by a cut) of e's pieces on mesh edge a-b nearest to X, -1 if none.
    int cut_point_on(int e, int a, int b, const Vec2& X) const {
        int k = 0;
        while (w_.elements.nodes[e][k] == a || w_.elements.nodes[e][k] == b) ++k;  // the corner off a-b
        int best = -1;
        for (int t : s_.pieces_of[e])
            for (int v : s_.tip_saved_triangles[t])
                if (v >= base_vertices_ && triangle_bary(w_, e, rest_2d(v))[k] <= 1e-9 &&
                    (best < 0 || (rest_2d(v) - X).norm() < (rest_2d(best) - X).norm()))
                    best = v;
        return best;
    }
    /// Sl's element as a fan from its centre over its edges' vertices, each triangle on one lip.
    void fan(const Slit& sl) {
        std::vector<int> rim;  // surface vertices, or -1 - j for crossing j
        double orient = 0.0;
        for (int t : s_.pieces_of[sl.e]) {
            const auto& tri = s_.tip_saved_triangles[t];
            if (orient == 0.0) orient = cross2(rest_2d(tri[1]) - rest_2d(tri[0]), rest_2d(tri[2]) - rest_2d(tri[0]));
            for (int v : tri)
                if (triangle_bary(w_, sl.e, rest_2d(v)).minCoeff() < 1e-9) rim.push_back(v);
        }
        std::sort(rim.begin(), rim.end());
        rim.erase(std::unique(rim.begin(), rim.end()), rim.end());
        for (int j : sl.crossings) {
            const Crossing& c = crossings_[j];
            rim.erase(std::remove_if(rim.begin(), rim.end(), [&](int v) { return v >= 0 && same_place(sl.e, rest_2d(v), c.X); }),
                      rim.end());
            rim.push_back(-1 - j);
        }
        const auto at = [&](int v) { return v < 0 ? crossings_[-1 - v].X : rest_2d(v); };
        std::sort(rim.begin(), rim.end(), [&](int u, int v) {
            const Vec2 ru = at(u) - sl.centre, rv = at(v) - sl.centre;
            return std::atan2(ru.y(), ru.x()) < std::atan2(rv.y(), rv.x());
        });
        for (size_t k = 0; k < rim.size(); ++k) {
            const int u = rim[k], v = rim[(k + 1) % rim.size()];
            const int lip = lip_of((sl.centre + at(u) + at(v)) / 3.0);
            const auto pick = [&](int q) { return q < 0 ? crossings_[-1 - q].on(lip) : q; };
            const int c = sl.centre_lip[lip > 0 ? 0 : 1];
            s_.triangles.push_back(orient > 0.0 ? std::array<int, 3>{c, pick(u), pick(v)} : std::array<int, 3>{c, pick(v), pick(u)});
            s_.triangle_owner.push_back(sl.e);
            s_.cut_face.push_back(0);
        }
    }

    World& w_;
    SurfaceMesh& s_;
    const ZoneIndex& zi_;
    int tip_ = -1, base_vertices_ = 0;
    Vec2 T_, d_;
    std::vector<Crossing> crossings_;
    std::vector<Slit> slits_;
};

}  // namespace

void take_off_tip_opening(SurfaceMesh& s) {
    if (s.tip_first_vertex < 0) return;
    s.triangles.swap(s.tip_saved_triangles);
    s.triangle_owner.swap(s.tip_saved_owner);
    s.cut_face.swap(s.tip_saved_cut_face);
    keep_vertices(s, static_cast<size_t>(s.tip_first_vertex));
    s.tip_first_vertex = -1;
    s.tip_vertices.clear();
}

void open_tips_on_surface(World& w, SurfaceMesh& s) {
    take_off_tip_opening(s);
    const CrackTips& ct = w.tips;
    if (ct.zone() == 0 || s.vertex_count() == 0 || ct.amplitude_step != w.step || ct.amplitude_version != ct.version)
        return;
    const ZoneIndex zi(w);
    if (w.elements.dim == 3) {  // the fronts' field on every vertex of the zone's elements, then the slits
        parallel_for(s.vertex_count(), [&](int v) {
            const int fe = s.element[v];
            if (zi.head[fe] < 0) return;
            const Vec3 X = vertex_rest(w, s, v);
            for (int z = zi.head[fe]; z >= 0; z = zi.next[z]) s.position[v] += front_enrichment(w, ct.amplitude, z, X, s.bary[v]);
        });
        s.tip_first_vertex = s.vertex_count();
        s.tip_saved_triangles = s.triangles, s.tip_saved_owner = s.triangle_owner, s.tip_saved_cut_face = s.cut_face;
        std::vector<uint8_t> hidden(s.triangles.size(), 0);
        s.front_slit_elements = slit_fronts(w, s, zi, hidden);
        drop_triangles(s, hidden);
        return;
    }
    if (ct.shown_step != w.step) return;
    for (int v = 0; v < s.vertex_count(); ++v) {  // the enriched field where the zone reaches
        const int fe = s.element[v];
        if (zi.head[fe] < 0) continue;
        const Vec2 X = vertex_rest(w, s, v).head<2>();
        for (int z = zi.head[fe]; z >= 0; z = zi.next[z])
            s.position[v] += tip_enrichment(w, ct.amplitude, z, X, s.bary[v].head<3>(), ct.lip[z]);
    }
    if (ct.shown_element.empty()) return;
    s.tip_first_vertex = s.vertex_count();
    s.tip_saved_triangles = s.triangles, s.tip_saved_owner = s.triangle_owner, s.tip_saved_cut_face = s.cut_face;
    std::vector<uint8_t> hidden(s.triangles.size(), 0);
    for (size_t i = 0; i < ct.shown_element.size(); ++i) {
        TipOverlay overlay(w, s, zi, static_cast<int>(i));
        const int first_vertex = s.vertex_count();
        if (overlay.walk(ct.shown_element[i], hidden)) {
            overlay.lay(hidden);
        } else {  // the crack meets a corner: the element shown whole
            keep_vertices(s, static_cast<size_t>(first_vertex));
        }
    }
    drop_triangles(s, hidden);  // the tips' elements' own pieces go; the fans stay
}

}  // namespace xcut
