#include "tools/python/py_simulation.h"

#include <fmt/format.h>

#include <algorithm>

#include "engine/error.h"
#include "engine/io/cell_stress.h"
#include "engine/io/scene_checks.h"
#include "systems/pipeline.h"
#include "systems/xfem_queries.h"

namespace xcut {
namespace {

std::vector<double> flatten(const std::vector<Vec3>& v, int count) {
    std::vector<double> out(3 * static_cast<size_t>(count));
    for (int i = 0; i < count; ++i)
        for (int k = 0; k < 3; ++k) out[3 * size_t(i) + k] = v[i][k];
    return out;
}

}  // namespace

PySimulation::PySimulation(const PySceneSource& source, const std::string& output_directory) {
    scene_ = source.path.empty()
                 ? load_scene_text(source.text, "<scene dict>", source.base_directory, source.overrides)
                 : load_scene(source.path, source.overrides);
    scene_.output.directory = output_directory;
    sim_ = make_simulation(scene_, !output_directory.empty());
    live_.assign(sim_->world.tools.count(), nullptr);
    warnings_ = sim_->world.mesh_notes;
    for (const std::string& w : plausibility_warnings(scene_, sim_->world, scene_.steps)) warnings_.push_back(w);
}

void PySimulation::step(int n) {
    if (failed_) throw NumericalError("the simulation failed earlier and cannot step on: " + failure_);
    try {
        for (int i = 0; i < n; ++i) {
            split_before_step_ = sim_->world.cuts.count() + sim_->world.snap.elements_split;
            step_simulation(*sim_);
        }
    } catch (const NumericalError& e) {
        failed_ = true;
        failure_ = e.what();
        throw;
    }
    if (sim_->output) sim_->output->finish();
}

std::vector<double> PySimulation::positions(bool all_dofs) const {
    const Nodes& n = sim_->world.nodes;
    return flatten(n.position, all_dofs ? n.count() : sim_->world.mesh_nodes);
}

std::vector<double> PySimulation::velocities(bool all_dofs) const {
    const Nodes& n = sim_->world.nodes;
    return flatten(n.velocity, all_dofs ? n.count() : sim_->world.mesh_nodes);
}

std::vector<double> PySimulation::rest_positions() const { return flatten(sim_->world.nodes.rest, sim_->world.mesh_nodes); }

std::vector<int> PySimulation::mesh_elements() const {
    const World& w = sim_->world;
    const int per = w.elements.dim + 1;
    std::vector<int> out;
    out.reserve(size_t(w.mesh_elements) * per);
    for (int e = 0; e < w.mesh_elements; ++e)
        for (int k = 0; k < per; ++k) out.push_back(w.elements.nodes[e][k]);
    return out;
}

std::vector<double> PySimulation::von_mises() const {
    const World& w = sim_->world;
    std::vector<double> out(w.mesh_elements, 0.0);
    for (int e = 0; e < w.mesh_elements; ++e) {
        // What carries the element: itself, its two virtual elements (XFEM) or its pieces (snapping).
        std::vector<int> carriers = {e};
        const int cut = e < static_cast<int>(w.cuts.cut_of_element.size()) ? w.cuts.cut_of_element[e] : -1;
        if (cut >= 0) {
            carriers.clear();
            for (int v : xcut::fragments_of(w, cut)) carriers.push_back(w.virtual_elements.element[v]);
        }
        if (e < static_cast<int>(w.snap.pieces.size()) && !w.snap.pieces[e].empty()) carriers = w.snap.pieces[e];
        for (int c : carriers) {
            const bool spare = c >= w.mesh_elements && !w.snap.piece_live.empty() && !w.snap.piece_live[c - w.mesh_elements];
            if (!spare) out[e] = std::max(out[e], xcut::von_mises(cell_cauchy_stress(w, c)));
        }
    }
    return out;
}

std::vector<int> PySimulation::cut_elements() const {
    const World& w = sim_->world;
    std::vector<int> out = w.cuts.element;
    for (int e = 0; e < static_cast<int>(w.snap.split.size()); ++e)
        if (w.snap.split[e]) out.push_back(e);
    return out;
}

std::vector<int> PySimulation::enriched_nodes() const {
    const World& w = sim_->world;
    std::vector<int> out;
    for (int j = 0; j < static_cast<int>(w.enriched.phantom.size()); ++j)
        if (w.enriched.phantom[j] >= 0) out.push_back(j);
    return out;
}

std::vector<double> PySimulation::openings(const std::vector<int>& nodes) const {
    std::vector<double> out;
    for (int j : nodes) out.push_back(enriched_displacement(sim_->world, j).norm());
    return out;
}

PySurface PySimulation::surface(bool collision) const {
    const SurfaceMesh& s = collision ? sim_->world.collision : sim_->world.visual;
    PySurface out;
    out.vertices = flatten(s.position, s.vertex_count());
    for (const auto& t : s.triangles) out.triangles.insert(out.triangles.end(), t.begin(), t.end());
    out.cut_face = s.cut_face;
    out.cut_face.resize(s.triangles.size(), 0);
    return out;
}

int PySimulation::tool_index(const std::string& name) const {
    const std::vector<std::string>& names = sim_->world.tools.name;
    const auto it = std::find(names.begin(), names.end(), name);
    if (it != names.end()) return static_cast<int>(it - names.begin());
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    throw InputError(scene_.file, "tools", fmt::format("no tool is named \"{}\" (the scene's: {})", name,
                                                       list.empty() ? "none" : list));
}

void PySimulation::check_tool(int tool) const {
    if (tool < 0 || tool >= sim_->world.tools.count())
        throw InputError(scene_.file, "tools", fmt::format("tool {} does not exist (the scene has {} tools)", tool,
                                                           sim_->world.tools.count()));
}

void PySimulation::set_tool_pose(int tool, const Vec3& position, const Eigen::Quaterniond& orientation) {
    check_tool(tool);
    if (!position.allFinite() || !orientation.coeffs().allFinite() || !(orientation.norm() > 0.0))
        throw InputError(scene_.file, fmt::format("tools[{}] pose", tool),
                         "the position must be finite and the quaternion finite and non-zero");
    if (!live_[tool]) {  // from now on the caller drives it, from where it is
        ToolBodies& tb = sim_->world.tools;
        Keyframe start{sim_->world.time, tb.position[tool], tb.orientation[tool]};
        auto device = std::make_unique<LiveDevice>(start, "python");
        device->pose(sim_->world.time);  // the current segment ends here: the next step moves from it
        live_[tool] = device.get();
        sim_->devices[tool] = std::move(device);
    }
    live_[tool]->set_target(position, orientation);
}

std::vector<MetricColumn> PySimulation::metrics() {
    int running = split_before_step_;
    return metric_columns(sim_->world, running);
}

}  // namespace xcut
