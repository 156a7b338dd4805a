#include "tools/viewer/viewer_app.h"

#include <epoxy/gl.h>
#include <GLFW/glfw3.h>
#include <fmt/format.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <thread>

#include "engine/error.h"
#include "engine/parallel.h"
#include "systems/pipeline.h"
#include "tools/viewer/panels.h"
#include "tools/viewer/scripted_input.h"
#include "tools/viewer/viewer_session.h"
#include "tools/viewer/viewer_timing.h"

namespace xcut::viewer {

namespace {

using Clock = std::chrono::steady_clock;

double wheel_steps = 0.0;  // GLFW's scroll callback has no user pointer of ours to spare: one window
void on_scroll(GLFWwindow*, double, double dy) { wheel_steps += dy; }

/// The window, its GL context and ImGui; torn down in reverse.
struct Window {
    GLFWwindow* handle = nullptr;
    Window(const ViewerOptions& o, const std::string& title) {
        if (!glfwInit())
            throw InputError("xcut view", "display", "cannot open a window: no display (set DISPLAY, or run under xvfb-run)");
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GL_TRUE);
        handle = glfwCreateWindow(o.width, o.height, title.c_str(), nullptr, nullptr);
        if (!handle) {
            glfwTerminate();
            throw InputError("xcut view", "display", "cannot create an OpenGL 3.3 core window");
        }
        glfwMakeContextCurrent(handle);
        glfwSwapInterval(o.input.empty() && o.screenshot.empty() ? 1 : 0);
        glfwSetScrollCallback(handle, on_scroll);  // before ImGui, which chains to it
        // A key or button pressed and released between two frames (a quick tap on a loaded machine,
        // where a frame can take longer than the tap) still reads as pressed at the next frame.
        glfwSetInputMode(handle, GLFW_STICKY_KEYS, GLFW_TRUE);
        glfwSetInputMode(handle, GLFW_STICKY_MOUSE_BUTTONS, GLFW_TRUE);
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;
        ImGui::StyleColorsLight();
        ImGui_ImplGlfw_InitForOpenGL(handle, true);
        ImGui_ImplOpenGL3_Init("#version 330 core");
    }
    ~Window() {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
        glfwDestroyWindow(handle);
        glfwTerminate();
    }
};

/// Mouse, wheel and key input, from the window or from a script, applied to the camera and tools.
class Input {
public:
    Input(ViewerSession& session, PanelState& panel, OrbitCamera& camera) : s_(session), panel_(panel), camera_(camera) {}

