#pragma once
// Systems declare what they read and write; the scheduler keeps, in pipeline order, those whose
// inputs the world holds, and drops the rest, so a scene pays nothing for what it does not use.
// (The idea of flecs' matching and EnTT's organizer, without their machinery: we have a handful of
// fixed component kinds.) Systems run one after another; each parallelizes inside with OpenMP,
// which on two cores keeps both busy without inter-system synchronization.
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "engine/world.h"

namespace xcut {

struct SystemDesc {
    SystemDesc() = default;
    SystemDesc(std::string name_, uint32_t reads_, uint32_t writes_, std::function<void(World&)> run_,
               std::string note_ = "")
        : name(std::move(name_)), reads(reads_), writes(writes_), run(std::move(run_)), note(std::move(note_)) {}

    /// Declares components the system reads when the world holds them but does not need to run
    /// (the XFEM data once something is cut, this step's contacts).
    SystemDesc& also_reads(uint32_t mask) {
        uses = mask;
        return *this;
    }

    std::string name;
    uint32_t reads = 0;     ///< every one must be present for the system to run
    uint32_t uses = 0;      ///< read when present, not required (also_reads)
    uint32_t writes = 0;
    std::function<void(World&)> run;
    std::string note;       ///< printed after the system in the schedule (a choice it made)
};

class Scheduler {
public:
    void add(SystemDesc system) { all_.push_back(std::move(system)); }
    /// Keeps the systems whose reads the world holds; call after the world is built.
    void build(World& world);
    /// One simulation step: runs the scheduled systems in order, timing each into world.metrics.
    void step(World& world);
    /// With the check on, each system's run is followed by engine/access_check.h's: a component it
    /// changed without declaring the write stops the step with a std::logic_error. Off by default.
    void set_access_check(bool on) { access_check_ = on; }
    /// The schedule as printed at start-up.
    std::string describe(const World& world) const;
    /// Every registered system in pipeline order with the components it reads and writes, as a
    /// Markdown table and a Mermaid flowchart (docs/architecture.md holds this text, generated).
    std::string dataflow_markdown() const;
    const std::vector<SystemDesc>& scheduled() const { return scheduled_; }
    /// Every system added, scheduled or not, in pipeline order.
    const std::vector<SystemDesc>& registered() const { return all_; }

private:
    std::vector<SystemDesc> all_;
    std::vector<SystemDesc> scheduled_;
    bool access_check_ = false;
};

}  // namespace xcut
