#include "tools/viewer/scripted_input.h"

#include <fmt/format.h>

#include <fstream>
#include <map>
#include <sstream>

#include "engine/error.h"

namespace xcut::viewer {

std::vector<InputEvent> read_input_script(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw InputError(path, "--input", "cannot read the input script");
    static const std::map<std::string, std::pair<InputEvent::Kind, int>> kinds = {
        {"hover", {InputEvent::kHover, 2}}, {"press", {InputEvent::kPress, 2}}, {"drag", {InputEvent::kDrag, 2}},
        {"release", {InputEvent::kRelease, 0}}, {"wheel", {InputEvent::kWheel, 1}}, {"key", {InputEvent::kKey, -1}}};
    std::vector<InputEvent> events;
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
        const std::string where = fmt::format("line {}", n);
        if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
        std::istringstream words(line);
        InputEvent e;
        std::string kind;
        if (!(words >> e.frame)) {
            if (words.eof() && line.find_first_not_of(" \t\r") == std::string::npos) continue;
            throw InputError(path, where, "expected: FRAME EVENT [ARGS] (a frame number first)");
        }
        if (e.frame < 0 || (!events.empty() && e.frame < events.back().frame))
            throw InputError(path, where, fmt::format("frame {} is negative or before the previous event's", e.frame));
        const auto k = kinds.find((words >> kind, kind));
        if (k == kinds.end())
            throw InputError(path, where, fmt::format("unknown event \"{}\" (hover, press, drag, release, wheel, key)", kind));
        e.kind = k->second.first;
        if (k->second.second == 2 && !(words >> e.x >> e.y)) throw InputError(path, where, kind + " needs X Y in pixels");
        if (k->second.second == 1 && !(words >> e.x)) throw InputError(path, where, "wheel needs a number of steps");
        if (k->second.second < 0 && !(words >> e.key)) throw InputError(path, where, "key needs a key name");
        std::string extra;
        if (words >> extra) throw InputError(path, where, fmt::format("unexpected \"{}\" after the event", extra));
        events.push_back(e);
    }
    return events;
}

}  // namespace xcut::viewer