    void mouse(double x, double y, bool left, bool right, bool middle, bool shift, int w, int h) {
        const double dx = x - x_, dy = y - y_;
        if (right && !shift && right_) camera_.orbit(dx * 0.008, dy * 0.008);
        if ((middle && middle_) || (right && shift && right_)) camera_.pan(dx / h, dy / h);
        if (s_.scalpel) {
            const Ray ray = camera_.ray(x, y, w, h);
            if (left != left_ || left || x != x_ || y != y_) {
                const auto hit = s_.cast(ray);
                if (left && !left_) s_.scalpel->press(hit);
                else if (left) s_.scalpel->drag(ray, hit);
                else if (left_) s_.scalpel->release();
                else s_.scalpel->hover(hit);
                if (hit) last_hit_ = hit->point + hit->normal * s_.sizes.probe_radius;
            }
        }
        x_ = x, y_ = y, left_ = left, right_ = right, middle_ = middle;
    }
    void wheel(double steps, bool shift) {
        if ((shift || left_) && s_.scalpel)
            s_.scalpel->depth = std::clamp(s_.scalpel->depth + 0.05 * steps * s_.scalpel->max_depth, 0.0, s_.scalpel->max_depth);
        else if (steps != 0.0)
            camera_.zoom(std::pow(0.9, steps));
    }
    void key(const std::string& k) {
        Overlays& o = panel_.overlays;
        static const std::map<std::string, bool Overlays::*> toggles = {
            {"t", &Overlays::tools}, {"m", &Overlays::mesh}, {"v", &Overlays::virtuals},
            {"q", &Overlays::quad}, {"c", &Overlays::contacts}, {"f", &Overlays::force}};
        if (const auto t = toggles.find(k); t != toggles.end()) o.*(t->second) = !(o.*(t->second)), panel_.overlays_changed = true;
        if (k == "space") s_.physics->play(!s_.physics->playing());
        if (k == "n") s_.physics->single_step();
        if (k == "g" && last_hit_ && s_.probe >= 0) s_.devices[s_.probe]->set_target(*last_hit_, Eigen::Quaterniond::Identity());
    }
    /// Arrow and page keys move the selected tool at 10 % of the body's size a second.
    void move_selected(const Vec3& axes, double seconds) {
        const int i = panel_.selected_tool;
        if (i < 0 || i >= static_cast<int>(s_.devices.size()) || !s_.devices[i] || !s_.devices[i]->live() || axes.isZero())
            return;
        const Vec3 fwd = (camera_.target - camera_.position).normalized();
        const Vec3 right = fwd.cross(Vec3::UnitZ()).normalized(), ahead = Vec3::UnitZ().cross(right);
        const Keyframe k = s_.devices[i]->target();
        const Vec3 move = (axes.x() * right + axes.y() * ahead + axes.z() * Vec3::UnitZ()) * s_.sizes.speed * seconds;
        s_.devices[i]->set_target(k.position + move, k.orientation);
    }

private:
    ViewerSession& s_;
    PanelState& panel_;
    OrbitCamera& camera_;
    double x_ = 0.0, y_ = 0.0;
    bool left_ = false, right_ = false, middle_ = false;
    std::optional<Vec3> last_hit_;
};

void window_input(GLFWwindow* win, Input& in, int w, int h, double seconds) {
    const ImGuiIO& io = ImGui::GetIO();
    double x, y;
    glfwGetCursorPos(win, &x, &y);
    int ww, wh;
    glfwGetWindowSize(win, &ww, &wh);
    x *= double(w) / std::max(ww, 1), y *= double(h) / std::max(wh, 1);
    const bool shift = glfwGetKey(win, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS || glfwGetKey(win, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
    if (!io.WantCaptureMouse) {
        in.mouse(x, y, glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS,
                 glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS,
                 glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS, shift, w, h);
        in.wheel(wheel_steps, shift);
    }
    wheel_steps = 0.0;
    if (io.WantCaptureKeyboard) return;
    static std::map<int, bool> down;
    static const std::map<int, std::string> names = {{GLFW_KEY_SPACE, "space"}, {GLFW_KEY_N, "n"}, {GLFW_KEY_T, "t"},
        {GLFW_KEY_M, "m"}, {GLFW_KEY_V, "v"}, {GLFW_KEY_Q, "q"}, {GLFW_KEY_C, "c"}, {GLFW_KEY_F, "f"}, {GLFW_KEY_G, "g"}};
    for (const auto& [code, name] : names) {
        const bool now = glfwGetKey(win, code) == GLFW_PRESS;
        if (now && !down[code]) in.key(name);
        down[code] = now;
    }
    auto held = [win](int k) { return glfwGetKey(win, k) == GLFW_PRESS ? 1.0 : 0.0; };
    in.move_selected(Vec3(held(GLFW_KEY_RIGHT) - held(GLFW_KEY_LEFT), held(GLFW_KEY_UP) - held(GLFW_KEY_DOWN),
                          held(GLFW_KEY_PAGE_UP) - held(GLFW_KEY_PAGE_DOWN)), seconds);
    if (glfwGetKey(win, GLFW_KEY_ESCAPE) == GLFW_PRESS) glfwSetWindowShouldClose(win, 1);
}

void scripted_input(const std::vector<InputEvent>& events, size_t& next, int frame, Input& in, int w, int h) {
    for (; next < events.size() && events[next].frame <= frame; ++next) {
        const InputEvent& e = events[next];
        static bool held = false;
        switch (e.kind) {
        case InputEvent::kHover: in.mouse(e.x, e.y, false, false, false, false, w, h); break;
        case InputEvent::kPress:
        case InputEvent::kDrag: held = true, in.mouse(e.x, e.y, true, false, false, false, w, h); break;
        case InputEvent::kRelease: held = false, in.mouse(-1, -1, false, false, false, false, w, h); break;
        case InputEvent::kWheel: in.wheel(e.x, held); break;
        case InputEvent::kKey: in.key(e.key); break;
        }
    }
}

/// The benchmark's phases: a second drawing, a second not, ...; counts the physics' steps in each.
class BenchBook {
public:
    BenchBook(double seconds, const PhysicsThread& physics) : seconds_(seconds), physics_(physics) {}
    /// After a frame: closes a drawing phase that is over and sits out the idle one that follows;
    /// false once the benchmark is over.
    bool idle_phase() {
        if (seconds_done() < 1.0) return true;
        close(figures.steps_drawing, figures.seconds_drawing);
        figures.frame_ms.pop_back();  // the first frame after a pause starts cold
        std::this_thread::sleep_for(std::chrono::seconds(1));  // the window is up but draws nothing
        close(figures.steps_idle, figures.seconds_idle);
        return figures.seconds_drawing + figures.seconds_idle < seconds_;
    }
    BenchFigures figures;

private:
    double seconds_done() const { return std::chrono::duration<double>(Clock::now() - phase_start_).count(); }
    void close(long& steps, double& seconds) {
        const int done = physics_.steps_done();
        steps += done - steps_at_start_, seconds += seconds_done();
        steps_at_start_ = done, phase_start_ = Clock::now();
    }
    double seconds_;
    const PhysicsThread& physics_;
    Clock::time_point phase_start_ = Clock::now();
    int steps_at_start_ = 0;
};

void push_history(std::deque<float>& d, float v) {
    d.push_back(v);
    while (d.size() > 300) d.pop_front();
}

}  // namespace

int run_viewer(const ViewerOptions& o) {
    set_thread_count(o.threads);
    // Mesa's software renderer (llvmpipe: no GPU, a virtual display) draws on as many threads as
    // there are cores, taking them from the physics: one is enough for this scene's frames, and
    // the physics kept 95 % of its headless rate against 80 % (docs/viewer.md). GPU drivers ignore it.
    setenv("LP_NUM_THREADS", "1", 0);
    ViewerSession session(o);
    const std::vector<InputEvent> events = o.input.empty() ? std::vector<InputEvent>{} : read_input_script(o.input);
    const bool scripted = !o.input.empty();
    PhysicsThread& physics = *session.physics;
    physics.set_lockstep(scripted);
    // The scene's duration ends the run as it does headless (play goes on past it); a benchmark
    // measures the rate for as long as it is asked, so it has no limit.
    physics.set_step_limit(o.steps >= 0 ? o.steps : o.run_on || o.bench_seconds > 0.0 ? -1 : session.scene.steps);
    physics.play(!o.paused);
    physics.set_paced(o.bench_seconds <= 0.0 && !scripted);
    physics.keep_timings(!o.timing_csv.empty());
    physics.start();
    // The physics (and its OpenMP team, made from its thread) keeps the normal priority; this thread,
    // and the renderer's threads it makes with the context, yield to it when the cores are short.
    ::setpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()), 10);
    Window window(o, "xcut view: " + session.scene.name);
    GlScene gl;
    PanelState panel;
    panel.scene_name = session.scene.name;
    panel.physics = session.physics.get();
    panel.scalpel = session.scalpel.get();
    panel.devices = session.devices;
    panel.selected_tool = session.probe;
    panel.fixed_dt = !session.scene.solver.realtime;
    panel.dt_ms = static_cast<float>(session.scene.solver.dt * 1e3);
    panel.recording = o.record;
    // Software OpenGL (Mesa's llvmpipe: a virtual display, no GPU) draws on the CPU, beside the
    // physics: there the frame cap is halved unless the user set one (docs/viewer.md, the figures).
    const std::string renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const bool software = renderer.find("llvmpipe") != std::string::npos || renderer.find("softpipe") != std::string::npos;
    const double fps = software && !o.fps_given ? o.fps / 2 : o.fps;
    fmt::print("OpenGL: {} ({}), frames capped at {} a second\n", renderer,
               software ? "software: on the CPU, beside the physics" : "hardware", fps);
    OrbitCamera camera = session.initial_camera(o.width, o.height);
    Input input(session, panel, camera);
    BenchBook bench(o.bench_seconds, physics);
    TimingLog timing;
    size_t next_event = 0;
    int allowed = 0;
    auto last = Clock::now();
    bool shot = false;  // the screenshot asked for is written
    for (int frame = 0; !glfwWindowShouldClose(window.handle); ++frame) {
        glfwPollEvents();
        int w, h;
        glfwGetFramebufferSize(window.handle, &w, &h);
        const auto now = Clock::now();
        if (!o.timing_csv.empty()) timing.frame_start.push_back(wall_seconds());
        const double seconds = std::chrono::duration<double>(now - last).count();
        last = now;
        bool fresh = false;
        if (scripted) {  // one step a frame, each after the frame's events: the same cut every run
            while (physics.steps_done() < allowed && !physics.failed()) std::this_thread::sleep_for(std::chrono::microseconds(200));
            fresh = session.refresh();
            scripted_input(events, next_event, frame, input, w, h);
            if (o.steps < 0 || allowed < o.steps) physics.allow_steps(1), ++allowed;
        } else {
            window_input(window.handle, input, w, h, seconds);
        }
        if (session.refresh() || fresh) {
            const Snapshot& s = session.buffer.front();
            push_history(panel.step_ms, static_cast<float>(s.step_ms));
            push_history(panel.energy, static_cast<float>(s.kinetic + s.elastic));
            gl.upload(s, panel.overlays);
        } else if (panel.overlays_changed) {
            gl.upload(session.buffer.front(), panel.overlays);
        }
        if (panel.overlays_changed) physics.set_options({panel.overlays.mesh, panel.overlays.virtuals});
        panel.overlays_changed = false;
        gl.draw(camera, w, h);
        const bool events_done = next_event >= events.size() && (!scripted || allowed >= std::max(o.steps, 0));
        const bool shoot = !o.screenshot.empty() && events_done && physics.idle() &&
                           session.buffer.front().step == session.first_step + physics.steps_done();
        if (shoot && !o.panels) {
            session.save_screenshot(read_framebuffer(w, h), camera, o);
            shot = true;
            break;
        }
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        draw_panels(session.buffer.front(), panel);
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        if (shoot && frame > 2) {  // panels: a few frames in, once ImGui has laid them out
            session.save_screenshot(read_framebuffer(w, h), camera, o);
            shot = true;
            break;
        }
        glfwSwapBuffers(window.handle);
        const double work_ms = std::chrono::duration<double, std::milli>(Clock::now() - now).count();
        if (fps > 0 && !scripted)  // a frame cap where no vsync holds the loop (virtual displays, some drivers)
            std::this_thread::sleep_until(now + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / fps)));
        panel.frame_ms = seconds * 1e3;
        if (o.bench_seconds > 0.0) {
            if (frame > 0) bench.figures.frame_ms.push_back(work_ms);
            if (!bench.idle_phase()) break;
        }
    }
    physics.stop();
    if (!o.screenshot.empty() && !shot && o.bench_seconds <= 0.0)
        fmt::print("warning: no screenshot written to {}: the window was closed (Esc) before the run's end, where it is "
                   "taken\n", o.screenshot);
    if (o.bench_seconds > 0.0) session.report_bench(bench.figures);
    if (!o.timing_csv.empty()) {
        timing.steps = physics.timings();
        report_timing(timing, session.scene.name, o.threads, o.timing_csv);
    }
    return session.finish();
}

}  // namespace xcut::viewer
