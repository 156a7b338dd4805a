#include "engine/scheduler.h"

#include <fmt/format.h>

#include "engine/access_check.h"

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
        if (access_check_) {
            const std::vector<uint64_t> before = component_hashes(world);
            scheduled_[i].run(world);
            check_declared_writes(scheduled_[i].name, scheduled_[i].writes, before, component_hashes(world));
        } else {
            scheduled_[i].run(world);
        }
        m.system_ms[i] = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    }
    m.step_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

std::string Scheduler::describe(const World& world) const {
    const uint32_t have = world.present();
    std::string out = fmt::format("schedule ({} of {} systems run):\n", scheduled_.size(), all_.size());
    int k = 1;
    for (const SystemDesc& s : scheduled_)
        out += fmt::format("  {}. {:<16} reads {:<40} writes {}{}\n", k++, s.name, component_list(s.reads | (s.uses & have)),
                           component_list(s.writes), s.note.empty() ? "" : "; " + s.note);
    for (const SystemDesc& s : all_)
        if ((s.reads & have) != s.reads)
            out += fmt::format("  -  {:<16} skipped: scene has no {}\n", s.name,
                               component_list(s.reads & ~have));
    return out;
}

std::string Scheduler::dataflow_markdown() const {
    auto names = [](uint32_t mask) {
        std::vector<std::string> out;
        for (uint32_t bit = 1; bit != 0; bit <<= 1)
            if (mask & bit) out.push_back(component_name(bit));
        return out;
    };
    std::string table = "| # | system | reads | also reads, when present | writes |\n|---|---|---|---|---|\n";
    std::string chart = "```mermaid\nflowchart LR\n";
    uint32_t used = 0;
    for (size_t i = 0; i < all_.size(); ++i) {
        const SystemDesc& s = all_[i];
        table += fmt::format("| {} | {} | {} | {} | {} |\n", i + 1, s.name, component_list(s.reads), component_list(s.uses),
                             component_list(s.writes));
        chart += fmt::format("  S{}[\"{}. {}\"]\n", i, i + 1, s.name);
        if (i > 0) chart += fmt::format("  S{} ==> S{}\n", i - 1, i);
        used |= s.reads | s.uses | s.writes;
    }
    for (const std::string& c : names(used)) chart += fmt::format("  {}[({})]\n", c, c);
    for (size_t i = 0; i < all_.size(); ++i) {
        for (const std::string& c : names(all_[i].writes)) chart += fmt::format("  S{} --> {}\n", i, c);
        for (const std::string& c : names((all_[i].reads | all_[i].uses) & ~all_[i].writes))
            chart += fmt::format("  {} -.-> S{}\n", c, i);
    }
    return table + "\n" + chart + "```\n";
}

}  // namespace xcut
