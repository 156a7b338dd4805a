#pragma once
// The world owns every component array of a scene and the per-step work buffers. It has no
// behaviour beyond saying which component kinds it holds: systems do the work.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "components/constraints.h"
#include "components/contacts.h"
#include "components/crack_tips.h"
#include "components/cut_elements.h"
#include "components/cut_plan.h"
#include "components/cut_state.h"
#include "components/grasps.h"
#include "components/elements.h"
#include "components/linear_system.h"
#include "components/material.h"
#include "components/metrics.h"
#include "components/nodes.h"
#include "components/pieces.h"
#include "components/quadratic_elements.h"
#include "components/snap_mesh.h"
#include "components/surface_mesh.h"
#include "components/tools.h"

namespace xcut {

/// Component kinds, as bits: systems declare reads and writes with them, and the scheduler drops a
/// system whose inputs the world does not hold.
enum ComponentBit : uint32_t {
    kNodes = 1u << 0,
    kElements = 1u << 1,
    kMaterials = 1u << 2,
    kConstraints = 1u << 3,
    kGravity = 1u << 4,
    kForces = 1u << 5,       ///< per-step force and preconditioner buffers
    kOutput = 1u << 6,       ///< output settings (series, metrics CSV)
    kMetrics = 1u << 7,
    kCutPlan = 1u << 8,      ///< scripted cuts
    kCutEvents = 1u << 9,    ///< the queue of splits; present when the scene has any cutter
    kXfem = 1u << 10,        ///< cut elements, virtual elements, enriched DOFs
    kTools = 1u << 11,       ///< tool bodies (scalpel, ...)
    kVisual = 1u << 12,      ///< visual surface mesh
    kCollision = 1u << 13,   ///< collision surface mesh
    kSurfaces = 1u << 14,    ///< any surface bound to the body (visual or collision)
    kShapedTools = 1u << 15, ///< tools with a contact shape
    kLinear = 1u << 16,      ///< the step's assembled system and the solver's kept preconditioner
    kContacts = 1u << 17,    ///< this step's tool contacts
    kCutState = 1u << 18,    ///< the blades' crossing lists, fronts and cut figures
    kSnap = 1u << 19,        ///< the snapping cutter's pieces and copies
    kPieces = 1u << 20,      ///< the connected pieces of tissue; present when the scene has any cutter
    kGrasps = 1u << 21,      ///< graspers' jaws and what they hold; present when a tool grasps
};
const char* component_name(uint32_t bit);
std::string component_list(uint32_t mask);

struct SolverSettings {
    double dt = 1e-3;              ///< time step [s]; the initial one in real-time mode
    double cg_tolerance = 1e-6;    ///< relative residual |r| / |b| at which CG stops [-]
    int cg_max_iterations = 200;
    bool realtime = false;         ///< adapt dt to the measured step time (paper §4.3)
    double dt_min = 1e-4;          ///< real-time mode bounds [s]
    double dt_max = 4e-2;
    double damping_mass = 0.0;       ///< Rayleigh alpha [1/s]: D = alpha M + beta K
    double damping_stiffness = 0.0;  ///< Rayleigh beta [s]
    int newton_iterations = 1;       ///< "newton.iterations": 1 = the once-linearized step (paper)
    double newton_tolerance = 1e-6;  ///< "newton.tolerance": residual relative to the first [-]
    /// "newton.on_energy_gain": a once-linearized step that gains energy goes on with up to this many
    /// Newton iterations (systems/solver/energy_check.h); 0 or 1: no check [-]
    int newton_on_energy_gain = 3;
    /// "linear": how the step's system is solved (systems/solver/linear_solver.h): "auto", "jacobi"
    /// (matrix-free Jacobi CG), "block_jacobi" (assembled, 3x3 block Jacobi CG), "amg" (CG
    /// preconditioned by a kept smoothed-aggregation multigrid), "cholesky" (CG preconditioned by a
    /// kept Cholesky factor), "direct" (factor and solve every step).
    std::string linear = "auto";
    int refactor_iterations = 8;     ///< "refactor_iterations": cholesky refactors when CG needs more [-]
    int refactor_every = 200;        ///< "refactor_every": ... or when the factor is this many steps old
    /// "renew_delay": amg renews an aged hierarchy off the step, taking the new one this many steps
    /// after asking (systems/solver/amg_background.h); 0: in the step that finds it aged [steps]
    int renew_delay = 6;
    /// "factor_delay": cholesky renews its factor off the step (at a cut, the old one goes on for
    /// the grown system through an augmented block; an aged one goes on as it is), taking the new
    /// one this many steps after asking (systems/solver/factor_background.h); 0: in the step [steps]
    int factor_delay = 10;
    /// "factor_precision": "auto" (a factor renewed off the step solves in single precision from
    /// 1 M non-zeros of L on, systems/solver/cholesky_factor.cpp), "double", "single"
    std::string factor_precision = "auto";
    /// "guess_history": the step's solve starts from the Galerkin projection onto the solutions of
    /// this many earlier steps (systems/kernels/solver/projected_guess.h); 0: from the previous step's [-]
    int guess_history = 6;
    int max_substeps = 16;           ///< a step whose solve fails is retried in up to this many substeps
    /// The watchdog stops a run whose kinetic + elastic energy exceeds this factor times the work
    /// put in (gravity, prescribed displacements, tools) plus the energy at the first step [-].
    double energy_factor = 100.0;
};

/// Per-step buffers: the solver's right-hand side pieces and the Jacobi preconditioner.
struct ForceState {
    Eigen::VectorXd force;                          ///< 3 per DOF node [N]: elastic + gravity
    Eigen::VectorXd stiffness_diagonal;             ///< diag(K) [N/m]
    std::vector<std::array<Vec3, 4>> element_buffer;  ///< per-element nodal terms before gathering
    std::vector<std::array<Vec3, 10>> quadratic_buffer;  ///< the same per quadratic element
    Eigen::VectorXd last_dv;                        ///< previous step's velocity change: CG's first guess
    double elastic_energy = 0.0;                    ///< [J]
    /// 3D, the step's energy check (systems/solver/energy_check.h): per element, the deformation
    /// gradient at the positions it checked and its polar rotation, which the next update_rotations
    /// takes where the element's gradient is the same to the bit (NaN where the rotation depended on
    /// the warm start: an inverted element's)
    std::vector<Mat3> checked_gradient, checked_rotation;
    /// 3 per DOF node: the held terms' part of `force` at the step's start (the contacts' and the
    /// grasps', which their systems add to both), for the energy check's count of their work [N]
    Eigen::VectorXd held_force;
};

struct OutputSettings {
    std::string directory;          ///< where the series and CSV go; empty: no output
    std::string name = "xcut";      ///< file stem
    int every = 10;                 ///< write a frame every N steps
    bool vtu = true;
    bool ascii = false;             ///< VTU arrays as text instead of zlib-compressed binary
    bool metrics_csv = true;
};

/// Whether the output writes a frame at `step` (every `every` steps; step 0 at start).
inline bool output_frame_due(const OutputSettings& o, int step) { return step % o.every == 0; }

struct World {
    Nodes nodes;
    Elements elements;
    Incidence incidence;          ///< mesh node -> mesh element (fixed topology)
    Incidence virtual_incidence;  ///< DOF node -> virtual element; rebuilt from the virtual elements only
    QuadraticElements quadratic;  ///< the 10-node tetrahedra of quadratic materials (none: all linear)
    LinearSystem linear;          ///< the step's assembled system and the solver's kept factor
    /// What reading the mesh repaired or read differently from its file (MeshData::notes), each
    /// "file: note"; the front end prints them as warnings.
    std::vector<std::string> mesh_notes;
    std::vector<std::string> body_names = {"body"};  ///< the scene's bodies (Elements::body indexes them)
    int mesh_nodes = 0;         ///< nodes [0, mesh_nodes) are the mesh's; after them, enriched DOFs
    /// Mesh node i's index in the mesh files' numbering (0-based through the bodies in order): the
    /// output's "file_node" array, so results map back to the input. Empty: the same as i.
    std::vector<int> mesh_file_index;
    int mesh_elements = 0;      ///< elements [0, mesh_elements) are the mesh's; after them, virtual
    Materials materials;
    Constraints constraints;
    Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  ///< [m/s^2]
    SolverSettings solver;
    ForceState forces;
    OutputSettings output;
    Metrics metrics;

    ToolBodies tools;
    CutState cut_state;
    Grasps grasps;
    CutPlan cut_plan;
    std::vector<CutEvent> pending_cuts;   ///< splits queued by cutters, applied by the EnrichmentSystem
    CutElements cuts;
    VirtualElements virtual_elements;
    EnrichedDofs enriched;
    CrackTips tips;          ///< crack tips enriched with branch functions (2D)
    Pieces pieces;           ///< the connected pieces of tissue (systems/cut/pieces_system.h)
    SnapMesh snap;           ///< the snapping-and-subdivision cutter, when the scene chooses it
    SurfaceMesh visual;
    SurfaceMesh collision;   ///< the surface tools touch (paper §3.5): coarser than the visual one
    Contacts contacts;       ///< this step's tool contacts on the collision surface

    bool verbose = false;  ///< systems may log events (cuts) to stdout
    double time = 0.0;   ///< [s]
    int step = 0;

    /// Which component kinds this world holds (non-empty).
    uint32_t present() const;
};

/// Builds the mesh node -> mesh element incidence (CSR), once.
void build_incidence(World& world);
/// Rebuilds the DOF node -> virtual element incidence: O(nodes + virtual elements), not O(mesh).
void build_virtual_incidence(World& world);

}  // namespace xcut
