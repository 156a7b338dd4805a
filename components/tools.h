#pragma once
// Tool bodies: a pose driven by a scripted trajectory (keyframes: linear position, slerp orientation)
// or by a recorded one replayed from CSV, for a scalpel the blade's cutting edge in the tool frame,
// and a contact shape (sphere, capsule, box or closed triangle mesh, in the tool frame) pressed into
// the tissue's collision surface by penalty (systems/collision_system.h).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "components/nodes.h"

namespace xcut {

struct Keyframe {
    double time = 0.0;                                          ///< [s]
    Vec3 position = Vec3::Zero();                               ///< tool origin in world [m]
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< tool frame -> world
};

/// A tool's contact shape in its own frame: sphere, capsule and box centred on `centre` (a scalpel's
/// handle sits above its blade), the capsule's axis along the tool's z; a mesh as given.
struct ToolShape {
    enum Kind : uint8_t { kNone, kSphere, kCapsule, kBox, kMesh };
    Kind kind = kNone;
    Vec3 centre = Vec3::Zero();            ///< sphere, capsule, box: centre in the tool frame [m]
    double radius = 0.0;                   ///< sphere, capsule [m]
    double length = 0.0;                   ///< capsule: distance between the two sphere centres [m]
    Vec3 half_extent = Vec3::Zero();       ///< box [m]
    std::vector<Vec3> vertices;            ///< mesh, closed and outward [m]
    std::vector<std::array<int, 3>> triangles;
};

struct ToolBodies {
    std::vector<std::string> name;
    std::vector<std::vector<Keyframe>> trajectory;  ///< strictly increasing times
    std::vector<Vec3> position;                     ///< current pose [m]
    std::vector<Eigen::Quaterniond> orientation;
    std::vector<uint8_t> has_blade;
    std::vector<Vec3> blade_tip;                    ///< cutting edge, tool frame: deep end [m]
    std::vector<Vec3> blade_heel;                   ///< cutting edge, tool frame: shallow end [m]
    /// The blade's face (3D): from its cutting edge to its back, tool frame [m]; the face is the
    /// parallelogram tip, heel, heel + back, tip + back, and it cuts what it passes through (a stab
    /// pushed along the edge too). Zero: an edge only, which cuts only what it sweeps.
    std::vector<Vec3> blade_back;
    std::vector<ToolShape> shape;                   ///< contact shape (kNone: the tool touches nothing)
    std::vector<double> contact_stiffness;          ///< penalty stiffness per contact vertex [N/m]
    std::vector<double> contact_damping;            ///< normal damping per contact vertex [N s/m]
    std::vector<Vec3> velocity;                     ///< of the tool origin over the last step [m/s]
    std::vector<Vec3> reaction_force;               ///< the tissue's force on the tool, last step [N]
    std::vector<Vec3> reaction_torque;              ///< about the tool origin [N m]
    /// A bladed tool's cutting resistance over the last step [N] (systems/cut/cutting_force.h), its
    /// torque about the tool origin [N m], and the length of its edge inside the tissue [m] (2D: the
    /// thickness while the cutting point is inside). Part of reaction_force / reaction_torque.
    std::vector<Vec3> cutting_force, cutting_torque;
    std::vector<double> blade_depth;
    std::vector<double> pose_time;                  ///< simulated time of the current pose [s]
    /// Per tool: the poses over the last step, its start first and its end last. For a bladed tool
    /// the device is sampled in between, as densely as the blade needs so that it moves at most the
    /// cut threshold from one sample to the next (the CutSystem sweeps them all, so a long step or
    /// the first one cuts what the blade passed through).
    std::vector<std::vector<Keyframe>> sweep;

    int count() const { return static_cast<int>(name.size()); }
};


}  // namespace xcut
