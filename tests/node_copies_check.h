#pragma once
// Material connectivity around a node, computed from scratch for the tests (the virtual node
// algorithm's rule, Molino, Bao & Fedkiw 2004), against the copies the EnrichmentSystem keeps
// incrementally (systems/cut/node_copies.cpp). Used by NodeCopies.* and the stress suite's
// multi-blade tests.
#include <numeric>
#include <string>
#include <vector>

#include "components/cut_elements.h"
#include "engine/world.h"
#include "systems/xfem_queries.h"

namespace xcut::testing {

/// One fragment of an element around a node: side 0 a whole element, else the cut element's side.
struct Fragment {
    int element, side;
};

inline int find(std::vector<int>& parent, int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
}

/// Whether fragment f has material on the face `face` (mesh nodes): a whole element everywhere, a
/// cut element's side where one of the face's nodes is on that side.
inline bool on_face(const World& w, const Fragment& f, const std::vector<int>& face) {
    if (f.side == 0) return true;
    for (int n : face)
        if (w.enriched.sign[n] == f.side) return true;
    return false;
}

/// The DOF node fragment f uses for mesh node j.
inline int dof_of(const World& w, const Fragment& f, int j) {
    if (f.side == 0) return j;
    const int c = w.cuts.cut_of_element[f.element];
    const int ve = w.virtual_elements.element[w.cuts.virtual_element[c][f.side > 0 ? 0 : 1]];
    const auto& mesh = w.elements.nodes[f.element];
    for (int a = 0; a < w.elements.nodes_per_element(); ++a)
        if (mesh[a] == j) return w.elements.nodes[ve][a];
    return -1;
}

/// Fragments around node j whose copy of j the engine and connectivity disagree on: pairs in one
/// class with different DOFs, or in two classes with one DOF.
inline int disagreements(const World& w, int j, std::string& first) {
    const Elements& el = w.elements;
    const int npe = el.nodes_per_element();
    std::vector<Fragment> frags;
    for (int p = w.incidence.offset[j]; p < w.incidence.offset[j + 1]; ++p) {
        const int e = w.incidence.entry[p] >> 2;
        if (e >= w.mesh_elements) continue;
        if (w.cuts.cut_of_element[e] < 0) frags.push_back({e, 0});
        else frags.push_back({e, 1}), frags.push_back({e, -1});
    }
    std::vector<int> parent(frags.size());
    std::iota(parent.begin(), parent.end(), 0);
    for (size_t a = 0; a < frags.size(); ++a)
        for (size_t b = a + 1; b < frags.size(); ++b) {
            const int ea = frags[a].element, eb = frags[b].element;
            if (ea == eb) continue;
            std::vector<int> face;  // the nodes both elements hold
            for (int x = 0; x < npe; ++x)
                for (int y = 0; y < npe; ++y)
                    if (el.nodes[ea][x] == el.nodes[eb][y]) face.push_back(el.nodes[ea][x]);
            if (static_cast<int>(face.size()) != el.dim) continue;  // not a face through j (j is in both)
            const Fragment &fa = frags[a], &fb = frags[b];
            if (!on_face(w, fa, face) || !on_face(w, fb, face)) continue;
            if (fa.side != 0 && fb.side != 0 && fa.side != fb.side) continue;  // the cut's two sides
            parent[find(parent, static_cast<int>(a))] = find(parent, static_cast<int>(b));
        }
    // A progressive front's tip element: its sides are one material at a node of a split edge the
    // blade has not crossed yet (the cut's extension ahead of the blade).
    for (size_t a = 0; a + 1 < frags.size(); ++a) {
        if (frags[a].side != 1 || frags[a + 1].element != frags[a].element) continue;
        const auto& nodes = el.nodes[frags[a].element];
        for (int k = 0; k < npe; ++k)
            if (nodes[k] != j && w.enriched.sign[nodes[k]] != w.enriched.sign[j] && !edge_crossed(w, j, nodes[k]))
                parent[find(parent, static_cast<int>(a))] = find(parent, static_cast<int>(a + 1));
    }
    int bad = 0;
    for (size_t a = 0; a < frags.size(); ++a)
        for (size_t b = a + 1; b < frags.size(); ++b) {
            const bool joined = find(parent, static_cast<int>(a)) == find(parent, static_cast<int>(b));
            const bool same = dof_of(w, frags[a], j) == dof_of(w, frags[b], j);
            if (joined == same) continue;
            if (bad++ == 0)
                first = "node " + std::to_string(j) + ": element " + std::to_string(frags[a].element) + " side " +
                        std::to_string(frags[a].side) + " and element " + std::to_string(frags[b].element) + " side " +
                        std::to_string(frags[b].side) + (joined ? " connected, different DOFs" : " apart, one DOF");
        }
    return bad;
}

/// Enriched mesh nodes of `w` whose copies disagree with connectivity; `first` describes the first.
inline int nodes_off_connectivity(const World& w, std::string& first) {
    int off = 0;
    for (int j = 0; j < w.mesh_nodes; ++j) {
        if (j >= static_cast<int>(w.enriched.enriched.size()) || !w.enriched.enriched[j]) continue;
        std::string what;
        if (disagreements(w, j, what) == 0) continue;
        if (off++ == 0) first = what;
    }
    return off;
}

}  // namespace xcut::testing
