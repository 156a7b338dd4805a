#include "engine/io/vtu_writer.h"

#include <zlib.h>

#include <cstring>
#include <fmt/format.h>
#include <fstream>
#include <stdexcept>
#include <string_view>

namespace xcut {

namespace {

constexpr size_t kBlock = 32768;  ///< vtkZLibDataCompressor's block size [bytes]

void put_u64(std::string& out, uint64_t v) {
    char b[8];
    std::memcpy(b, &v, 8);  // x86-64 and AArch64 are little-endian, as the header says
    out.append(b, 8);
}

/// [blocks][block size][last block size][compressed size of each] then the zlib blocks.
std::string compressed(std::string_view raw) {
    const size_t blocks = raw.empty() ? 0 : (raw.size() + kBlock - 1) / kBlock;
    std::string header, body;
    put_u64(header, blocks);
    put_u64(header, kBlock);
    put_u64(header, blocks ? raw.size() - (blocks - 1) * kBlock : 0);
    for (size_t b = 0; b < blocks; ++b) {
        const size_t n = std::min(kBlock, raw.size() - b * kBlock);
        uLongf size = compressBound(static_cast<uLong>(n));
        std::string packed(size, '\0');
        // Level 1: most of zlib's size gain at a fraction of its time (output runs beside the step).
        if (compress2(reinterpret_cast<Bytef*>(packed.data()), &size, reinterpret_cast<const Bytef*>(raw.data() + b * kBlock),
                      static_cast<uLong>(n), 1) != Z_OK)
            throw std::runtime_error("zlib could not compress a VTU array");
        put_u64(header, size);
        body.append(packed.data(), size);
    }
    return header + body;
}

}  // namespace

template <class T>
VtuWriter::Array VtuWriter::make(const std::string& name, const char* type, int components, const std::vector<T>& values,
                                 bool pack) const {
    Array a;
    a.name = name, a.type = type, a.components = components, a.count = values.size();
    const std::string_view raw(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
    a.bytes = pack && !ascii_ ? compressed(raw) : std::string(raw);
    return a;
}

void VtuWriter::points(const std::vector<double>& xyz) {
    points_ = make("Points", "Float64", 3, xyz);
    point_count_ = xyz.size() / 3;
}

void VtuWriter::cells(const std::vector<int32_t>& connectivity, const std::vector<int32_t>& offsets,
                      const std::vector<uint8_t>& types) {
    cells_ = {make("connectivity", "Int32", 1, connectivity), make("offsets", "Int32", 1, offsets),
              make("types", "UInt8", 1, types)};
    cell_count_ = types.size();
}

void VtuWriter::point_data(const std::string& name, int components, const std::vector<double>& values) {
    point_data_.push_back(make(name, "Float64", components, values));
}
void VtuWriter::point_data(const std::string& name, const std::vector<uint8_t>& values) {
    point_data_.push_back(make(name, "UInt8", 1, values));
}
void VtuWriter::point_data(const std::string& name, const std::vector<int32_t>& values) {
    point_data_.push_back(make(name, "Int32", 1, values));
}
void VtuWriter::cell_data(const std::string& name, int components, const std::vector<double>& values) {
    cell_data_.push_back(make(name, "Float64", components, values));
}
void VtuWriter::cell_data(const std::string& name, const std::vector<int32_t>& values) {
    cell_data_.push_back(make(name, "Int32", 1, values));
}
void VtuWriter::cell_data(const std::string& name, const std::vector<uint8_t>& values) {
    cell_data_.push_back(make(name, "UInt8", 1, values));
}
void VtuWriter::field(const std::string& name, const std::string& text) {
    std::vector<uint8_t> bytes(text.begin(), text.end());
    fields_.push_back(make(name, "UInt8", 1, bytes, /*pack=*/false));  // VTK stores strings as UInt8 arrays with NumberOfTuples
}

void VtuWriter::open_array(std::string& xml, const Array& a, size_t& offset) const {
    xml += fmt::format("<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" ", a.type, a.name, a.components);
    if (!ascii_) {
        xml += fmt::format("format=\"appended\" offset=\"{}\"/>\n", offset);
        offset += a.bytes.size();
        return;
    }
    xml += "format=\"ascii\">\n";
    for (size_t i = 0; i < a.count; ++i) {
        if (a.type == "Float64") {
            double v;
            std::memcpy(&v, a.bytes.data() + 8 * i, 8);
            xml += fmt::format("{:.10g}", v);
        } else if (a.type == "Int32") {
            int32_t v;
            std::memcpy(&v, a.bytes.data() + 4 * i, 4);
            xml += fmt::format("{}", v);
        } else {
            xml += fmt::format("{}", static_cast<int>(static_cast<uint8_t>(a.bytes[i])));
        }
        xml += (i + 1) % (a.components * 3) == 0 ? '\n' : ' ';
    }
    xml += "\n</DataArray>\n";
}

void VtuWriter::write(const std::string& path) const {
    std::string xml = fmt::format("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
                                  "byte_order=\"LittleEndian\" header_type=\"UInt64\"{}>\n<UnstructuredGrid>\n",
                                  ascii_ ? "" : " compressor=\"vtkZLibDataCompressor\"");
    size_t offset = 0;  // into the appended data, where each array's compressed bytes go in this order
    if (!fields_.empty()) {
        xml += "<FieldData>\n";
        for (const Array& f : fields_) {
            xml += fmt::format("<Array type=\"String\" Name=\"{}\" NumberOfTuples=\"1\" format=\"ascii\">\n", f.name);
            for (unsigned char c : f.bytes) xml += fmt::format("{} ", int(c));
            xml += "0\n</Array>\n";
        }
        xml += "</FieldData>\n";
    }
    xml += fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n<PointData>\n", point_count_, cell_count_);
    for (const Array& a : point_data_) open_array(xml, a, offset);
    xml += "</PointData>\n<CellData>\n";
    for (const Array& a : cell_data_) open_array(xml, a, offset);
    xml += "</CellData>\n<Points>\n";
    open_array(xml, points_, offset);
    xml += "</Points>\n<Cells>\n";
    for (const Array& a : cells_) open_array(xml, a, offset);
    xml += "</Cells>\n</Piece>\n</UnstructuredGrid>\n";
    if (!ascii_) xml += "<AppendedData encoding=\"raw\">\n_";
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << xml;
    if (!ascii_) {  // straight from each array: no second copy of them all
        for (const std::vector<Array>* arrays : {&point_data_, &cell_data_})
            for (const Array& a : *arrays) out << a.bytes;
        out << points_.bytes;
        for (const Array& a : cells_) out << a.bytes;
        out << "\n</AppendedData>\n";
    }
    out << "</VTKFile>\n";
    if (!out) throw std::runtime_error(fmt::format("{}: cannot write", path));
}

}  // namespace xcut
