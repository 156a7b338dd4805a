#pragma once
// Scene files: JSON, schema in docs/scene-format.md. Loading checks every field and names the file
// and field path of any error; building turns the scene into a World ready to step.
#include "engine/devices/device_spec.h"
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "engine/io/generators.h"
#include "engine/mesh_data.h"
#include "engine/mesh_repair.h"
#include "engine/io/render.h"
#include "engine/world.h"

namespace xcut {

/// Bounds on what a scene file may ask for, so that every input has a bounded cost: past one, the
/// load stops with an InputError naming the field and the bound (docs/scene-format.md#limits).
inline constexpr size_t kMaxSceneBytes = 16u << 20;  ///< a scene file [bytes]
inline constexpr int kMaxSceneDepth = 64;            ///< JSON nesting levels
inline constexpr size_t kMaxSceneNameLength = 128;   ///< "name": a file stem of the output
inline constexpr int kMaxTools = 64;                 ///< entries of "tools"
inline constexpr int kMaxScriptedCuts = 100000;      ///< entries of "cuts"
inline constexpr long long kMaxSteps = 100'000'000;  ///< "steps", or "duration" / dt
inline constexpr size_t kMaxTrajectoryRows = 10'000'000;   ///< poses of a trajectory (CSV or inline)
inline constexpr size_t kMaxTrajectoryBytes = size_t{1} << 30;  ///< a trajectory CSV [bytes]
/// What a run may write [bytes] (VTU frames, surfaces, the CSV), estimated at load from the mesh,
/// the steps and output.every; "output.max_gb" raises it.
inline constexpr double kDefaultMaxOutputBytes = 20e9;

struct MeshSpec {
    std::string generator;     ///< "box" | "plate"; empty when a file is given
    GridSpec grid;
    std::string file;          ///< resolved path of a mesh file
    double max_volume = 0.0;   ///< surfaces tetrahedralized with TetGen: max tet volume [m^3]; 0: none
    MeshPlacement placement;   ///< "units"/"scale", "rotate", "translate", "reorient", "region_array"
};

/// "region_materials": the material of the cells of one region (a name or a number).
struct RegionMaterial {
    std::string region;
    Material material;
};

/// A body of a multi-body scene ("bodies": [...]) after the first; the first body fills
/// Scene::mesh, material and region_materials, so a one-body scene reads as before.
struct BodySpec {
    std::string name;
    MeshSpec mesh;
    Material material;
    std::vector<RegionMaterial> region_materials;
};

/// "constraints.fixed_sets"[i]: exactly one of a region (of `body`, or of every body that has it), a
/// sphere, or a file of node indices; held on `axes`, starting displaced by `displacement`.
struct FixedSetSpec {
    std::string field;                 ///< "constraints.fixed_sets[i]", for messages
    std::string region, body;          ///< a region's name or number; the body's name (empty: any)
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    double radius = -1.0;              ///< [m]; < 0: not a sphere
    std::string file;                  ///< resolved path of an index file
    uint8_t axes = 7;
    Eigen::Vector3d displacement = Eigen::Vector3d::Zero();
};

struct Scene {
    std::string file;          ///< the scene file, for messages
    std::string name;
    MeshSpec mesh;
    Material material;                             ///< cells of no listed region
    std::vector<RegionMaterial> region_materials;  ///< "region_materials"
    std::string body_name = "body";                ///< the first body's name ("bodies[0].name")
    std::vector<BodySpec> more_bodies;             ///< "bodies"[1...]
    Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
    Constraints constraints;
    std::vector<FixedSetSpec> fixed_sets;  ///< "constraints.fixed_sets", resolved by build_world
    SolverSettings solver;
    int steps = 100;
    OutputSettings output;
    std::vector<ScriptedCut> cuts;   ///< "cuts": programmatic XFEM cuts
    ToolBodies tools;                ///< "tools"
    Grasps grasps;                   ///< "tools[i].grasp", one entry per tool
    std::vector<DeviceSpec> devices; ///< "tools[i].device", one per tool
    double cut_threshold = 0.0;      ///< "cutter.threshold" [m]; 0: mean edge length
    int cut_min_depth = 1;           ///< "cutter.neighbourhood_depth"
    std::string cutter = "xfem";     ///< "cutter.type": "xfem" (enrichment) or "snap" (snapping and subdivision)
    double tip_radius = -1.0;        ///< "cutter.tip.radius" [m]: blades carry branch-enriched tips (2D) or fronts (3D); < 0: off
    double tip_stride = kTipStrideFraction;  ///< "cutter.tip.stride" [-] of the mean edge: a moving blade's tip follows in such strides
    int recut = -1;                  ///< "cutter.recut": -1 unset (2D on, 3D off), 0 off, 1 on
    std::string cut_front = "semi";  ///< "cutter.front": "semi" (paper §3.3) or "progressive" (docs/xfem.md)
    double snap_threshold = 0.1;     ///< "cutter.snap_threshold": fraction of the crossed edge (components/snap_mesh.h)
    int visual_subdivisions = -1;    ///< "visual.subdivisions"; -1: no visual surface
    int collision_subdivisions = -1; ///< "collision.subdivisions"; -1: no collision surface
    Camera camera;                   ///< "camera"; automatic framing unless given
    /// "allow": plausibility checks the scene silences (engine/io/scene_checks.h), by name.
    std::vector<std::string> allow;
    double max_output_gb = kDefaultMaxOutputBytes / 1e9;  ///< "output.max_gb": what a run may write [GB]
};


/// Reads a recorded trajectory: CSV with header time,x,y,z,qw,qx,qy,qz (SI units; quaternion
/// tool -> world). Throws InputError naming the file and line.
std::vector<Keyframe> read_trajectory_csv(const std::string& path);
/// Checks keyframes: strictly increasing finite times, finite positions, non-zero quaternions
/// (normalized here). `where` names the field for messages.
void check_trajectory(std::vector<Keyframe>& keys, const std::string& file, const std::string& where);

/// `overrides`: "field.path=json-value" pairs (from --set) applied to the JSON before it is read.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});
/// A scene given as JSON text (the Python API's dict): the same schema, checks and messages as a
/// file's, `label` naming it in messages; relative file names start at `base_directory`; its name,
/// when it gives none, is "scene".
Scene load_scene_text(const std::string& text, const std::string& label, const std::string& base_directory,
                      const std::vector<std::string>& overrides = {});
/// Reads or generates the first body's mesh (validated).
MeshData load_scene_mesh(const Scene& scene);

/// Every body of the scene as one mesh: the bodies' nodes and cells one after the other (a body is
/// a range of nodes and elements, not a second world), with each cell's material and body.
struct SceneBodies {
    MeshData mesh;                          ///< all bodies; cell_region keeps each body's own region numbers (names: below)
    std::vector<Material> materials;        ///< per body in order: its material, then its region materials
    std::vector<uint16_t> material_of_cell;
    std::vector<int> body_of_cell;
    std::vector<std::string> names;         ///< per body
    std::vector<std::map<int, std::string>> region_names;  ///< per body
    /// Per point of `mesh`: its index in the files' numbering, 0-based through the bodies in order
    /// (what "fixed_nodes" and node-set files count); `file_points`: the files' points together.
    std::vector<int> file_index;
    long long file_points = 0;
};
/// The mesh point a scene's node index (the files' numbering) names; throws InputError naming
/// `scene_file` and `field` when the files have no such node or no element uses it (dropped).
int node_of_file_index(const SceneBodies& bodies, const std::string& scene_file, const std::string& field,
                       long long index);
SceneBodies load_scene_bodies(const Scene& scene);
/// The world for a scene: components, constraints, settings.
World build_world(const Scene& scene);

}  // namespace xcut
