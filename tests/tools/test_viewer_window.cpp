// `xcut view` in a real window, as a person opens it: under Xvfb with Mesa's software OpenGL. A
// frame of the window against the headless Embree render of the same state, and a mouse drag
// (played from an input script) that cuts, shows the wound, and replays headless from its record.
#include <gtest/gtest.h>
#include <png.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "tests/test_helpers.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

#ifdef XCUT_HAS_VIEWER

struct Rgb {
    int width = 0, height = 0;
    std::vector<unsigned char> px;
};

Rgb read_png(const fs::path& path) {
    png_image img{};
    img.version = PNG_IMAGE_VERSION;
    Rgb out;
    if (!png_image_begin_read_from_file(&img, path.c_str())) return out;
    img.format = PNG_FORMAT_RGB;
    out.width = static_cast<int>(img.width), out.height = static_cast<int>(img.height);
    out.px.resize(PNG_IMAGE_SIZE(img));
    if (!png_image_finish_read(&img, nullptr, out.px.data(), 0, nullptr)) out.px.clear();
    return out;
}


std::string view(const std::string& args) {
    return std::string(XCUT_XVFB_RUN) + " -a -s '-screen 0 1280x1024x24' " + XCUT_BINARY + " view " + XCUT_SOURCE_DIR +
           "/scenes/skin_slab.json --size 800 --set mesh.element_size=0.003 " + args;
}

bool background(const Rgb& im, size_t i) {  // the renderer's background, 235 238 242
    return std::abs(im.px[3 * i] - 235) <= 3 && std::abs(im.px[3 * i + 1] - 238) <= 3 && std::abs(im.px[3 * i + 2] - 242) <= 3;
}

int elements_split(const std::string& out) {
    std::smatch m;
    return std::regex_search(out, m, std::regex(R"((\d+) elements split)")) ? std::stoi(m[1]) : -1;
}

// The window's frame and the Embree render of the snapshot it drew, from the same camera: their
// silhouettes (pixels not background) overlap by at least 95 % (intersection over union).
TEST(ViewerWindow, FrameMatchesTheHeadlessRender) {
    const fs::path dir = testing::temp_dir("viewer_frame");
    std::ofstream(dir / "keys.txt") << "0 key t\n0 key q\n0 key c\n0 key f\n";  // the surface alone
    std::string out;
    ASSERT_EQ(testing::run_command(view("--steps 20 --input " + (dir / "keys.txt").string() + " --screenshot " + (dir / "gl.png").string() +
                       " --reference " + (dir / "embree.png").string()), out), 0) << out;
    const Rgb gl = read_png(dir / "gl.png"), rt = read_png(dir / "embree.png");
    ASSERT_EQ(gl.width, 800);
    ASSERT_EQ(gl.height, 500);
    ASSERT_EQ(rt.width, gl.width);
    ASSERT_EQ(rt.px.size(), gl.px.size());
    long both = 0, either = 0, body = 0;
    for (size_t i = 0; i < gl.px.size() / 3; ++i) {
        const bool a = !background(gl, i), b = !background(rt, i);
        both += a && b, either += a || b, body += b;
    }
    EXPECT_GT(body, 800 * 500 / 10) << "the body fills a good part of the view";
    const double iou = double(both) / double(either);
    EXPECT_GE(iou, 0.95) << "silhouette overlap (intersection over union)";
    RecordProperty("silhouette_iou", std::to_string(iou));
    fs::remove_all(dir);
}

