#include "systems/solver/fill_estimate.h"

#include <cholmod.h>

#include <algorithm>
#include <vector>

namespace xcut {

double estimated_factor_nonzeros(const World& w) {
    const int n = w.nodes.count(), per = w.elements.nodes_per_element();
    // The node graph's lower triangle by columns: column i holds i and every node j > i that shares
    // an element with it (sorted, each once).
    std::vector<std::vector<int>> below(n);
    for (int e = 0; e < w.elements.count(); ++e)
        for (int a = 0; a < per; ++a)
            for (int b = 0; b < per; ++b) {
                const int i = w.elements.nodes[e][a], j = w.elements.nodes[e][b];
                if (i >= 0 && j > i) below[i].push_back(j);
            }
    size_t entries = 0;
    for (int i = 0; i < n; ++i) {
        below[i].push_back(i);
        std::sort(below[i].begin(), below[i].end());
        below[i].erase(std::unique(below[i].begin(), below[i].end()), below[i].end());
        entries += below[i].size();
    }
    cholmod_common c;
    cholmod_start(&c);
    c.supernodal = CHOLMOD_SIMPLICIAL;  // column counts only: no supernodal symbolic factor
    c.nmethods = 1, c.method[0].ordering = CHOLMOD_AMD, c.postorder = false;
    double lnz = 0.0;
    if (cholmod_sparse* A = cholmod_allocate_sparse(n, n, entries, 1, 1, -1, CHOLMOD_PATTERN, &c)) {
        int* p = static_cast<int*>(A->p);
        int* row = static_cast<int*>(A->i);
        p[0] = 0;
        for (int i = 0; i < n; ++i) {
            std::copy(below[i].begin(), below[i].end(), row + p[i]);
            p[i + 1] = p[i] + static_cast<int>(below[i].size());
        }
        if (cholmod_factor* L = cholmod_analyze(A, &c)) {
            lnz = 9.0 * (c.lnz - n) + 6.0 * n;  // c.lnz counts the diagonal
            cholmod_free_factor(&L, &c);
        }
        cholmod_free_sparse(&A, &c);
    }
    cholmod_finish(&c);
    return lnz;
}

}  // namespace xcut
