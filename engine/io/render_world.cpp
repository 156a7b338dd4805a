// The picture of a world (engine/io/render.h): the visual surface coloured by material or region
// (the wound in red) or by a field, the tools, a scale bar and, for a field, a colour bar.
#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "engine/error.h"
#include "engine/io/cell_stress.h"
#include "engine/io/image_overlay.h"
#include "engine/io/render.h"
#include "engine/io/tool_meshes.h"

namespace xcut {
namespace {

using Colour = std::array<double, 3>;

/// Tissue tones, one per material (or region): skin, fat, muscle, then further distinct ones.
constexpr std::array<Colour, 8> kTissue = {{{0.93, 0.76, 0.66}, {0.96, 0.86, 0.52}, {0.74, 0.36, 0.33},
                                           {0.60, 0.70, 0.88}, {0.66, 0.84, 0.62}, {0.84, 0.66, 0.88},
                                           {0.55, 0.80, 0.80}, {0.88, 0.62, 0.45}}};
constexpr Colour kWound = {0.80, 0.12, 0.12}, kTool = {0.52, 0.56, 0.62}, kBlade = {0.80, 0.83, 0.88};

/// The field's value on each visual triangle: von Mises of the element its first vertex is bound to
/// (a virtual element past a cut, so each lip shows its side) [Pa], or the mean displacement of the
/// owning mesh element's nodes [m].
std::vector<double> triangle_field(const World& w, const std::string& field) {
    const SurfaceMesh& s = w.visual;
    std::vector<double> value(s.triangles.size(), 0.0);
    for (size_t t = 0; t < s.triangles.size(); ++t) {
        if (field == "von_mises") {
            value[t] = von_mises(cell_cauchy_stress(w, s.element[s.triangles[t][0]]));
        } else {
            const auto& n = w.elements.nodes[s.triangle_owner[t]];
            const int per = w.elements.nodes_per_element();
            for (int k = 0; k < per; ++k) value[t] += (w.nodes.position[n[k]] - w.nodes.rest[n[k]]).norm() / per;
        }
    }
    return value;
}

/// Pixels on the right kept for the colour bar and its labels.
int colour_bar_strip(const RenderOptions& o, int width, int height) {
    return o.field.empty() ? 0 : std::min(width / 3, 110 * overlay_scale(height));
}

}  // namespace

Camera frame_world(const World& world, int width, int height, const RenderOptions& options) {
    std::vector<Vec3> points = world.visual.position;
    if (options.tools) {
        const ToolTriangles tools = tool_triangles(world.tools, 0.0);
        points.insert(points.end(), tools.position.begin(), tools.position.end());
    }
    Camera c = frame_points(points, width - colour_bar_strip(options, width, height), height);
    c.width = width;
    return c;
}

Image render_world(const World& w, const Camera& camera, const RenderOptions& o) {
    if (!o.field.empty() && o.field != "von_mises" && o.field != "displacement")
        throw InputError("render", "--field", fmt::format("\"{}\" is not a field (von_mises, displacement)", o.field));
    const SurfaceMesh& s = w.visual;
    std::vector<Vec3> positions = s.position;
    std::vector<std::array<int, 3>> triangles = s.triangles;
    std::vector<Colour> colours(triangles.size());
    double low = 0.0, high = 0.0;
    if (o.field.empty()) {
        // By material when the tissue has several, else by region (a Gmsh physical group).
        std::set<int> materials, regions;
        for (int e = 0; e < w.mesh_elements; ++e) materials.insert(w.elements.material[e]), regions.insert(w.elements.region[e]);
        const bool by_material = materials.size() > 1;
        std::vector<int> keys(by_material ? materials.begin() : regions.begin(), by_material ? materials.end() : regions.end());
        for (size_t t = 0; t < triangles.size(); ++t) {
            const int e = s.triangle_owner[t];
            const int key = by_material ? w.elements.material[e] : w.elements.region[e];
            const size_t i = std::lower_bound(keys.begin(), keys.end(), key) - keys.begin();
            colours[t] = t < s.cut_face.size() && s.cut_face[t] ? kWound : kTissue[i % kTissue.size()];
        }
    } else {
        const std::vector<double> value = triangle_field(w, o.field);
        if (!value.empty()) low = *std::min_element(value.begin(), value.end()), high = *std::max_element(value.begin(), value.end());
        for (size_t t = 0; t < triangles.size(); ++t)
            colours[t] = field_colour(high > low ? (value[t] - low) / (high - low) : 0.0);
    }
    if (o.tools) {
        const ToolTriangles tools = tool_triangles(w.tools, 0.02 * (camera.target - camera.position).norm());
        const int base = static_cast<int>(positions.size());
        positions.insert(positions.end(), tools.position.begin(), tools.position.end());
        for (size_t t = 0; t < tools.triangles.size(); ++t) {
            const auto& tri = tools.triangles[t];
            triangles.push_back({base + tri[0], base + tri[1], base + tri[2]});
            colours.push_back(tools.blade[t] ? kBlade : kTool);
        }
    }
    // With a colour bar, the bodies are drawn left of it, the camera's view narrowed to that part.
    const int strip = colour_bar_strip(o, camera.width, camera.height);
    Camera view = camera;
    view.width -= strip;
    const Image part = render_triangles(positions, triangles, colours, view);
    Image img = part;
    if (strip > 0) {
        img.width = camera.width;
        img.rgb.assign(3 * size_t(img.width) * img.height, 0);
        img.triangle.assign(size_t(img.width) * img.height, -1);
        fill_rect(img, 0, 0, img.width, img.height, {235 / 255.0, 238 / 255.0, 242 / 255.0});
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < part.width; ++x) {
                const size_t from = size_t(y) * part.width + x, to = size_t(y) * img.width + x;
                for (int k = 0; k < 3; ++k) img.rgb[3 * to + k] = part.rgb[3 * from + k];
                img.triangle[to] = part.triangle[from];
            }
    }
    if (o.scale_bar) draw_scale_bar(img, pixels_per_metre(view));
    if (o.field == "von_mises") draw_colour_bar(img, low, high, "Pa", "von Mises");
    if (o.field == "displacement") draw_colour_bar(img, 1e3 * low, 1e3 * high, "mm", "|u|");
    return img;
}

}  // namespace xcut
