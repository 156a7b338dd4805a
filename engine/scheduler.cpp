#include "engine/scheduler.h"

#include <fmt/format.h>

namespace xcut {

void Scheduler::build(World& world) {
    scheduled_.clear();
    world.metrics.system_names.clear();
    const uint32_t have = world.present();
    for (const SystemDesc& s : all_) {
        if ((s.reads & have) != s.reads) continue;
        scheduled_.push_back(s);
        world.metrics.system_names.push_back(s.name);
    }
}

void Scheduler::step(World& world) {
    using Clock = std::chrono::steady_clock;
    StepMetrics& m = world.metrics.current;
    m.system_ms.assign(scheduled_.size(), 0.0);
    const auto start = Clock::now();
    for (size_t i = 0; i < scheduled_.size(); ++i) {
        const auto t0 = Clock::now();
        scheduled_[i].run(world);
        m.system_ms[i] = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    }
    m.step_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

std::string Scheduler::describe(const World& world) const {
    const uint32_t have = world.present();
    std::string out = fmt::format("schedule ({} of {} systems run):\n", scheduled_.size(), all_.size());
    int k = 1;
    for (const SystemDesc& s : scheduled_)
        out += fmt::format("  {}. {:<16} reads {:<40} writes {}\n", k++, s.name, component_list(s.reads),
                           component_list(s.writes));
    for (const SystemDesc& s : all_)
        if ((s.reads & have) != s.reads)
            out += fmt::format("  -  {:<16} skipped: scene has no {}\n", s.name,
                               component_list(s.reads & ~have));
    return out;
}

}  // namespace xcut
