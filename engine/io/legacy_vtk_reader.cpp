// Legacy VTK (.vtk) reader, ASCII and BINARY (big-endian), file versions 2 to 5.1 (5.x stores cells
// as OFFSETS and CONNECTIVITY). DATASET UNSTRUCTURED_GRID becomes the mesh, its CELL_DATA arrays
// kept; DATASET POLYDATA must be a closed triangle surface and is tetrahedralized like an OBJ/STL.
// Reference: VTK's "VTK File Formats" (simple legacy formats) and vtkDataReader. Errors name the
// file and the line (or the byte, in binary data).
#include <fmt/format.h>

#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "engine/error.h"
#include "engine/io/byte_cursor.h"
#include "engine/io/input_file.h"
#include "engine/io/mesh_io.h"
#include "engine/io/vtk_cells.h"

namespace xcut {
namespace {

using mesh_io_detail::ByteCursor;

/// Bytes of a legacy VTK data type in BINARY files; 0 if unknown.
int type_size(std::string_view t) {
    static const std::map<std::string_view, int> kSize = {
        {"bit", 0},           {"char", 1},          {"unsigned_char", 1}, {"short", 2},
        {"unsigned_short", 2}, {"int", 4},           {"unsigned_int", 4},  {"long", 8},
        {"unsigned_long", 8}, {"vtktypeint64", 8},  {"vtktypeuint64", 8}, {"vtkidtype", 8},
        {"float", 4},         {"double", 8},        {"vtktypeint32", 4}};
    const auto it = kSize.find(t);
    return it == kSize.end() ? 0 : it->second;
}

class LegacyVtkReader {
public:
    LegacyVtkReader(const std::string& path, std::string_view text) : c_(path, text) {}

    /// The unstructured grid, or (poly = true) the polydata surface's points and triangles.
    void read();
    MeshData grid();
    ClosedSurface surface();
    bool poly() const { return poly_; }

private:
    /// `count` values of the file type `type` (ASCII tokens or big-endian binary), as doubles.
    std::vector<double> values(long long count, std::string_view type, const char* what);
    std::vector<long long> integers(long long count, std::string_view type, const char* what);
    void read_cells(bool modern, long long a, long long b, std::vector<long long>& offsets, std::vector<long long>& conn);
    void read_attributes(long long n, bool keep);
    void skip_metadata();

