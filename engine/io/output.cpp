#include "engine/io/output.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/os.h>

#include "engine/error.h"
#include "engine/parallel.h"
#include "engine/io/cell_stress.h"
#include "engine/io/clipped_cells.h"
#include "engine/io/metrics_columns.h"
#include "engine/io/vtu_writer.h"

namespace xcut {
namespace {

int vtk_cell_type(int dim) { return dim == 3 ? 10 : 5; }  // VTK_TETRA, VTK_TRIANGLE

}  // namespace

void write_vtu(const World& world, const std::string& path) {
    const Nodes& n = world.nodes;
    const Elements& el = world.elements;
    // Cells: every element that carries material (weight > 0): uncut mesh elements, and the virtual
    // elements of cut ones clipped to their sides, so ParaView shows the opening.
    const ClippedCells shown = clipped_cells(world);
    std::vector<int> side(el.count(), 0), parent(el.count());
    for (int e = 0; e < world.mesh_elements; ++e) parent[e] = e;
    for (int v = 0; v < world.virtual_elements.count(); ++v) {
        side[world.virtual_elements.element[v]] = world.virtual_elements.side[v];
        parent[world.virtual_elements.element[v]] = world.virtual_elements.parent[v];
    }
    VtuWriter vtu(world.output.ascii);
    const size_t points = shown.position.size();
    std::vector<double> xyz, u, v;  // each array sized once: a file of 53k cells is written beside the step
    xyz.reserve(3 * points), u.reserve(3 * points), v.reserve(3 * points);
    for (size_t i = 0; i < points; ++i)
        for (int k = 0; k < 3; ++k) {
            xyz.push_back(shown.position[i][k]);
            u.push_back(shown.position[i][k] - shown.rest[i][k]);
            v.push_back(shown.velocity[i][k]);
        }
    vtu.points(xyz);
    vtu.point_data("displacement_m", 3, u);
    vtu.point_data("velocity_m_per_s", 3, v);
    std::vector<uint8_t> fixed(points, 0), enriched(points, 0);
    for (int i = 0; i < n.count(); ++i) fixed[i] = n.fixed[i], enriched[i] = i >= world.mesh_nodes;
    for (size_t i = n.count(); i < points; ++i) enriched[i] = 2;
    vtu.point_data("fixed", fixed);
    // Each mesh node's index in the input files (a mesh read with unused nodes dropped is numbered
    // apart from its file); -1 for enriched DOFs and clipped points.
    std::vector<int32_t> file_node(points, -1);
    for (int i = 0; i < world.mesh_nodes; ++i)
        file_node[i] = world.mesh_file_index.empty() ? i : world.mesh_file_index[i];
    vtu.point_data("file_node", file_node);
    vtu.point_data("enriched_dof", enriched);
    std::vector<int32_t> side_of, parent_of, region, material, body, conn, offsets;
    std::vector<double> fraction, mises, stress;
    std::vector<uint8_t> types;
    const size_t cells = shown.cells.size();
    for (auto* a : {&side_of, &parent_of, &region, &material, &body, &offsets}) a->reserve(cells);
    fraction.reserve(cells), mises.reserve(cells), stress.reserve(9 * cells), types.reserve(cells);
    conn.reserve(static_cast<size_t>(el.nodes_per_element()) * cells);
    int last = -1;
    Mat3 sigma = Mat3::Zero();
    for (size_t c = 0; c < shown.cells.size(); ++c) {
        const int e = shown.element[c];
        side_of.push_back(side[e]), parent_of.push_back(parent[e]), fraction.push_back(el.weight[e]);
        region.push_back(el.region.empty() ? 0 : el.region[e]), material.push_back(el.material[e]);
        body.push_back(el.body.empty() ? 0 : el.body[e]);
        if (e != last) sigma = cell_cauchy_stress(world, e), last = e;  // the pieces of one element share it
        mises.push_back(von_mises(sigma));
        for (int r = 0; r < 3; ++r)
            for (int k = 0; k < 3; ++k) stress.push_back(sigma(r, k));
        // A quadratic piece is written as one (VTK_QUADRATIC_TETRA, 2D VTK_QUADRATIC_TRIANGLE: corners,
        // then mid-edge points).
        const int t = shown.quadratic[c];
        for (int a = 0; a < el.nodes_per_element(); ++a) conn.push_back(shown.cells[c][a]);
        if (t >= 0) conn.insert(conn.end(), shown.edge_points[t].begin(), shown.edge_points[t].begin() + (el.dim == 3 ? 6 : 3));
        types.push_back(static_cast<uint8_t>(t < 0 ? vtk_cell_type(el.dim) : el.dim == 3 ? 24 : 22));
        offsets.push_back(static_cast<int32_t>(conn.size()));
    }
    vtu.cell_data("side", side_of);
    vtu.cell_data("parent", parent_of);
    vtu.cell_data("volume_fraction", 1, fraction);
    vtu.cell_data("region", region);
    vtu.cell_data("material", material);
    vtu.cell_data("body", body);
    vtu.cell_data("von_mises_Pa", 1, mises);
    vtu.cell_data("stress_Pa", 9, stress);
    vtu.cells(conn, offsets, types);
    vtu.field("units", "SI: lengths m, time s, displacement_m m, velocity_m_per_s m/s, von_mises_Pa and stress_Pa "
                       "(Cauchy, row-major 3x3) Pa; each cut element is shown as its two virtual elements clipped to their sides (enriched_dof 2: a point of a clipped piece: a cut point, a mid-edge point of a cut quadratic element's piece, or a 2D crack tip's point: its element is four triangles fanned from the tip); quadratic elements and the pieces of cut ones are VTK quadratic tetrahedra (their stress: the mean over the element, or over its side); region: the mesh file's region; material: index into the scene's "
                       "materials (per body: \"material\", then \"region_materials\" in order); body: index into the scene's bodies");
    vtu.write(path);
}

void write_surface_obj(const World& world, const std::string& path) {
    const SurfaceMesh& s = world.visual;
    auto out = fmt::output_file(path);
    out.print("# xcut visual surface: {} vertices, {} triangles, t = {} s\n", s.vertex_count(), s.triangles.size(),
              world.time);
    for (const Vec3& p : s.position) out.print("v {:.9g} {:.9g} {:.9g}\n", p.x(), p.y(), p.z());
    // Two groups: the skin, then the wound's faces ("g cut"), so a viewer can colour the cut.
    for (int cut = 0; cut < 2; ++cut) {
        out.print("g {}\n", cut ? "cut" : "skin");
        for (size_t k = 0; k < s.triangles.size(); ++k) {
            const bool is_cut = k < s.cut_face.size() && s.cut_face[k];
            if (is_cut != (cut == 1)) continue;
            const auto& t = s.triangles[k];
            out.print("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
        }
    }
}

void write_surface_vtu(const World& world, const std::string& path) {
    const SurfaceMesh& s = world.visual;
    VtuWriter vtu(world.output.ascii);
    std::vector<double> xyz;
    for (const Vec3& p : s.position) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
    vtu.points(xyz);
    std::vector<int32_t> conn, offsets, owner;
    for (size_t t = 0; t < s.triangles.size(); ++t) {
        conn.insert(conn.end(), s.triangles[t].begin(), s.triangles[t].end());
        offsets.push_back(static_cast<int32_t>(conn.size()));
        owner.push_back(t < s.triangle_owner.size() ? s.triangle_owner[t] : -1);
    }
    std::vector<uint8_t> cut(s.triangles.size(), 0);
    for (size_t t = 0; t < s.triangles.size() && t < s.cut_face.size(); ++t) cut[t] = s.cut_face[t];
    vtu.cell_data("cut_face", cut);
    vtu.cell_data("mesh_element", owner);
    vtu.cells(conn, offsets, std::vector<uint8_t>(s.triangles.size(), 5));
    vtu.field("units", "SI: lengths m; cut_face 1 on the wound's faces (the internal cut surface), 0 on the skin");
    vtu.write(path);
}

void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& frames) {
    auto out = fmt::output_file(path);
    out.print("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n");
    for (const auto& [t, file] : frames)
        out.print("<DataSet timestep=\"{:.10g}\" part=\"0\" file=\"{}\"/>\n", t, file);
    out.print("</Collection>\n</VTKFile>\n");
}

OutputWriter::OutputWriter(const World& world) : dir_(world.output.directory), stem_(world.output.name) {
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (ec) throw InputError(dir_, "output.directory", "cannot create the directory: " + ec.message());
    if (world.output.metrics_csv) {
        csv_.open(dir_ + "/" + stem_ + "_metrics.csv");
        if (!csv_) throw InputError(dir_, "output.directory", "cannot write the metrics CSV");
        int split_total = 0;  // the header: the columns' names (their values before a step mean nothing)
        const std::vector<MetricColumn> columns = metric_columns(world, split_total);
        for (size_t i = 0; i < columns.size(); ++i) csv_ << (i ? "," : "") << columns[i].name;
        csv_ << "\n";
    }
}

void OutputWriter::write_frame(const World& world) {
    if (!world.output.vtu) return;
    const std::string file = fmt::format("{}_{:06d}.vtu", stem_, world.step);
    write_vtu(world, dir_ + "/" + file);
    frames_.emplace_back(world.time, file);
    write_pvd(dir_ + "/" + stem_ + ".pvd", frames_);
    if (world.visual.vertex_count() > 0) {
        const std::string surface = fmt::format("{}_surface_{:06d}", stem_, world.step);
        write_surface_obj(world, dir_ + "/" + surface + ".obj");
        write_surface_vtu(world, dir_ + "/" + surface + ".vtu");
        surface_frames_.emplace_back(world.time, surface + ".vtu");
        write_pvd(dir_ + "/" + stem_ + "_surface.pvd", surface_frames_);
    }
}

void OutputWriter::frame_if_due(const World& world) {
    if (output_frame_due(world.output, world.step)) write_frame(world);
}

void OutputWriter::metrics_row(const World& world) {
    if (!csv_.is_open()) return;
    const std::vector<MetricColumn> columns = metric_columns(world, split_total_);
    for (size_t i = 0; i < columns.size(); ++i) csv_ << (i ? "," : "") << format_metric(columns[i]);
    csv_ << "\n";
}

void OutputWriter::finish() {
    if (csv_.is_open()) csv_.flush();
}

ProgressBar::ProgressBar(std::string label, int total)
    : label_(std::move(label)), total_(total), enabled_(isatty(fileno(stderr)) != 0), start_(wall_seconds()) {}

void ProgressBar::update(int done) {
    if (!enabled_ || total_ <= 0) return;
    const double elapsed = wall_seconds() - start_;
    const int percent = static_cast<int>(100.0 * done / total_);
    if (elapsed < 1.0 || percent == last_percent_) return;
    last_percent_ = percent;
    const int width = 30, filled = width * done / total_;
    const double eta = done > 0 ? elapsed * (total_ - done) / done : 0.0;
    fmt::print(stderr, "\r{} [{:<{}}] {:3d}% {}/{} eta {:.0f}s ", label_, std::string(filled, '#'), width, percent,
               done, total_, eta);
}

void ProgressBar::finish() {
    if (enabled_ && last_percent_ >= 0) fmt::print(stderr, "\n");
}

}  // namespace xcut
