#include "tools/viewer/panels.h"

#include <imgui.h>

#include <algorithm>
#include <vector>

namespace xcut::viewer {

namespace {

void run_controls(const Snapshot& s, PanelState& st) {
    PhysicsThread& p = *st.physics;
    if (ImGui::Button(p.playing() ? "Pause (space)" : "Play (space)")) p.play(!p.playing());
    ImGui::SameLine();
    if (ImGui::Button("Step (n)")) p.single_step();
    bool paced = p.paced();
    if (ImGui::Checkbox("Keep to real time", &paced)) p.set_paced(paced);
    if (st.fixed_dt && ImGui::SliderFloat("dt [ms]", &st.dt_ms, 0.5f, 40.f, "%.1f")) p.set_dt(st.dt_ms * 1e-3);
    ImGui::Text("t = %.3f s, step %d, dt %.2f ms", s.time, s.step, s.dt * 1e3);
    ImGui::Text("real-time factor %.2f, step %.2f ms, frame %.1f ms", s.realtime_factor, s.step_ms, st.frame_ms);
    if (!st.recording.empty()) ImGui::TextColored(ImVec4(0.9f, 0.2f, 0.2f, 1.f), "recording to %s", st.recording.c_str());
    if (p.failed()) ImGui::TextColored(ImVec4(0.9f, 0.1f, 0.1f, 1.f), "stopped: %s", p.error().c_str());
}

void overlay_controls(PanelState& st) {
    Overlays& o = st.overlays;
    const Overlays before = o;
    ImGui::Checkbox("tools (t)", &o.tools);
    ImGui::SameLine();
    ImGui::Checkbox("mesh (m)", &o.mesh);
    ImGui::SameLine();
    ImGui::Checkbox("virtual elements (v)", &o.virtuals);
    ImGui::Checkbox("collision quad (q)", &o.quad);
    ImGui::SameLine();
    ImGui::Checkbox("contacts (c)", &o.contacts);
    ImGui::SameLine();
    ImGui::Checkbox("force (f)", &o.force);
    st.overlays_changed |= !(before == o);
}

void tool_controls(const Snapshot& s, PanelState& st) {
    if (st.scalpel) {
        float depth = static_cast<float>(st.scalpel->depth * 1e3);
        if (ImGui::SliderFloat("blade depth [mm]", &depth, 0.f, static_cast<float>(st.scalpel->max_depth * 1e3)))
            st.scalpel->depth = depth * 1e-3;
    }
    for (size_t i = 0; i < s.tools.size() && i < st.devices.size(); ++i) {
        const ToolView& t = s.tools[i];
        ImGui::PushID(static_cast<int>(i));
        LiveDevice* d = st.devices[i];
        if (ImGui::RadioButton(t.name.c_str(), st.selected_tool == static_cast<int>(i))) st.selected_tool = static_cast<int>(i);
        ImGui::SameLine();
        if (d && !d->live()) {
            if (ImGui::SmallButton("take over")) d->take_over(), st.selected_tool = static_cast<int>(i);
        } else if (d) {
            Keyframe k = d->target();
            float p[3] = {float(k.position.x() * 1e3), float(k.position.y() * 1e3), float(k.position.z() * 1e3)};
            ImGui::SetNextItemWidth(220.f);
            if (ImGui::DragFloat3("[mm]", p, 0.1f)) d->set_target(Vec3(p[0], p[1], p[2]) * 1e-3, k.orientation);
        }
        ImGui::SameLine();
        ImGui::Text("|F| %.3f N", t.force.norm());
        ImGui::PopID();
    }
    ImGui::TextDisabled("shift+wheel: depth; arrows, page up/down: the selected tool; g: probe here");
}

void plot(const char* label, const std::deque<float>& values, const char* unit) {
    std::vector<float> v(values.begin(), values.end());
    const float last = v.empty() ? 0.f : v.back();
    char overlay[64];
    std::snprintf(overlay, sizeof(overlay), "%.4g %s", last, unit);
    ImGui::PlotLines(label, v.data(), static_cast<int>(v.size()), 0, overlay, FLT_MAX, FLT_MAX, ImVec2(0, 50));
}

void readouts(const Snapshot& s, PanelState& st) {
    ImGui::Text("linear solve: %s, %d CG iterations, residual %.2e", s.linear.c_str(), s.cg_iterations, s.cg_residual);
    ImGui::Text("DOFs %d, enriched nodes %d, elements split %d", s.dofs, s.enriched_nodes, s.elements_split);
    if (s.pieces_freed > 0) ImGui::Text("pieces %d (%d freed by cuts)", s.pieces, s.pieces_freed);
    ImGui::Text("kinetic %.3e J, elastic %.3e J", s.kinetic, s.elastic);
    if (ImGui::BeginTable("schedule", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingFixedFit)) {
        for (size_t i = 0; i < s.systems.size(); ++i) {
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(0);
            ImGui::TextUnformatted(s.systems[i].c_str());
            ImGui::TableSetColumnIndex(1);
            ImGui::Text("%.3f ms", i < s.system_ms.size() ? s.system_ms[i] : 0.0);
        }
        ImGui::EndTable();
    }
    plot("step time", st.step_ms, "ms");
    plot("energy", st.energy, "J");
}

}  // namespace

void draw_panels(const Snapshot& snap, PanelState& st) {
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(470, 0), ImGuiCond_FirstUseEver);
    ImGui::Begin(("xcut: " + st.scene_name).c_str());
    run_controls(snap, st);
    if (ImGui::CollapsingHeader("Overlays", ImGuiTreeNodeFlags_DefaultOpen)) overlay_controls(st);
    if (ImGui::CollapsingHeader("Tools", ImGuiTreeNodeFlags_DefaultOpen)) tool_controls(snap, st);
    if (ImGui::CollapsingHeader("Solver and schedule", ImGuiTreeNodeFlags_DefaultOpen)) readouts(snap, st);
    ImGui::End();
}

}  // namespace xcut::viewer
