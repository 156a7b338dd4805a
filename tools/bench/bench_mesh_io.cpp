#include "tools/bench/bench_mesh_io.h"

#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <vector>

#include "engine/error.h"
#include "engine/io/mesh_io.h"
#include "tools/bench/bench.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

/// Converts the Gmsh mesh to the VTK encodings with meshio's and VTK's own writers.
const char* kConvert = R"(import sys, meshio, vtk
m = meshio.read(sys.argv[1])
m = meshio.Mesh(m.points, [("tetra", m.get_cells_type("tetra"))])
m.write(sys.argv[2] + "/meshio_zlib.vtu", binary=True, compression="zlib")
r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName(sys.argv[2] + "/meshio_zlib.vtu"); r.Update()
for name, zlib in (("vtk_appended_raw", False), ("vtk_appended_zlib", True)):
    w = vtk.vtkXMLUnstructuredGridWriter(); w.SetFileName(sys.argv[2] + "/" + name + ".vtu"); w.SetInputData(r.GetOutput())
    w.SetDataMode(2); w.SetEncodeAppendedData(False)
    w.SetCompressorTypeToZLib() if zlib else w.SetCompressorTypeToNone()
    w.Write()
w = vtk.vtkUnstructuredGridWriter(); w.SetFileName(sys.argv[2] + "/vtk_legacy_binary.vtk"); w.SetInputData(r.GetOutput())
w.SetFileTypeToBinary(); w.Write()
)";

void run_or_throw(const std::string& command, const fs::path& dir) {
    const std::string log = (dir / "log.txt").string();
    if (std::system(fmt::format("cd '{}' && {} > '{}' 2>&1", dir.string(), command, log).c_str()) != 0) {
        std::ifstream in(log);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        throw InputError("xcut bench --suite mesh_io", command, "failed (gmsh, and python3 with meshio and VTK: "
                                                                 "tools/install-deps.sh):\n" + text);
    }
}

struct Row {
    std::string file, writer;
    double mb = 0, ms = 0;
    size_t tets = 0;
};

}  // namespace

int mesh_io_bench_command(const MeshIoBenchOptions& o) {
    const fs::path dir = fs::temp_directory_path() / fmt::format("xcut_bench_mesh_io_{}", ::getpid());
    fs::create_directories(dir);
    // A 1 x 1 x 0.5 m box; gmsh makes about 3.3 tets per (clmax)^3 of volume.
    const double clmax = o.tiny ? 0.043 : 0.02;
    std::ofstream(dir / "box.geo") << fmt::format("SetFactory(\"OpenCASCADE\");\nBox(1) = {{0, 0, 0, 1, 1, 0.5}};\n"
                                                  "Mesh.CharacteristicLengthMax = {};\n", clmax);
    fmt::print("mesh_io benchmark: meshing a box with gmsh (clmax {} m) and writing it with gmsh, meshio and VTK...\n", clmax);
    std::fflush(stdout);
    try {
        run_or_throw("gmsh -3 box.geo -format msh41 -bin -o gmsh41_bin.msh", dir);
        run_or_throw("gmsh -3 box.geo -format msh22 -bin -o gmsh22_bin.msh", dir);
        std::ofstream(dir / "convert.py") << kConvert;
        run_or_throw("/usr/bin/python3 convert.py gmsh41_bin.msh .", dir);
    } catch (const InputError&) {
        fs::remove_all(dir);
        throw;
    }
    const std::vector<std::pair<std::string, std::string>> files = {
        {"gmsh41_bin.msh", "gmsh"}, {"gmsh22_bin.msh", "gmsh"}, {"meshio_zlib.vtu", "meshio"},
        {"vtk_appended_raw.vtu", "VTK"}, {"vtk_appended_zlib.vtu", "VTK"}, {"vtk_legacy_binary.vtk", "VTK"}};
    std::vector<Row> rows;
    for (const auto& [name, writer] : files) {
        Row r{name, writer, static_cast<double>(fs::file_size(dir / name)) / 1e6, 1e300, 0};
        for (int k = 0; k < o.repeats; ++k) {
            const auto t0 = std::chrono::steady_clock::now();
            const MeshData m = read_mesh_file((dir / name).string(), 0.0);
            r.ms = std::min(r.ms, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
            r.tets = m.cells.size();
        }
        rows.push_back(r);
    }
    fs::remove_all(dir);
    const double gmsh_ms = rows[0].ms;
    const std::string path = !o.csv.empty() ? o.csv : o.tiny ? "results/bench_mesh_io_quick.csv" : "results/bench_mesh_io.csv";
    auto csv = open_csv(path);
    csv.print("file,writer,tets,megabytes,read_ms,ratio_to_gmsh41_binary\n");
    fmt::print("{:<24} {:>7} {:>8} {:>7} {:>9} {:>14}\n", "file", "writer", "tets", "MB", "read ms", "vs gmsh 4.1 bin");
    for (const Row& r : rows) {
        fmt::print("{:<24} {:>7} {:>8} {:>7.1f} {:>9.1f} {:>13.2f}x\n", r.file, r.writer, r.tets, r.mb, r.ms, r.ms / gmsh_ms);
        csv.print("{},{},{},{:.3f},{:.3f},{:.3f}\n", r.file, r.writer, r.tets, r.mb, r.ms, r.ms / gmsh_ms);
    }
    double worst_vtu = 0;
    for (const Row& r : rows)
        if (r.file.size() > 4 && r.file.substr(r.file.size() - 4) == ".vtu") worst_vtu = std::max(worst_vtu, r.ms);
    fmt::print("target: binary VTU <= 2x binary Gmsh, both well under 1 s: slowest VTU {:.2f}x ({:.0f} ms), Gmsh {:.0f} ms\n",
               worst_vtu / gmsh_ms, worst_vtu, gmsh_ms);
    fmt::print("csv: {}\n", path);
    return 0;
}

}  // namespace xcut
