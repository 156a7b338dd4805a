// docs/architecture.md's data-flow table and picture are the scheduler's own description of the
// pipeline (Scheduler::dataflow_markdown), so they cannot drift from the code: regenerate them with
// `xcut schedule scenes/open_surgery.json --dataflow` between the dataflow markers.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "systems/pipeline.h"

namespace xcut {
namespace {

std::string read_file(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

TEST(ArchitectureDoc, DataflowIsTheSchedulersOwn) {
    const Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/open_surgery.json");
    const auto sim = make_simulation(scene, /*with_output=*/false);
    const std::string generated = sim->scheduler.dataflow_markdown();
    const std::string doc = read_file(std::string(XCUT_SOURCE_DIR) + "/docs/architecture.md");
    const std::string begin = "<!-- dataflow:begin (xcut schedule scenes/open_surgery.json --dataflow) -->\n";
    const std::string end = "<!-- dataflow:end -->";
    const size_t b = doc.find(begin), e = doc.find(end);
    ASSERT_NE(b, std::string::npos) << "docs/architecture.md has no dataflow markers";
    ASSERT_NE(e, std::string::npos);
    EXPECT_EQ(doc.substr(b + begin.size(), e - b - begin.size()), generated)
        << "regenerate docs/architecture.md's data flow:\n" << generated;
    // Every system of the pipeline is in it, in order.
    size_t at = 0;
    for (const SystemDesc& s : sim->scheduler.registered()) {
        const size_t found = generated.find("| " + s.name + " |", at);
        ASSERT_NE(found, std::string::npos) << s.name;
        at = found;
    }
}

}  // namespace
}  // namespace xcut
