#pragma once
// The tools a person holds in the viewer: a scalpel driven by the mouse, a probe driven by keys,
// and any of the scene's own tools taken over from its script (to hold a retractor where it is,
// say). The hand tools are added to the scene as overrides ("tools+=..."), so a recorded session
// (--record) names them in its session.json and `xcut run SCENE --replay DIR` rebuilds them.
//
// The scalpel's blade is a straight edge along the tool's z from its tip (the tool origin) to its
// heel. A press plunges the tip to `depth` below the surface point under the cursor, along that
// point's normal; a drag moves it at that depth under the cursor; a release lifts it `lift` above
// the surface, where it hovers after the cursor. Moves between these poses stay above the tissue or
// along the blade itself, so only a drag cuts.
#include <optional>
#include <string>
#include <vector>

#include "engine/devices/live_device.h"
#include "engine/io/embree_surface.h"
#include "tools/viewer/snapshot.h"

namespace xcut::viewer {

/// Sizes of the hand tools for a body of bounding box [lo, hi] [m].
struct HandToolSizes {
    double lift = 0.0;          ///< hover height of the blade's tip above the surface [m]
    double depth = 0.0;         ///< default cutting depth [m]
    double max_depth = 0.0;     ///< deepest cut the blade reaches [m]
    double probe_radius = 0.0;  ///< [m]
    Vec3 scalpel_park = Vec3::Zero(), probe_park = Vec3::Zero();  ///< start poses above the body [m]
};
HandToolSizes hand_tool_sizes(const Vec3& lo, const Vec3& hi);

/// The "tools+=" overrides that add the hand scalpel and, when the scene has a collision surface it
/// can touch, the probe.
std::vector<std::string> hand_tool_overrides(const HandToolSizes& sizes, bool with_probe);
inline constexpr const char* kHandScalpel = "hand_scalpel";
inline constexpr const char* kHandProbe = "hand_probe";

struct Ray {
    Vec3 origin = Vec3::Zero(), direction = Vec3::UnitZ();  ///< direction unit
};

struct SurfaceHit {
    Vec3 point = Vec3::Zero();   ///< [m]
    Vec3 normal = Vec3::UnitZ(); ///< unit, facing the ray's origin
    int triangle = -1;
    bool cut_face = false;       ///< a face of the wound's inside
};

/// Embree ray casts onto a snapshot's visual surface.
class SurfaceRaycaster {
public:
    void build(const Snapshot& snapshot);
    std::optional<SurfaceHit> cast(const Ray& ray) const;

private:
    EmbreeSurface embree_;
    bool built_ = false;
    std::vector<uint8_t> cut_face_;
};

class MouseScalpel {
public:
    MouseScalpel(LiveDevice& device, const HandToolSizes& sizes);
    /// The cursor moved with no button held: the blade hovers above the skin under it.
    void hover(const std::optional<SurfaceHit>& hit);
    /// Button down on the skin: plunge to the depth.
    void press(const std::optional<SurfaceHit>& hit);
    /// Button held: cut along under the cursor; a cursor off the skin moves on the entry's tangent plane.
    void drag(const Ray& ray, const std::optional<SurfaceHit>& hit);
    /// Button up: lift out of the tissue.
    void release();
    bool cutting() const { return cutting_; }
    double depth = 0.0;  ///< [m], set by the panel or the wheel
    double max_depth = 0.0;

private:
    void place(const Vec3& surface_point);
    LiveDevice& device_;
    double lift_;
    bool cutting_ = false;
    Vec3 entry_ = Vec3::Zero(), normal_ = Vec3::UnitZ(), last_ = Vec3::Zero();
};

}  // namespace xcut::viewer
