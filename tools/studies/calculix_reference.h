#pragma once
// Independent references for the accuracy suite: the problems solved by CalculiX (Debian's
// calculix-ccx) with quadratic elements at several refinements, by tools/reference/
// calculix_reference.py, from the same parameters the engine's problems use (passed as JSON), and
// extrapolated (Richardson, with the observed order) with an estimate of their own error. Cached
// as JSON in the suite's cache directory, keyed by the parameters, the levels and the script.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace xcut {

struct ExternalReference {
    bool available = false;      ///< CalculiX and the script ran (or the cache had it)
    std::string why;             ///< when not available: what was missing or failed
    std::string solver;          ///< "CalculiX C3D20", "CalculiX CPS8"
    std::vector<double> values;  ///< problem 3: tip deflection; 5: 3 per sample point; 6: CMOD; 14: corner's y [m]
    double error_estimate = 0.0; ///< its own relative error, estimated from its convergence [-]
    double order = 0.0;          ///< the order of convergence observed
    std::vector<int> levels;
    std::vector<int> dofs;       ///< per level
    std::vector<double> seconds; ///< per level: CalculiX's wall time [s]
    std::vector<double> level_value;  ///< per level, problems 3 and 6: the value [m]
    bool from_cache = false;
    std::string path;            ///< the cache file
};

/// Problem 3, 5, 6 or 14's reference at `levels` (cells across the problem's reference length); never
/// throws for a missing CalculiX: the result says why it is not available.
ExternalReference calculix_reference(int problem, const nlohmann::json& params, const std::vector<int>& levels,
                                     const std::string& cache_dir);

}  // namespace xcut
