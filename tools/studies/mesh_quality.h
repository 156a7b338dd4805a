#pragma once
// Quality of the elements that carry material after cutting (`xcut compare`): the smallest
// dihedral angle of the tetrahedra (2D: the smallest triangle angle) in the rest shape, the
// smallest volume (2D: area x thickness), and the smallest *effective* volume V x weight — for an
// XFEM virtual element the volume of its side, V_s = V x V_s/V, which is what its stiffness and
// mass scale with; for a snap piece its own volume.
#include "engine/world.h"

namespace xcut {

struct MeshQuality {
    int elements = 0;                 ///< live elements (weight > 0)
    double min_angle_deg = 180.0;     ///< smallest dihedral (3D) / triangle angle (2D) [deg]
    double min_volume = 0.0;          ///< smallest rest volume [m^3]
    double min_effective_volume = 0.0;  ///< smallest rest volume x weight [m^3]
    int below_threshold = 0;          ///< elements whose smallest angle is below the threshold
};

/// Smallest dihedral angle of tetrahedron abcd [rad]: pi minus the largest angle between the
/// outward normals of two faces.
double min_dihedral_angle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
/// Smallest angle of triangle abc [rad].
double min_triangle_angle(const Vec3& a, const Vec3& b, const Vec3& c);

MeshQuality mesh_quality(const World& world, double threshold_deg);

}  // namespace xcut
