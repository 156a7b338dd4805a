#pragma once
// A preconditioner made on the background thread (engine/background_threads.h), taken at the step
// it is due: the wait, if it has not finished, is measured [ms] (systems/solver/amg_background.h,
// systems/solver/factor_background.h).
#include <chrono>
#include <future>
#include <memory>

namespace xcut {

/// A result being made off the step, due at the first solve of `due_step`.
template <class T>
struct PendingResult {
    std::future<std::shared_ptr<T>> result;
    int requested_step = 0;  ///< World::step when it was asked for
    int due_step = 0;        ///< the World::step at whose first solve it is taken
};

/// The result, waiting for it if it is not ready; `wait_ms` the time waited [ms].
template <class T>
std::shared_ptr<T> take_when_due(PendingResult<T>& pending, double& wait_ms) {
    const auto t0 = std::chrono::steady_clock::now();
    std::shared_ptr<T> value = pending.result.get();
    wait_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return value;
}

}  // namespace xcut
