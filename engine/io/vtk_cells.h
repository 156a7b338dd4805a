#pragma once
// VTK cell types as both VTK readers (XML .vtu, legacy .vtk) turn them into xcut's cells: linear,
// quadratic and Lagrange tetrahedra (their four corners come first in VTK's node order), else
// triangles as a 2D mesh; other cells (vertices, lines, hexahedra...) are skipped and counted. Cell
// data arrays follow the cells kept. Type numbers: VTK's vtkCellType.h. Internal to engine/io.
#include <fmt/format.h>

#include <array>
#include <map>
#include <string>
#include <vector>

#include "engine/error.h"
#include "engine/mesh_data.h"

namespace xcut::mesh_io_detail {

class VtkCells {
public:
    static bool is_tet(int type) { return type == 10 || type == 24 || type == 71; }  // TETRA, QUADRATIC_, LAGRANGE_
    static bool is_tri(int type) { return type == 5 || type == 22 || type == 69; }   // TRIANGLE, QUADRATIC_, LAGRANGE_
    static int corners(int type) { return is_tet(type) ? 4 : 3; }

    /// Cell `index` of the file, of VTK type `type`, with `n` node indices at `nodes`; messages name
    /// it "cell <index>".
    template <class Index>
    void add(long long index, int type, const Index* nodes, long long n, const std::string& path) {
        auto where = [&] { return fmt::format("cell {}", index); };
        if (!is_tet(type) && !is_tri(type)) {
            ++skipped_[type];
            return;
        }
        if (n < corners(type)) throw InputError(path, where(), fmt::format("a cell of type {} with {} nodes", type, n));
        if (type != 10 && type != 5) ++high_order_[type];
        std::array<int, 4> c{-1, -1, -1, -1};
        for (int a = 0; a < corners(type); ++a) {
            if (nodes[a] < 0 || nodes[a] > 0x7fffffff)
                throw InputError(path, where(), fmt::format("node index {} is out of range", static_cast<long long>(nodes[a])));
            c[a] = static_cast<int>(nodes[a]);
        }
        auto& kept = is_tet(type) ? tets_ : tris_;
        kept.cells.push_back(c);
        kept.index.push_back(index);
    }

    /// Moves the kept cells (tetrahedra, else triangles) into `mesh`, with the cell-data arrays
    /// (`arrays`: one row per file cell) cut to them. Throws when there is neither.
    void finish(MeshData& mesh, std::vector<MeshData::CellArray> arrays) {
        const bool three_d = !tets_.cells.empty();
        if (!three_d && tris_.cells.empty()) {
            std::string found;
            for (const auto& [type, n] : skipped_) found += fmt::format("{}{} of VTK type {}", found.empty() ? "" : ", ", n, type);
            throw InputError(mesh.source, "cells",
                             fmt::format("no tetrahedra or triangles (VTK types 10, 24, 71 and 5, 22, 69); the file holds {}",
                                         found.empty() ? "no cells" : found));
        }
        Kept& kept = three_d ? tets_ : tris_;
        mesh.dim = three_d ? 3 : 2;
        mesh.cells = std::move(kept.cells);
        mesh.cell_id = kept.index;
        for (auto& a : arrays) {
            MeshData::CellArray cut{a.name, a.components, {}};
            cut.values.reserve(kept.index.size() * a.components);
            for (long long e : kept.index)
                for (int k = 0; k < a.components; ++k) cut.values.push_back(a.values[e * a.components + k]);
            mesh.cell_data.push_back(std::move(cut));
        }
        for (const auto& [type, n] : high_order_)
            if (is_tet(type) == three_d)
                mesh.notes.push_back(fmt::format("{} higher-order {} (VTK type {}) read as linear ones: their corner "
                                                 "nodes only", n, three_d ? "tetrahedra" : "triangles", type));
    }

private:
    struct Kept {
        std::vector<std::array<int, 4>> cells;
        std::vector<long long> index;  ///< the file's cell index of each
    };
    Kept tets_, tris_;
    std::map<int, long long> skipped_, high_order_;
};

}  // namespace xcut::mesh_io_detail
