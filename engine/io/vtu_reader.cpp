// VTK XML UnstructuredGrid (.vtu) reader on pugixml and zlib. Data arrays in every encoding VTK and
// ParaView write: format "ascii", "binary" (base64, the header encoded with the data or apart) and
// "appended" (raw or base64), each uncompressed or compressed by vtkZLibDataCompressor; header
// UInt32 or UInt64; either byte order. Reference: VTK's "VTK File Formats" (XML formats) and
// vtkXMLDataParser, which reads the header and compressed blocks as read here. Cell data arrays are
// kept (MeshData::cell_data). Errors name the file and the XML element (and line).
#include <pugixml.hpp>
#include <zlib.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fmt/format.h>
#include <string>
#include <string_view>
#include <vector>

#include "engine/error.h"
#include "engine/io/byte_cursor.h"
#include "engine/io/input_file.h"
#include "engine/io/mesh_io.h"
#include "engine/io/vtk_cells.h"

namespace xcut {
namespace {

using mesh_io_detail::VtkCells;

/// Bytes of an array, from raw bytes or a base64 stream decoded on demand. Base64 is decoded one
/// 4-character quantum at a time and '=' padding ends a quantum, so a header encoded apart from its
/// data and a header encoded with it read alike.
class ByteSource {
public:
    ByteSource(std::string_view text, bool base64) : text_(text), base64_(base64) {}
    /// The next n bytes; false if the data ends first.
    bool take(size_t n, std::string& out) {
        out.clear();
        if (!base64_) {
            if (text_.size() - at_ < n) return false;
            out.assign(text_.substr(at_, n));
            at_ += n;
            return true;
        }
        out.reserve(n);
        const size_t from_buffer = std::min(n, buffer_.size() - used_);
        out.append(buffer_, used_, from_buffer);
        used_ += from_buffer;
        if (used_ == buffer_.size()) buffer_.clear(), used_ = 0;
        while (out.size() < n) {
            // Whole quanta straight into `out`; a quantum that overshoots n leaves its rest buffered.
            char bytes[3];
            int got = 0;
            if (!decode_quantum(bytes, got)) return false;
            const size_t keep = std::min<size_t>(got, n - out.size());
            out.append(bytes, keep);
            buffer_.append(bytes + keep, got - keep);
        }
        return true;
    }
    size_t bytes_left_bound() const { return base64_ ? (text_.size() - at_) * 3 / 4 + buffer_.size() - used_ : text_.size() - at_; }

private:
    static const signed char* table() {
        static const auto t = [] {
            std::array<signed char, 256> a{};
            a.fill(-1);
            const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
            for (int i = 0; i < 64; ++i) a[static_cast<unsigned char>(alphabet[i])] = static_cast<signed char>(i);
            a['='] = 64;
            return a;
        }();
        return t.data();
    }
    /// One 4-character quantum (whitespace skipped) into 1-3 bytes.
    bool decode_quantum(char* bytes, int& got) {
        const signed char* t = table();
        int q[4];
        int k = 0;
        while (k < 4 && at_ < text_.size()) {
            const signed char v = t[static_cast<unsigned char>(text_[at_++])];
            if (v >= 0) q[k++] = v;
            else if (!std::isspace(static_cast<unsigned char>(text_[at_ - 1]))) return false;
        }
        if (k < 4 || q[0] == 64 || q[1] == 64 || (q[2] == 64 && q[3] != 64)) return false;
        const int pad = (q[2] == 64) + (q[3] == 64);
        const unsigned v = (q[0] << 18) | (q[1] << 12) | ((pad >= 2 ? 0 : q[2]) << 6) | (pad >= 1 ? 0 : q[3]);
        bytes[0] = static_cast<char>(v >> 16), bytes[1] = static_cast<char>(v >> 8), bytes[2] = static_cast<char>(v);
        got = 3 - pad;
        return true;
    }
    std::string_view text_;
    bool base64_;
    size_t at_ = 0;
    std::string buffer_;  ///< decoded bytes not yet taken (at most 2)
    size_t used_ = 0;
};

struct VtuFile {
    std::string path;
    std::string text;           ///< the whole file
    std::string_view appended;  ///< the bytes after AppendedData's '_'
    bool appended_base64 = false;
    bool big_endian = false;
    int header_bytes = 4;       ///< UInt32 or UInt64 headers
    bool zlib = false;

