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

    double mu() const { return young / (2.0 * (1.0 + poisson)); }
    double lambda() const { return young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson)); }
    /// Plane-stress lambda: the 3D law with sigma_zz = 0 eliminated.
    double lambda_plane_stress() const { return 2.0 * lambda() * mu() / (lambda() + 2.0 * mu()); }
};

struct Materials {
    std::vector<Material> list;
};

}  // namespace xcut
