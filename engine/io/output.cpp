#include "engine/io/output.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/os.h>

#include "engine/error.h"

namespace xcut {
namespace {

double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

int vtk_cell_type(int dim) { return dim == 3 ? 10 : 5; }  // VTK_TETRA, VTK_TRIANGLE

}  // namespace

void write_vtu(const World& world, const std::string& path) {
    const Nodes& n = world.nodes;
    const Elements& el = world.elements;
    const int npe = el.nodes_per_element();
    // Cells: every element that carries material (weight > 0): uncut mesh elements and the virtual
    // elements of cut ones, so ParaView shows the opening. Cell fields say which is which.
    std::vector<int> cells;
    for (int e = 0; e < el.count(); ++e)
        if (el.weight[e] > 0.0) cells.push_back(e);
    std::vector<int> side(el.count(), 0), parent(el.count());
    for (int e = 0; e < world.mesh_elements; ++e) parent[e] = e;
    for (int v = 0; v < world.virtual_elements.count(); ++v) {
        side[world.virtual_elements.element[v]] = world.virtual_elements.side[v];
        parent[world.virtual_elements.element[v]] = world.virtual_elements.parent[v];
    }
    auto out = fmt::output_file(path);
    out.print("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n");
    out.print("<UnstructuredGrid>\n<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", n.count(), cells.size());
    out.print("<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for (const Vec3& p : n.position) out.print("{:.10g} {:.10g} {:.10g}\n", p.x(), p.y(), p.z());
    out.print("</DataArray>\n</Points>\n<PointData Vectors=\"displacement\">\n");
    out.print("<DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for (int i = 0; i < n.count(); ++i) {
        const Vec3 u = n.position[i] - n.rest[i];
        out.print("{:.10g} {:.10g} {:.10g}\n", u.x(), u.y(), u.z());
    }
    out.print("</DataArray>\n<DataArray type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for (const Vec3& v : n.velocity) out.print("{:.10g} {:.10g} {:.10g}\n", v.x(), v.y(), v.z());
    out.print("</DataArray>\n<DataArray type=\"UInt8\" Name=\"fixed\" format=\"ascii\">\n");
    for (uint8_t f : n.fixed) out.print("{} ", int(f));
    out.print("\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"enriched_dof\" format=\"ascii\">\n");
    for (int i = 0; i < n.count(); ++i) out.print("{} ", i >= world.mesh_nodes ? 1 : 0);
    out.print("\n</DataArray>\n</PointData>\n<CellData Scalars=\"side\">\n");
    out.print("<DataArray type=\"Int8\" Name=\"side\" format=\"ascii\">\n");
    for (int e : cells) out.print("{} ", side[e]);
    out.print("\n</DataArray>\n<DataArray type=\"Int32\" Name=\"parent\" format=\"ascii\">\n");
    for (int e : cells) out.print("{} ", parent[e]);
    out.print("\n</DataArray>\n<DataArray type=\"Float64\" Name=\"volume_fraction\" format=\"ascii\">\n");
    for (int e : cells) out.print("{:.6g} ", el.weight[e]);
    out.print("\n</DataArray>\n</CellData>\n<Cells>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n");
    for (int e : cells) {
        for (int a = 0; a < npe; ++a) out.print("{} ", el.nodes[e][a]);
        out.print("\n");
    }
    out.print("</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n");
    for (size_t c = 0; c < cells.size(); ++c) out.print("{} ", (c + 1) * npe);
    out.print("\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for (size_t c = 0; c < cells.size(); ++c) out.print("{} ", vtk_cell_type(el.dim));
    out.print("\n</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
}

void write_surface_obj(const World& world, const std::string& path) {
    const SurfaceMesh& s = world.visual;
    auto out = fmt::output_file(path);
    out.print("# xcut visual surface: {} vertices, {} triangles, t = {} s\n", s.vertex_count(), s.triangles.size(),
              world.time);
    for (const Vec3& p : s.position) out.print("v {:.9g} {:.9g} {:.9g}\n", p.x(), p.y(), p.z());
    for (const auto& t : s.triangles) out.print("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
}

void write_surface_vtu(const World& world, const std::string& path) {
    const SurfaceMesh& s = world.visual;
    auto out = fmt::output_file(path);
    out.print("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n");
    out.print("<UnstructuredGrid>\n<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", s.vertex_count(), s.triangles.size());
    out.print("<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for (const Vec3& p : s.position) out.print("{:.10g} {:.10g} {:.10g}\n", p.x(), p.y(), p.z());
    out.print("</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n");
    for (const auto& t : s.triangles) out.print("{} {} {}\n", t[0], t[1], t[2]);
    out.print("</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n");
    for (size_t c = 0; c < s.triangles.size(); ++c) out.print("{} ", 3 * (c + 1));
    out.print("\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for (size_t c = 0; c < s.triangles.size(); ++c) out.print("5 ");
    out.print("\n</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
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
        csv_ << "step,time_s,dt_s,dofs,cg_iterations,cg_residual,kinetic_J,elastic_J,gravity_work_J,step_ms,solve_flag,"
                "substeps";
        for (const std::string& s : world.metrics.system_names) csv_ << "," << s << "_ms";
        cut_columns_ = world.tools.count() > 0;
        if (cut_columns_)
            csv_ << ",quads,elements_tested,crossings,elements_split,cut_update_ms,crossing_delay_mean_s,"
                    "crossing_delay_max_s,enriched_nodes";
        force_columns_ = (world.present() & kShapedTools) != 0;
        if (force_columns_) {
            csv_ << ",contacts";
            for (const std::string& n : world.tools.name)
                for (const char* q : {"fx_N", "fy_N", "fz_N", "tx_Nm", "ty_Nm", "tz_Nm"}) csv_ << "," << n << "_" << q;
        }
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
    if (world.step % world.output.every == 0) write_frame(world);
}

void OutputWriter::metrics_row(const World& world) {
    const StepMetrics& m = world.metrics.current;
    if (csv_.is_open()) {
        csv_ << fmt::format("{},{:.9g},{:.9g},{},{},{:.3e},{:.9e},{:.9e},{:.9e},{:.4f},{},{}", m.step, m.time, m.dt,
                            m.dofs, m.cg_iterations, m.cg_residual, m.kinetic_energy, m.elastic_energy,
                            m.gravity_work, m.step_ms, m.solve_flag, m.substeps);
        for (double ms : m.system_ms) csv_ << fmt::format(",{:.4f}", ms);
        if (cut_columns_) {
            // Delays of the elements split in this step (the tail of the run-long list).
            const CutState& cs = world.cut_state;
            double sum = 0.0, max = 0.0;
            const size_t n = static_cast<size_t>(cs.elements_split);
            for (size_t i = cs.delay_sim.size() - std::min(n, cs.delay_sim.size()); i < cs.delay_sim.size(); ++i)
                sum += cs.delay_sim[i], max = std::max(max, cs.delay_sim[i]);
            csv_ << fmt::format(",{},{},{},{},{:.4f},{:.6g},{:.6g},{}", cs.quads_built, cs.elements_tested,
                                cs.crossings_found, cs.elements_split, cs.update_ms, n > 0 ? sum / n : 0.0, max,
                                world.enriched.count());
        }
        if (force_columns_) {
            // The tissue's reaction on each tool (zero before its first contact step).
            const ToolBodies& tb = world.tools;
            csv_ << "," << world.contacts.count();
            for (int i = 0; i < tb.count(); ++i) {
                const bool known = i < static_cast<int>(tb.reaction_force.size());
                const Vec3 f = known ? tb.reaction_force[i] : Vec3::Zero(), t = known ? tb.reaction_torque[i] : Vec3::Zero();
                csv_ << fmt::format(",{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e}", f.x(), f.y(), f.z(), t.x(), t.y(), t.z());
            }
        }
        csv_ << "\n";
    }
}

void OutputWriter::finish() {
    if (csv_.is_open()) csv_.flush();
}

ProgressBar::ProgressBar(std::string label, int total)
    : label_(std::move(label)), total_(total), enabled_(isatty(fileno(stderr)) != 0), start_(now_seconds()) {}

void ProgressBar::update(int done) {
    if (!enabled_ || total_ <= 0) return;
    const double elapsed = now_seconds() - start_;
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
