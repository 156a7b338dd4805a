#pragma once
// Linear elastic materials (the corotational model's small-strain law) and Rayleigh damping.
#include <string>
#include <vector>

namespace xcut {

struct Material {
    std::string name = "skin";
    double young = 1.0e4;       ///< E [Pa] (paper §4: skin, 1e4 Pa)
    double poisson = 0.3;       ///< nu [-]
    double density = 1000.0;    ///< rho [kg/m^3]
    double thickness = 1.0e-3;  ///< 2D only: out-of-plane thickness [m]
    /// Fracture toughness J_c [J/m^2]: the work a blade spends per unit area of new cut surface,
    /// felt as a cutting resistance J_c per metre of edge in the tissue (Mahvash & Hayward 2004;
    /// systems/cut/cutting_force.h). 0: the blade cuts without resistance.
    double toughness = 0.0;
    /// Friction of the wound's lips on the blade [N/m] per metre of edge in the tissue, against the
    /// blade's motion in any direction (a stab too). 0: none.
    double blade_friction = 0.0;
    /// "element": "quadratic": its tetrahedra are 10-node quadratic ones (components/quadratic_elements.h),
    /// which neither lock in bending nor, as much, as nu nears 0.5; false: the linear element.
    bool quadratic = false;
    /// "element": "quadratic-p0": quadratic, with the volumetric strain's mean over the element (a
    /// constant pressure per element, P2-P0) in place of its value at each point: no volumetric
    /// locking as nu nears 0.5 (systems/kernels/quadratic_tet.h).
    bool mean_dilatation = false;

    double mu() const { return young / (2.0 * (1.0 + poisson)); }
    double lambda() const { return young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson)); }
    /// Plane-stress lambda: the 3D law with sigma_zz = 0 eliminated.
    double lambda_plane_stress() const { return 2.0 * lambda() * mu() / (lambda() + 2.0 * mu()); }
};

struct Materials {
    std::vector<Material> list;
};

}  // namespace xcut
