#pragma once
// The viewer's Dear ImGui panels: run controls, overlays, tools, and live readouts (the schedule's
// time per system, CG iterations and residual, DOFs, cut figures, plots of step time and energy).
#include <deque>
#include <string>
#include <vector>

#include "engine/devices/live_device.h"
#include "tools/viewer/gl_scene.h"
#include "tools/viewer/hand_tools.h"
#include "tools/viewer/physics_thread.h"

namespace xcut::viewer {

struct PanelState {
    std::string scene_name;
    PhysicsThread* physics = nullptr;
    MouseScalpel* scalpel = nullptr;             ///< null in 2D scenes
    std::vector<LiveDevice*> devices;            ///< per tool
    int selected_tool = -1;                      ///< the tool the keys move (-1: none)
    Overlays overlays;
    bool overlays_changed = false;
    bool fixed_dt = true;
    float dt_ms = 10.f;                          ///< [ms]
    std::deque<float> step_ms, energy;           ///< recent steps, oldest first [ms], [J]
    double frame_ms = 0.0;                       ///< last frame's time [ms]
    std::string recording;                       ///< the session directory, if recording
};

void draw_panels(const Snapshot& snap, PanelState& state);

}  // namespace xcut::viewer
