#pragma once
// What a conjugate-gradient run reports (systems/kernels/solver/conjugate_gradient.h, team_cg.h).

namespace xcut {

struct CgResult {
    int iterations = 0;
    double relative_residual = 0.0;  ///< |r| / |b| over the free entries [-]; NaN when b or A was not finite
};

}  // namespace xcut
