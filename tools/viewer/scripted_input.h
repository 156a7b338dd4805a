#pragma once
// `xcut view --input FILE`: mouse and key events played at given frames, for tests and demos that
// must cut the same way every time (the physics then steps once per frame). One event a line:
//     FRAME hover X Y | press X Y | drag X Y | release | wheel STEPS | key NAME
// X, Y in window pixels from the top-left corner; NAME one of the viewer's keys (space, n, m, v,
// ...: docs/viewer.md). '#' starts a comment. Frames must not decrease.
#include <string>
#include <vector>

namespace xcut::viewer {

struct InputEvent {
    enum Kind { kHover, kPress, kDrag, kRelease, kWheel, kKey };
    int frame = 0;
    Kind kind = kHover;
    double x = 0.0, y = 0.0;  ///< pixels; wheel: steps in x
    std::string key;
};

/// Throws InputError naming the file and line.
std::vector<InputEvent> read_input_script(const std::string& path);

}  // namespace xcut::viewer