    ByteCursor c_;
    bool binary_ = false, poly_ = false;
    double version_ = 0.0;
    std::vector<Eigen::Vector3d> points_;
    std::vector<long long> offsets_, conn_, types_;
    std::vector<MeshData::CellArray> cell_data_;
};

std::vector<double> LegacyVtkReader::values(long long count, std::string_view type, const char* what) {
    const int size = type_size(type);
    if (size == 0) c_.fail(fmt::format("data type \"{}\" is not supported", ByteCursor::clip(type)));
    c_.check_count(count, what, binary_ ? size : 2);
    std::vector<double> out(count);
    if (!binary_) {
        for (double& v : out) v = c_.real(what);
        return out;
    }
    c_.end_line();
    for (double& v : out) {
        switch (size) {
            case 1: v = type == "char" ? c_.binary<int8_t>(what, true) : c_.binary<uint8_t>(what, true); break;
            case 2: v = type == "short" ? c_.binary<int16_t>(what, true) : c_.binary<uint16_t>(what, true); break;
            case 4:
                v = type == "float" ? c_.binary<float>(what, true)
                    : type == "unsigned_int" ? c_.binary<uint32_t>(what, true) : c_.binary<int32_t>(what, true);
                break;
            default:
                v = type == "double" ? c_.binary<double>(what, true)
                    : (type == "unsigned_long" || type == "vtktypeuint64") ? static_cast<double>(c_.binary<uint64_t>(what, true))
                                                                             : static_cast<double>(c_.binary<int64_t>(what, true));
        }
        if (!std::isfinite(v)) c_.fail(fmt::format("{} is NaN or infinite", what));
    }
    return out;
}

std::vector<long long> LegacyVtkReader::integers(long long count, std::string_view type, const char* what) {
    if (type == "float" || type == "double") c_.fail(fmt::format("{} must be integers, not {}", what, type));
    const std::vector<double> v = values(count, type, what);
    std::vector<long long> out(v.size());
    for (size_t i = 0; i < v.size(); ++i) {
        if (v[i] != std::floor(v[i]) || std::abs(v[i]) > 9e15) c_.fail(fmt::format("{} {} is not an index", what, v[i]));
        out[i] = static_cast<long long>(v[i]);
    }
    return out;
}

void LegacyVtkReader::read_cells(bool modern, long long a, long long b, std::vector<long long>& offsets,
                                 std::vector<long long>& conn) {
    if (modern) {  // 5.x: CELLS nOffsets nConnectivity, then OFFSETS type ..., CONNECTIVITY type ...
        c_.expect("OFFSETS");
        const std::string type(c_.token("offset type"));
        offsets = integers(a, type, "offset");
        c_.expect("CONNECTIVITY");
        const std::string ctype(c_.token("connectivity type"));
        conn = integers(b, ctype, "connectivity");
        if (offsets.empty() || offsets.front() != 0) c_.fail("OFFSETS must start at 0");
        offsets.erase(offsets.begin());  // end offsets, one per cell
        return;
    }
    // Before 5: CELLS n size, then n rows "k i1 ... ik" (size numbers in all).
    const std::vector<long long> rows = integers(b, "int", "cell list value");
    offsets.clear(), conn.clear();
    size_t at = 0;
    for (long long e = 0; e < a; ++e) {
        if (at >= rows.size() || rows[at] < 0 || rows[at] > static_cast<long long>(rows.size() - at - 1))
            c_.fail(fmt::format("cell {} does not fit in the CELLS list of {} numbers", e, b));
        conn.insert(conn.end(), rows.begin() + at + 1, rows.begin() + at + 1 + rows[at]);
        at += rows[at] + 1;
        offsets.push_back(static_cast<long long>(conn.size()));
    }
    if (at != rows.size()) c_.fail(fmt::format("CELLS announces {} numbers for {} cells, they use {}", b, a, at));
}

void LegacyVtkReader::skip_metadata() {
    // METADATA runs to the first empty line (vtkDataReader::ReadMetaData).
    c_.rest_of_line();
    while (c_.left() > 0) {
        const std::string_view line = c_.rest_of_line();
        if (line.find_first_not_of(" \t") == std::string_view::npos) return;
    }
}

void LegacyVtkReader::read_attributes(long long n, bool keep) {
    // SCALARS/VECTORS/NORMALS/TENSORS/FIELD/LOOKUP_TABLE... until the next section.
    while (!c_.done()) {
        const std::string kw(c_.token("an attribute"));
        if (kw == "POINT_DATA" || kw == "CELL_DATA") {
            const long long m = c_.integer("count");
            read_attributes(m, kw == "CELL_DATA");
            return;
        }
        if (kw == "METADATA") { skip_metadata(); continue; }
        if (kw == "SCALARS") {
            const std::string name(c_.token("name")), type(c_.token("type"));
            // An optional component count before LOOKUP_TABLE.
            int nc = 1;
            std::string next(c_.token("LOOKUP_TABLE"));
            if (next != "LOOKUP_TABLE") {
                nc = static_cast<int>(std::strtol(next.c_str(), nullptr, 10));
                if (nc < 1 || nc > 4) c_.fail(fmt::format("SCALARS component count \"{}\" (1 to 4)", next));
                next = std::string(c_.token("LOOKUP_TABLE"));
            }
            if (next != "LOOKUP_TABLE") c_.fail(fmt::format("expected LOOKUP_TABLE, found \"{}\"", ByteCursor::clip(next)));
            c_.token("table name");
            std::vector<double> v = values(n * nc, type, "scalar");
            if (keep) cell_data_.push_back({name, nc, std::move(v)});
        } else if (kw == "VECTORS" || kw == "NORMALS" || kw == "TENSORS") {
            const std::string name(c_.token("name")), type(c_.token("type"));
            const int nc = kw == "TENSORS" ? 9 : 3;
            std::vector<double> v = values(n * nc, type, "value");
            if (keep) cell_data_.push_back({name, nc, std::move(v)});
        } else if (kw == "FIELD") {
            c_.token("field name");
            const long long arrays = c_.count("array count", 8);
            for (long long k = 0; k < arrays; ++k) {
                std::string name(c_.token("array name"));
                if (name == "METADATA") {  // VTK 9 writes each array's information after its values
                    skip_metadata();
                    name = std::string(c_.token("array name"));
                }
                const long long nc = c_.integer("component count"), tuples = c_.integer("tuple count");
                const std::string type(c_.token("type"));
                if (nc < 1 || nc > 64 || tuples < 0) c_.fail(fmt::format("array \"{}\": {} components, {} tuples", name, nc, tuples));
                c_.check_count(tuples, "tuple count", 1);
                std::vector<double> v = values(nc * tuples, type, "value");
                if (keep && tuples == n) cell_data_.push_back({name, static_cast<int>(nc), std::move(v)});
            }
        } else if (kw == "LOOKUP_TABLE") {
            c_.token("table name");
            const long long size = c_.count("table size", 1);
            values(4 * size, binary_ ? "unsigned_char" : "float", "colour");
        } else {
            c_.fail(fmt::format("\"{}\" is not a legacy VTK attribute xcut reads", ByteCursor::clip(kw)));
        }
    }
}

void LegacyVtkReader::read() {
    const std::string_view head = c_.rest_of_line();
    if (head.rfind("# vtk DataFile Version", 0) != 0)
        c_.fail("not a legacy VTK file: the first line is not \"# vtk DataFile Version x.y\"");
    version_ = std::strtod(std::string(head.substr(22)).c_str(), nullptr);
    c_.rest_of_line();  // title
    const std::string_view mode = c_.token("ASCII or BINARY");
    if (mode != "ASCII" && mode != "BINARY") c_.fail(fmt::format("expected ASCII or BINARY, found \"{}\"", ByteCursor::clip(mode)));
    binary_ = mode == "BINARY";
    c_.expect("DATASET");
    const std::string_view dataset = c_.token("dataset type");
    if (dataset != "UNSTRUCTURED_GRID" && dataset != "POLYDATA")
        c_.fail(fmt::format("DATASET {}: xcut reads UNSTRUCTURED_GRID (a volume mesh) or POLYDATA (a closed surface)",
                            ByteCursor::clip(dataset)));
    poly_ = dataset == "POLYDATA";
    const bool modern = version_ >= 5.0;
    while (!c_.done()) {
        const std::string kw(c_.token("a section"));
        if (kw == "POINTS") {
            const long long n = c_.count("point count", 2);
            const std::string type(c_.token("point type"));
            const std::vector<double> xyz = values(3 * n, type, "coordinate");
            points_.resize(n);
            for (long long i = 0; i < n; ++i) points_[i] = Eigen::Vector3d(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
        } else if (kw == "CELLS" || kw == "POLYGONS" || kw == "VERTICES" || kw == "LINES" || kw == "TRIANGLE_STRIPS") {
            const long long a = c_.count("cell count", 1), b = c_.count("size", 1);
            std::vector<long long> offsets, conn;
            read_cells(modern, a, b, offsets, conn);
            if (kw == "CELLS" || kw == "POLYGONS") offsets_ = std::move(offsets), conn_ = std::move(conn);
            else if (kw == "TRIANGLE_STRIPS" && !offsets.empty()) c_.fail("TRIANGLE_STRIPS are not read: triangulate the surface");
        } else if (kw == "CELL_TYPES") {
            types_ = integers(c_.count("cell type count", 1), "int", "cell type");
        } else if (kw == "METADATA") {
            skip_metadata();
        } else if (kw == "CELL_DATA" || kw == "POINT_DATA") {
            const long long n = c_.integer("count");
            read_attributes(n, kw == "CELL_DATA");
        } else if (kw == "FIELD") {  // dataset-level field data (e.g. TIME): read and dropped
            read_attributes(0, false);
        } else {
            if (ByteCursor::is_binary(kw))
                c_.fail(fmt::format("binary data (\"{}\") where a section keyword belongs: a count before it (POINTS n, "
                                    "CELLS n size, CELL_TYPES n) is smaller than the data that follows",
                                    ByteCursor::clip(kw)));
            c_.fail(fmt::format("\"{}\" is not a legacy VTK section xcut reads", ByteCursor::clip(kw)));
        }
    }
    if (points_.empty()) c_.fail("no POINTS");
    if (offsets_.empty()) c_.fail(poly_ ? "no POLYGONS" : "no CELLS");
}

MeshData LegacyVtkReader::grid() {
    if (types_.size() != offsets_.size())
        throw InputError(c_.path(), "CELL_TYPES", fmt::format("{} types for {} cells", types_.size(), offsets_.size()));
    MeshData mesh;
    mesh.source = c_.path();
    mesh.points = points_;
    mesh_io_detail::VtkCells kept;
    for (size_t e = 0; e < offsets_.size(); ++e) {
        const long long begin = e ? offsets_[e - 1] : 0, end = offsets_[e];
        if (begin < 0 || end < begin || end > static_cast<long long>(conn_.size()))
            throw InputError(c_.path(), "CELLS", fmt::format("cell {} runs from {} to {}", e, begin, end));
        kept.add(static_cast<long long>(e), static_cast<int>(types_[e]), conn_.data() + begin, end - begin, c_.path());
    }
    for (const auto& a : cell_data_)
        if (a.values.size() != offsets_.size() * a.components)
            throw InputError(c_.path(), "CELL_DATA", fmt::format("array \"{}\" has {} values for {} cells", a.name, a.values.size(), offsets_.size()));
    kept.finish(mesh, cell_data_);
    return mesh;
}

ClosedSurface LegacyVtkReader::surface() {
    ClosedSurface s;
    s.points = points_;
    for (size_t e = 0; e < offsets_.size(); ++e) {
        const long long begin = e ? offsets_[e - 1] : 0, end = offsets_[e];
        if (begin < 0 || end < begin || end > static_cast<long long>(conn_.size()) || end - begin < 3)
            throw InputError(c_.path(), "POLYGONS", fmt::format("polygon {} has {} vertices", e, end - begin));
        for (long long k = begin; k < end; ++k)
            if (conn_[k] < 0 || conn_[k] >= static_cast<long long>(points_.size()))
                throw InputError(c_.path(), "POLYGONS", fmt::format("polygon {} refers to point {} ({} points)", e, conn_[k], points_.size()));
        for (long long k = begin + 1; k + 1 < end; ++k)  // a fan, like the OBJ reader
            s.triangles.push_back({static_cast<int>(conn_[begin]), static_cast<int>(conn_[k]), static_cast<int>(conn_[k + 1])});
    }
    check_closed_surface(c_.path(), s);
    return s;
}

}  // namespace

MeshData read_legacy_vtk(const std::string& path, double max_volume, double volume_to_m3) {
    const std::string text = read_input_file(path, "file", "mesh");
    LegacyVtkReader r(path, text);
    r.read();
    if (r.poly()) return tetrahedralize_surface(path, r.surface(), max_volume, 1.5, volume_to_m3);
    return r.grid();
}

}  // namespace xcut
