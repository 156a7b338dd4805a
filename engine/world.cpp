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
        case kVisual: return "VisualMesh";
        case kCollision: return "CollisionMesh";
        case kSurfaces: return "Surfaces";
        case kShapedTools: return "ShapedTools";
        case kLinear: return "LinearSystem";
        case kContacts: return "Contacts";
        case kCutState: return "CutState";
        case kSnap: return "SnapMesh";
        case kPieces: return "Pieces";
        case kGrasps: return "Grasps";
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
    if (nodes.count() > 0) mask |= kNodes | kLinear;
    if (elements.count() > 0) mask |= kElements;
    if (!materials.list.empty()) mask |= kMaterials;
    if (!constraints.boxes.empty() || !constraints.nodes.empty()) mask |= kConstraints;
    if (gravity.squaredNorm() > 0.0) mask |= kGravity;
    if (!output.directory.empty()) mask |= kOutput;
    if (!cut_plan.cuts.empty()) mask |= kCutPlan | kCutEvents | kPieces;
    if (cuts.count() > 0 || tips.count() > 0) mask |= kXfem;
    if (tools.count() > 0) mask |= kTools;
    for (uint8_t blade : tools.has_blade)
        if (blade) mask |= kCutEvents | kCutState | kPieces;
    for (const ToolShape& s : tools.shape)
        if (s.kind != ToolShape::kNone) mask |= kShapedTools | kContacts;
    if (snap.enabled) mask |= kSnap;
    if (grasps.any()) mask |= kGrasps;
    if (visual.vertex_count() > 0) mask |= kVisual | kSurfaces;
    if (collision.vertex_count() > 0) mask |= kCollision | kSurfaces;
    return mask;
}

namespace {

/// CSR of `nodes` entries from elements [first, last) of world.elements.
void fill_incidence(const World& world, int nodes, int first, int last, Incidence& inc) {
    const int npe = world.elements.nodes_per_element();
    const auto& conn = world.elements.nodes;
    inc.offset.assign(nodes + 1, 0);
    for (int e = first; e < last; ++e)
        for (int a = 0; a < npe; ++a) ++inc.offset[conn[e][a] + 1];
    for (int i = 0; i < nodes; ++i) inc.offset[i + 1] += inc.offset[i];
    inc.entry.resize(inc.offset[nodes]);
    std::vector<int> fill(inc.offset.begin(), inc.offset.end() - 1);
    // Elements in increasing order per node: the gather sums in this fixed order.
    for (int e = first; e < last; ++e)
        for (int a = 0; a < npe; ++a) inc.entry[fill[conn[e][a]]++] = e * 4 + a;
}

}  // namespace

void build_incidence(World& world) {
    fill_incidence(world, world.mesh_nodes, 0, world.mesh_elements, world.incidence);
    world.virtual_incidence.offset.assign(world.nodes.count() + 1, 0);
    world.virtual_incidence.entry.clear();
}

void build_virtual_incidence(World& world) {
    fill_incidence(world, world.nodes.count(), world.mesh_elements, world.elements.count(), world.virtual_incidence);
}

}  // namespace xcut
