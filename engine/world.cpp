#include "engine/world.h"

namespace xcut {

const char* component_name(uint32_t bit) {
    switch (bit) {
        case kNodes: return "Nodes";
        case kElements: return "Elements";
        case kMaterials: return "Materials";
        case kConstraints: return "Constraints";
        case kGravity: return "Gravity";
        case kForces: return "Forces";
        case kOutput: return "Output";
        case kMetrics: return "Metrics";
        case kCutPlan: return "CutPlan";
        case kCutEvents: return "CutEvents";
        case kXfem: return "Xfem";
        case kTools: return "Tools";
        default: return "?";
    }
}

std::string component_list(uint32_t mask) {
    std::string s;
    for (uint32_t bit = 1; bit != 0 && bit <= mask; bit <<= 1) {
        if (!(mask & bit)) continue;
        if (!s.empty()) s += ",";
        s += component_name(bit);
    }
    return s.empty() ? "-" : s;
}

uint32_t World::present() const {
    uint32_t mask = kForces | kMetrics;
    if (nodes.count() > 0) mask |= kNodes;
    if (elements.count() > 0) mask |= kElements;
    if (!materials.list.empty()) mask |= kMaterials;
    if (!constraints.boxes.empty() || !constraints.nodes.empty()) mask |= kConstraints;
    if (gravity.squaredNorm() > 0.0) mask |= kGravity;
    if (!output.directory.empty()) mask |= kOutput;
    if (!cut_plan.cuts.empty()) mask |= kCutPlan | kCutEvents;
    if (cuts.count() > 0) mask |= kXfem;
    if (tools.count() > 0) mask |= kTools | kCutEvents;
    return mask;
}

void build_incidence(World& world) {
    const int n = world.nodes.count();
    const int npe = world.elements.nodes_per_element();
    Incidence& inc = world.incidence;
    inc.offset.assign(n + 1, 0);
    for (const auto& el : world.elements.nodes)
        for (int a = 0; a < npe; ++a) ++inc.offset[el[a] + 1];
    for (int i = 0; i < n; ++i) inc.offset[i + 1] += inc.offset[i];
    inc.entry.resize(inc.offset[n]);
    std::vector<int> fill(inc.offset.begin(), inc.offset.end() - 1);
    // Elements in increasing order per node: the gather sums in this fixed order.
    for (int e = 0; e < world.elements.count(); ++e)
        for (int a = 0; a < npe; ++a) inc.entry[fill[world.elements.nodes[e][a]]++] = e * 4 + a;
}

}  // namespace xcut