// A drag across the skin with the left button (an input script, one step a frame): elements split,
// the frame shows the wound's red inside, and the recorded session replays headless to the same cut.
TEST(ViewerWindow, MouseDragCutsShowsTheWoundAndReplays) {
    const fs::path dir = testing::temp_dir("viewer_drag");
    {
        std::ofstream in(dir / "drag.txt");
        in << "0 key t\n0 key q\n1 hover 480 340\n3 press 480 340\n";
        for (int i = 0; i < 30; ++i) in << 4 + i << " drag " << 480 - i << " " << 340 - 5 * i << "\n";
        in << "40 release\n";
    }
    std::string out;
    const std::string no_script = " --set 'tools=[]'";  // the hand scalpel alone
    ASSERT_EQ(testing::run_command(view("--steps 60" + no_script + " --input " + (dir / "drag.txt").string() + " --record " +
                       (dir / "session").string() + " --screenshot " + (dir / "cut.png").string()), out), 0) << out;
    const int split = elements_split(out);
    EXPECT_GT(split, 30) << out;
    const Rgb im = read_png(dir / "cut.png");
    ASSERT_FALSE(im.px.empty());
    long wound = 0;
    for (size_t i = 0; i < im.px.size() / 3; ++i)
        wound += im.px[3 * i] > 60 && im.px[3 * i] > 3 * im.px[3 * i + 1] && im.px[3 * i] > 3 * im.px[3 * i + 2];
    EXPECT_GT(wound, 100) << "red wound pixels in the frame";
    // The same window with no drag cuts nothing.
    std::ofstream(dir / "still.txt") << "0 key t\n";
    ASSERT_EQ(testing::run_command(view("--steps 10" + no_script + " --input " + (dir / "still.txt").string() + " --screenshot " +
                       (dir / "still.png").string()), out), 0) << out;
    EXPECT_EQ(elements_split(out), 0) << out;
    // Headless replay of the recorded session: the same scene (session.json adds the hand tools), the same cut.
    ASSERT_EQ(testing::run_command(std::string(XCUT_BINARY) + " run " + XCUT_SOURCE_DIR + "/scenes/skin_slab.json -q --steps 60 " +
                  "--set mesh.element_size=0.003" + no_script + " --replay " + (dir / "session").string() + " -o " +
                  (dir / "replay").string(), out), 0) << out;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(out, m, std::regex(R"(cut: (\d+) elements split)"))) << out;
    EXPECT_EQ(std::stoi(m[1]), split);
    fs::remove_all(dir);
}

// The same as a person does it: X input events from xdotool on the window (GLFW's own mouse path,
// the physics paced to real time): press, drag and release on the skin, right of the panels, then
// Esc. The viewer runs until Esc (30 s at most): on a loaded machine the window took 4 s to show and
// xdotool 5 s to drag, past the 3 s a fixed step count gave, and the drag came after the viewer had
// closed (0 elements split).
TEST(ViewerWindow, RealMouseDragFromXdotoolCuts) {
    const fs::path dir = testing::temp_dir("viewer_xdotool");
    {
        std::ofstream sh(dir / "drag.sh");
        sh << XCUT_BINARY << " view " << XCUT_SOURCE_DIR << "/scenes/skin_slab.json --steps 3000 --set 'tools=[]' "
           << "--screenshot " << (dir / "cut.png").string() << " > " << (dir / "view.log").string() << " 2>&1 & pid=$!\n"
           << "wid=$(" << XCUT_XDOTOOL << " search --sync --onlyvisible --name 'xcut view')\n"
           << "sleep 0.5\n"
           << XCUT_XDOTOOL << " mousemove --window $wid 760 500 mousedown 1\n"
           << "for i in $(seq 1 30); do " << XCUT_XDOTOOL
           << " mousemove --window $wid $((760 - i / 2)) $((500 - 8 * i)); sleep 0.02; done\n"
           << XCUT_XDOTOOL << " mouseup 1\n"
           << "sleep 0.5\n"  // the steps after the release: the last crossed elements split
           << XCUT_XDOTOOL << " key Escape\n"  // a tap: read at the next frame however long that takes
           << "wait $pid\n";
    }
    std::string out;
    ASSERT_EQ(testing::run_command(std::string(XCUT_XVFB_RUN) + " -a -s '-screen 0 1600x1200x24' bash " +
                                   (dir / "drag.sh").string(), out), 0) << out;
    std::ifstream log(dir / "view.log");
    std::stringstream ss;
    ss << log.rdbuf();
    EXPECT_GT(elements_split(ss.str()), 20) << ss.str();
    EXPECT_EQ(ss.str().find(", 3000 steps;"), std::string::npos) << "Esc closed it: " << ss.str();
    // The screenshot is taken at the run's end, which Esc came before: the viewer says it wrote none.
    EXPECT_NE(ss.str().find("warning: no screenshot written to " + (dir / "cut.png").string()), std::string::npos) << ss.str();
    EXPECT_FALSE(fs::exists(dir / "cut.png"));
    fs::remove_all(dir);
}

