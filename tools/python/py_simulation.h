#pragma once
// The simulation the Python module drives (tools/python/module.cpp binds it): a scene built like
// `xcut run` builds it, stepped on request, its state read out as flat arrays, its tools moved by
// the caller. Plain C++ (no Python here), so what the module does is what the CLI does.
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "engine/devices/live_device.h"
#include "engine/io/metrics_columns.h"
#include "engine/simulation.h"

namespace xcut {

struct PySceneSource {
    std::string path;            ///< a scene file, or empty when `text` holds the scene
    std::string text;            ///< the scene as JSON text (a dict dumped by the module)
    std::string base_directory;  ///< with `text`: where its relative file names start
    std::vector<std::string> overrides;  ///< "field.path=json", as --set
};

/// A triangle surface's state: vertices [m], outward triangles, 1 on the wound's faces.
struct PySurface {
    std::vector<double> vertices;
    std::vector<int> triangles;
    std::vector<uint8_t> cut_face;
};

class PySimulation {
public:
    /// Builds the scene; `output_directory` empty: no files (the default from Python), otherwise
    /// the series, CSV and surfaces go there as `xcut run -o DIR` writes them.
    PySimulation(const PySceneSource& source, const std::string& output_directory);

    /// Runs `n` steps; a NumericalError stops it and every later step refuses (the state is not
    /// a solution any more).
    void step(int n);

    std::mutex& mutex() { return mutex_; }
    const World& world() const { return sim_->world; }
    const Scene& scene() const { return scene_; }
    const std::vector<std::string>& warnings() const { return warnings_; }
    int steps_done() const { return sim_->steps_done; }
    bool failed() const { return failed_; }

    // State, copied out (the engine's arrays grow when a cut adds DOFs).
    std::vector<double> positions(bool all_dofs) const;   ///< N x 3 [m]
    std::vector<double> velocities(bool all_dofs) const;  ///< N x 3 [m/s]
    std::vector<double> rest_positions() const;           ///< mesh nodes, N x 3 [m]
    std::vector<int> mesh_elements() const;               ///< M x (dim + 1)
    /// Per mesh element [Pa]; a cut element: the larger of its two sides'.
    std::vector<double> von_mises() const;
    std::vector<int> cut_elements() const;                ///< mesh elements split (XFEM or snapping)
    std::vector<int> enriched_nodes() const;              ///< mesh nodes with a phantom (XFEM)
    std::vector<double> openings(const std::vector<int>& nodes) const;  ///< |a_j| of each of enriched_nodes() [m]
    PySurface surface(bool collision) const;

    /// Tool index of a name; throws InputError listing the tools when there is none.
    int tool_index(const std::string& name) const;
    /// The tool moves to this pose over the next step (from its current one), as a live device:
    /// from then on the caller drives it. Position [m], quaternion (w, x, y, z) tool -> world.
    void set_tool_pose(int tool, const Vec3& position, const Eigen::Quaterniond& orientation);
    /// Whether the caller has taken the tool over (set_tool_pose).
    bool tool_driven(int tool) const { return live_[tool] != nullptr; }

    /// The metrics CSV's columns for the last step.
    std::vector<MetricColumn> metrics();

private:
    void check_tool(int tool) const;
    Scene scene_;
    std::unique_ptr<Simulation> sim_;
    std::vector<LiveDevice*> live_;  ///< per tool: its live device once the caller drives it
    std::vector<std::string> warnings_;
    int split_before_step_ = 0;  ///< elements split before the last step (its elements_split column)
    bool failed_ = false;
    std::string failure_;
    std::mutex mutex_;
};

}  // namespace xcut
