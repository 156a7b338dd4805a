// The picture of a world: framing that crops nothing, the tools drawn, materials told apart, the
// scale bar and the field's colour bar.
#include <gtest/gtest.h>

#include <set>

#include "engine/error.h"
#include "engine/io/image_overlay.h"
#include "engine/io/render.h"
#include "systems/pipeline.h"

namespace xcut {
namespace {

/// Where a point lands in the picture [px], by the pinhole model.
Eigen::Vector2d project(const Camera& c, const Vec3& p) {
    const Vec3 f = (c.target - c.position).normalized(), r = f.cross(c.up).normalized(), u = r.cross(f);
    const Vec3 q = p - c.position;
    const double half_h = std::tan(0.5 * c.fov_deg * M_PI / 180.0), half_w = half_h * c.width / c.height;
    return {(q.dot(r) / q.dot(f) / half_w + 1.0) * 0.5 * c.width, (1.0 - q.dot(u) / q.dot(f) / half_h) * 0.5 * c.height};
}

TEST(RenderWorld, FramingKeepsEveryPointInsideTheView) {
    // A long thin rod and a flat sheet: shapes a bounding-sphere framing crops or leaves tiny.
    for (const std::vector<Vec3>& points : {std::vector<Vec3>{{0, 0, 0}, {0.5, 0, 0}, {0.5, 0.01, 0.01}, {0, 0.01, 0}},
                                            std::vector<Vec3>{{-0.03, -0.02, 0}, {0.03, 0.02, 0.002}, {0.03, -0.02, 0}}}) {
        const Camera c = frame_points(points, 640, 360);
        double lo = 1e9, hi = -1e9;
        for (const Vec3& p : points) {
            const Eigen::Vector2d px = project(c, p);
            EXPECT_GE(px.x(), 0.0);
            EXPECT_LE(px.x(), 640.0);
            EXPECT_GE(px.y(), 0.0);
            EXPECT_LE(px.y(), 360.0);
            lo = std::min(lo, px.x()), hi = std::max(hi, px.x());
        }
        EXPECT_GT(hi - lo, 0.3 * 640) << "framed, not lost in the middle";
    }
}

struct Rendered {
    std::unique_ptr<Simulation> sim;
    Scene scene;
};

Rendered run(const std::string& scene_file, int steps) {
    Rendered r;
    r.scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/" + scene_file);
    r.sim = make_simulation(r.scene, false);
    for (int i = 0; i < steps; ++i) step_simulation(*r.sim);
    return r;
}

int count_colour(const Image& img, const std::array<unsigned char, 3>& rgb) {
    int n = 0;
    for (size_t i = 0; i < img.rgb.size(); i += 3) n += img.rgb[i] == rgb[0] && img.rgb[i + 1] == rgb[1] && img.rgb[i + 2] == rgb[2];
    return n;
}

TEST(RenderWorld, ToolsAreDrawnAndFramed) {
    Rendered r = run("open_surgery.json", 2);  // a retractor (box) and a probe (sphere) above the skin
    RenderOptions with, without;
    without.tools = false;
    const Camera c = frame_world(r.sim->world, 320, 240, with);
    const Image a = render_world(r.sim->world, c, with), b = render_world(r.sim->world, c, without);
    const int surface = static_cast<int>(r.sim->world.visual.triangles.size());
    int tool_pixels = 0;
    for (int t : a.triangle) tool_pixels += t >= surface;
    EXPECT_GT(tool_pixels, 200);
    for (int t : b.triangle) EXPECT_LT(t, surface);
    for (const Vec3& p : r.sim->world.tools.position) {  // every tool inside the picture
        const Eigen::Vector2d px = project(c, p);
        EXPECT_GT(px.x(), 0.0);
        EXPECT_LT(px.x(), 320.0);
        EXPECT_GT(px.y(), 0.0);
        EXPECT_LT(px.y(), 240.0);
    }
}

TEST(RenderWorld, MaterialsGetColoursOfTheirOwn) {
    Rendered r = run("layered_incision.json", 0);  // skin, fat and muscle
    RenderOptions o;
    o.tools = false, o.scale_bar = false;
    const Camera c = frame_world(r.sim->world, 320, 240, o);
    const Image img = render_world(r.sim->world, c, o);
    std::set<int> materials;  // of the elements whose triangles show
    for (int t : img.triangle)
        if (t >= 0) materials.insert(r.sim->world.elements.material[r.sim->world.visual.triangle_owner[t]]);
    ASSERT_GE(materials.size(), 2u);
    // Lit the same way, two materials' pixels differ in hue: count distinct chroma directions.
    std::set<std::array<int, 2>> hues;
    for (size_t i = 0; i < img.rgb.size(); i += 3) {
        if (img.triangle[i / 3] < 0) continue;
        const double s = img.rgb[i] + img.rgb[i + 1] + img.rgb[i + 2] + 1e-9;
        hues.insert({int(20 * img.rgb[i] / s), int(20 * img.rgb[i + 1] / s)});
    }
    EXPECT_GE(hues.size(), 2u);
}

TEST(RenderWorld, FieldGetsAColourBarAndTheBodiesStayLeftOfIt) {
    Rendered r = run("skin_slab.json", 10);
    RenderOptions o;
    o.field = "von_mises";
    const Camera c = frame_world(r.sim->world, 400, 300, o);
    const Image img = render_world(r.sim->world, c, o);
    ASSERT_EQ(img.width, 400);
    int right_hits = 0, bar = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 300; x < img.width; ++x) right_hits += img.triangle[y * img.width + x] >= 0;
    EXPECT_EQ(right_hits, 0) << "the bodies are drawn left of the colour bar";
    const Rgb top = field_colour(1.0), foot = field_colour(0.0);
    for (const Rgb& rgb : {top, foot})
        bar += count_colour(img, {static_cast<unsigned char>(std::lround(255 * rgb[0])),
                                  static_cast<unsigned char>(std::lround(255 * rgb[1])),
                                  static_cast<unsigned char>(std::lround(255 * rgb[2]))});
    EXPECT_GT(bar, 10) << "the bar's two ends, unshaded";
    o.field = "temperature";
    EXPECT_THROW(render_world(r.sim->world, c, o), InputError);
}

TEST(RenderWorld, ScaleBarIsARoundLengthNearAFifthOfTheWidth) {
    Image img;
    img.width = 500, img.height = 300;
    img.rgb.assign(3 * 500 * 300, 255);
    draw_scale_bar(img, 8000.0);  // 8 px/mm: a fifth is 12.5 mm, drawn as 10 mm = 80 px
    int dark_in_row = 0;
    const int y = img.height - 14 + 1;
    for (int x = 0; x < img.width; ++x) dark_in_row += img.rgb[3 * (y * img.width + x)] < 100;
    EXPECT_EQ(dark_in_row, 80);
    EXPECT_EQ(text_width("10 mm", 1), 30);
}

}  // namespace
}  // namespace xcut