// Without --steps the viewer stops at the scene's duration, as a headless run does (it used to step
// on for ever: a screenshot waiting for it to be idle never came).
TEST(ViewerWindow, StopsAtTheScenesDuration) {
    const fs::path dir = testing::temp_dir("viewer_duration");
    std::string out;
    ASSERT_EQ(testing::run_command(view("--set duration=0.12 --set 'tools=[]' --screenshot " + (dir / "end.png").string()), out),
              0) << out;
    EXPECT_NE(out.find(", 12 steps;"), std::string::npos) << out;
    EXPECT_TRUE(fs::exists(dir / "end.png"));
    fs::remove_all(dir);
}

// Tissue of quadratic elements is cut by XFEM: the viewer opens a scene that has nothing else with
// the hand probe and the hand scalpel.
TEST(ViewerWindow, QuadraticTissueOpensWithTheProbeAndTheScalpel) {
    const fs::path dir = testing::temp_dir("viewer_quadratic");
    std::string out;
    ASSERT_EQ(testing::run_command(std::string(XCUT_XVFB_RUN) + " -a -s '-screen 0 1280x1024x24' " + XCUT_BINARY + " view " +
                                       XCUT_SOURCE_DIR + "/scenes/flap_lift.json --size 800 --steps 5 --screenshot " +
                                       (dir / "flap.png").string(), out), 0) << out;
    EXPECT_NE(out.find("hand scalpel on the left button"), std::string::npos) << out;
    EXPECT_NE(out.find("3 tools"), std::string::npos) << "the scene's probe, the hand scalpel and the hand probe: " << out;
    EXPECT_TRUE(fs::exists(dir / "flap.png"));
    fs::remove_all(dir);
}

// --timing-csv: every frame's and step's time kept; the summary printed and its row appended.
TEST(ViewerWindow, TimingLogSaysHowEvenlyFramesAndStepsCame) {
    const fs::path dir = testing::temp_dir("viewer_timing");
    const fs::path csv = dir / "timing.csv";
    std::string out;
    ASSERT_EQ(testing::run_command(view("--set duration=0.12 --set 'tools=[]' --screenshot " + (dir / "end.png").string() +
                                        " --timing-csv " + csv.string()), out), 0) << out;
    EXPECT_NE(out.find("timing (session, "), std::string::npos) << out;  // nothing split: no cut part
    EXPECT_NE(out.find("11 physics updates"), std::string::npos) << out;  // 12 steps
    std::ifstream in(csv);
    std::string header, row, extra;
    ASSERT_TRUE(std::getline(in, header) && std::getline(in, row)) << out;
    EXPECT_FALSE(std::getline(in, extra));
    EXPECT_EQ(header.rfind("scene,threads,part,seconds,frames,", 0), 0u) << header;
    EXPECT_EQ(std::count(row.begin(), row.end(), ','), std::count(header.begin(), header.end(), ',')) << row;
    EXPECT_EQ(row.rfind("skin_slab,2,session,", 0), 0u) << row;
    fs::remove_all(dir);
}

TEST(ViewerWindow, NoDisplayIsAClearError) {
    std::string out;
    EXPECT_EQ(testing::run_command("env -u DISPLAY -u WAYLAND_DISPLAY " + std::string(XCUT_BINARY) + " view " + XCUT_SOURCE_DIR +
                  "/scenes/skin_slab.json", out), 2) << out;
    EXPECT_NE(out.find("no display"), std::string::npos) << out;
}

#else

TEST(ViewerWindow, BuiltWithoutTheViewerSaysSo) {
    const std::string cmd = std::string(XCUT_BINARY) + " view " + XCUT_SOURCE_DIR + "/scenes/skin_slab.json > /dev/null 2>&1";
    const int status = std::system(cmd.c_str());
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2);
}

#endif

}  // namespace
}  // namespace xcut