    [[noreturn]] void fail(const pugi::xml_node& at, const std::string& message) const {
        const ptrdiff_t off = at.offset_debug();
        const long long line = off < 0 ? 0 : 1 + std::count(text.begin(), text.begin() + std::min<ptrdiff_t>(off, text.size()), '\n');
        std::string name = at.name();
        if (at.attribute("Name")) name += fmt::format(" \"{}\"", at.attribute("Name").value());
        throw InputError(path, line ? fmt::format("line {}, <{}>", line, name) : fmt::format("<{}>", name), message);
    }
};

struct TypeInfo {
    int size;
    bool is_float, is_signed;
};

TypeInfo type_info(const VtuFile& f, const pugi::xml_node& a) {
    const std::string t = a.attribute("type").value();
    static const std::pair<const char*, TypeInfo> kTypes[] = {
        {"Int8", {1, false, true}},   {"UInt8", {1, false, false}}, {"Int16", {2, false, true}},
        {"UInt16", {2, false, false}}, {"Int32", {4, false, true}},  {"UInt32", {4, false, false}},
        {"Int64", {8, false, true}},  {"UInt64", {8, false, false}}, {"Float32", {4, true, true}},
        {"Float64", {8, true, true}}};
    for (const auto& [name, info] : kTypes)
        if (t == name) return info;
    f.fail(a, fmt::format("type \"{}\" is not a VTK data type (Int8..UInt64, Float32, Float64)", t));
}

/// One value of `info`'s type from `p` (file byte order) as T.
template <class T>
T decode_value(const char* p, const TypeInfo& info, bool swap) {
    unsigned char b[8];
    std::memcpy(b, p, info.size);
    if (swap) std::reverse(b, b + info.size);
    auto as = [&](auto v) {
        std::memcpy(&v, b, sizeof(v));
        return static_cast<T>(v);
    };
    if (info.is_float) return info.size == 4 ? as(float{}) : as(double{});
    switch (info.size) {
        case 1: return info.is_signed ? as(int8_t{}) : as(uint8_t{});
        case 2: return info.is_signed ? as(int16_t{}) : as(uint16_t{});
        case 4: return info.is_signed ? as(int32_t{}) : as(uint32_t{});
        default: return info.is_signed ? as(int64_t{}) : static_cast<T>(as(uint64_t{}));
    }
}

bool swapped(const VtuFile& f) { return f.big_endian != mesh_io_detail::ByteCursor::host_big_endian(); }

unsigned long long header_value(const VtuFile& f, const std::string& bytes) {
    return decode_value<unsigned long long>(bytes.data(), {f.header_bytes, false, false}, swapped(f));
}

/// The array's bytes after its header: `expected` of them, inflated when the file is compressed.
std::string binary_payload(const VtuFile& f, const pugi::xml_node& a, ByteSource& src, unsigned long long expected) {
    std::string h, data;
    auto next_header = [&](const char* what) {
        if (!src.take(f.header_bytes, h)) f.fail(a, fmt::format("the data end before the header's {}", what));
        return header_value(f, h);
    };
    if (!f.zlib) {
        const unsigned long long n = next_header("byte count");
        if (n != expected) f.fail(a, fmt::format("the header says {} bytes, the array needs {}", n, expected));
        if (!src.take(n, data)) f.fail(a, fmt::format("the data end before the array's {} bytes", n));
        return data;
    }
    // vtkZLibDataCompressor: [blocks][block size][last block size (0: full)][compressed size of each].
    const unsigned long long blocks = next_header("block count"), block = next_header("block size"),
                             last = next_header("last block size");
    if (blocks > src.bytes_left_bound() / f.header_bytes) f.fail(a, fmt::format("{} blocks do not fit in the file", blocks));
    const unsigned long long total = blocks == 0 ? 0 : (blocks - 1) * block + (last ? last : block);
    if (total != expected || (last > block))
        f.fail(a, fmt::format("the compressed blocks hold {} bytes, the array needs {}", total, expected));
    std::vector<unsigned long long> sizes(blocks);
    for (auto& s : sizes) s = next_header("compressed block size");
    data.resize(expected);
    std::string packed;
    for (unsigned long long b = 0; b < blocks; ++b) {
        // zlib inflates at most 1032:1, which bounds what a small corrupt file can claim.
        const unsigned long long want = (b + 1 == blocks && last) ? last : block;
        if (sizes[b] > src.bytes_left_bound() || want > 1032 * sizes[b] + 64 || !src.take(sizes[b], packed))
            f.fail(a, fmt::format("compressed block {} of {} bytes is not in the file", b, sizes[b]));
        uLongf got = static_cast<uLongf>(want);
        const int rc = uncompress(reinterpret_cast<Bytef*>(data.data() + b * block), &got,
                                  reinterpret_cast<const Bytef*>(packed.data()), static_cast<uLong>(packed.size()));
        if (rc != Z_OK || got != want) f.fail(a, fmt::format("compressed block {} does not inflate (zlib: {})", b, zError(rc)));
    }
    return data;
}

/// The values of DataArray `a`: `count` tuples of `components` (0: as the array says, returned in
/// `components`), converted to T.
template <class T>
std::vector<T> read_array(const VtuFile& f, const pugi::xml_node& a, unsigned long long count, int& components) {
    const int nc = a.attribute("NumberOfComponents").as_int(1);
    if (nc < 1 || nc > 64 || (components && nc != components))
        f.fail(a, fmt::format("NumberOfComponents is {}, expected {}", nc, components ? components : 1));
    components = nc;
    const TypeInfo info = type_info(f, a);
    if constexpr (std::is_integral_v<T>)
        if (info.is_float) f.fail(a, fmt::format("holds {}, not integers", a.attribute("type").value()));
    const unsigned long long n = count * nc;
    std::vector<T> out;
    const std::string format = a.attribute("format").value();
    if (format == "ascii") {
        const std::string_view text = a.child_value();
        out.reserve(std::min<size_t>(n, text.size() / 2 + 1));
        size_t i = 0;
        while (i < text.size()) {
            while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
            const size_t start = i;
            while (i < text.size() && !std::isspace(static_cast<unsigned char>(text[i]))) ++i;
            if (start == i) break;
            T v{};
            const auto [end, ec] = std::from_chars(text.data() + start, text.data() + i, v);
            if (ec != std::errc() || end != text.data() + i)
                f.fail(a, fmt::format("\"{}\" is not a number (value {})", text.substr(start, std::min<size_t>(i - start, 40)), out.size()));
            if (out.size() == n) f.fail(a, fmt::format("more than the {} values expected", n));
            out.push_back(v);
        }
        if (out.size() != n) f.fail(a, fmt::format("{} values, expected {}", out.size(), n));
        return out;
    }
    std::string bytes;
    if (format == "binary") {
        ByteSource src(a.child_value(), true);
        bytes = binary_payload(f, a, src, n * info.size);
    } else if (format == "appended") {
        const long long offset = a.attribute("offset").as_llong(-1);
        if (f.appended.empty() && f.appended.data() == nullptr) f.fail(a, "format \"appended\" but the file has no <AppendedData>");
        if (offset < 0 || static_cast<unsigned long long>(offset) > f.appended.size())
            f.fail(a, fmt::format("offset {} is outside the appended data ({} bytes)", a.attribute("offset").value(), f.appended.size()));
        ByteSource src(f.appended.substr(offset), f.appended_base64);
        bytes = binary_payload(f, a, src, n * info.size);
    } else {
        f.fail(a, fmt::format("format \"{}\" (ascii, binary or appended)", format));
    }
    out.resize(n);
    const bool swap = swapped(f);
    for (unsigned long long i = 0; i < n; ++i) {
        out[i] = decode_value<T>(bytes.data() + i * info.size, info, swap);
        if constexpr (std::is_floating_point_v<T>)
            if (!std::isfinite(out[i])) f.fail(a, fmt::format("value {} is NaN or infinite", i));
    }
    return out;
}

pugi::xml_node named_array(const VtuFile& f, const pugi::xml_node& parent, const char* name) {
    for (pugi::xml_node a : parent.children("DataArray"))
        if (std::string_view(a.attribute("Name").value()) == name) return a;
    f.fail(parent, fmt::format("has no DataArray Name=\"{}\"", name));
}

/// Splits off raw appended data (it is not XML) and reads the file's attributes.
void open_vtu(VtuFile& f, pugi::xml_document& doc) {
    std::string xml;  // the XML before the appended data, closed; empty: the whole file is XML
    const size_t app = f.text.find("<AppendedData");
    if (app != std::string::npos) {
        const size_t under = f.text.find('_', f.text.find('>', app));
        if (under == std::string::npos) throw InputError(f.path, "<AppendedData>", "no '_' marks the start of the data");
        const std::string tag = f.text.substr(app, f.text.find('>', app) - app);
        f.appended_base64 = tag.find("\"base64\"") != std::string::npos;
        f.appended = std::string_view(f.text).substr(under + 1);
        xml = f.text.substr(0, app) + "</VTKFile>";
    }
    const std::string_view parsed = xml.empty() ? std::string_view(f.text) : std::string_view(xml);
    const pugi::xml_parse_result r = doc.load_buffer(parsed.data(), parsed.size());
    if (!r) {
        const long long line = 1 + std::count(parsed.begin(), parsed.begin() + std::min<ptrdiff_t>(r.offset, parsed.size()), '\n');
        throw InputError(f.path, fmt::format("line {}", line), fmt::format("not valid XML: {}", r.description()));
    }
    const pugi::xml_node root = doc.child("VTKFile");
    if (!root) throw InputError(f.path, "<VTKFile>", "not a VTK XML file: no <VTKFile> element");
    if (std::string_view(root.attribute("type").value()) != "UnstructuredGrid")
        f.fail(root, fmt::format("type \"{}\": xcut reads UnstructuredGrid (.vtu) files", root.attribute("type").value()));
    const std::string order = root.attribute("byte_order").value(), header = root.attribute("header_type").value(),
                      compressor = root.attribute("compressor").value();
    f.big_endian = order == "BigEndian";
    f.header_bytes = header == "UInt64" ? 8 : 4;
    if (!header.empty() && header != "UInt64" && header != "UInt32") f.fail(root, fmt::format("header_type \"{}\"", header));
    f.zlib = compressor == "vtkZLibDataCompressor";
    if (!compressor.empty() && !f.zlib)
        f.fail(root, fmt::format("compressor \"{}\" is not supported: save uncompressed or with zlib", compressor));
}

}  // namespace

MeshData read_vtu(const std::string& path) {
    VtuFile f;
    f.path = path;
    f.text = read_input_file(path, "file", "mesh");
    pugi::xml_document doc;
    open_vtu(f, doc);
    const pugi::xml_node grid = doc.child("VTKFile").child("UnstructuredGrid");
    if (!grid) f.fail(doc.child("VTKFile"), "has no <UnstructuredGrid>");
    const pugi::xml_node piece = grid.child("Piece");
    if (!piece) f.fail(grid, "has no <Piece>");
    if (piece.next_sibling("Piece")) f.fail(grid, "has several pieces: merge them first (ParaView: Merge Blocks)");
    const long long np = piece.attribute("NumberOfPoints").as_llong(-1), nc = piece.attribute("NumberOfCells").as_llong(-1);
    if (np < 1 || np > 4 * kMaxMeshCells) f.fail(piece, fmt::format("NumberOfPoints {} (1 to {})", piece.attribute("NumberOfPoints").value(), 4 * kMaxMeshCells));
    if (nc < 1 || nc > 4 * kMaxMeshCells) f.fail(piece, fmt::format("NumberOfCells {} (1 to {})", piece.attribute("NumberOfCells").value(), 4 * kMaxMeshCells));

    MeshData mesh;
    mesh.source = path;
    int three = 3, one = 1;
    const pugi::xml_node pts = piece.child("Points").child("DataArray");
    if (!pts) f.fail(piece, "has no <Points><DataArray>");
    const std::vector<double> xyz = read_array<double>(f, pts, np, three);
    mesh.points.resize(np);
    for (long long i = 0; i < np; ++i) mesh.points[i] = Eigen::Vector3d(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);

    const pugi::xml_node cells = piece.child("Cells");
    if (!cells) f.fail(piece, "has no <Cells>");
    const pugi::xml_node offsets_node = named_array(f, cells, "offsets");
    const std::vector<long long> offsets = read_array<long long>(f, offsets_node, nc, one);
    const std::vector<long long> types = read_array<long long>(f, named_array(f, cells, "types"), nc, one);
    const long long total = offsets.back();
    if (total < 0 || total > 64 * nc) f.fail(offsets_node, fmt::format("the last offset {} is out of range", total));
    const std::vector<long long> conn = read_array<long long>(f, named_array(f, cells, "connectivity"), total, one);
    mesh_io_detail::VtkCells kept;
    for (long long e = 0; e < nc; ++e) {
        const long long begin = e ? offsets[e - 1] : 0, end = offsets[e];
        if (begin < 0 || end < begin || end > total) f.fail(offsets_node, fmt::format("offsets of cell {} run from {} to {}", e, begin, end));
        kept.add(e, static_cast<int>(types[e]), conn.data() + begin, end - begin, path);
    }
    std::vector<MeshData::CellArray> arrays;
    for (pugi::xml_node a : piece.child("CellData").children("DataArray")) {
        int components = 0;
        std::vector<double> values = read_array<double>(f, a, nc, components);
        arrays.push_back({a.attribute("Name").value(), components, std::move(values)});
    }
    kept.finish(mesh, std::move(arrays));
    return mesh;
}

}  // namespace xcut
