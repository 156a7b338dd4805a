#pragma once
// A VTK XML UnstructuredGrid (.vtu) writer: arrays in binary appended data compressed by zlib (what
// ParaView and VTK write by default; header UInt64, 32 KiB blocks as vtkZLibDataCompressor makes
// them), or ASCII for reading by eye. The arrays are given first, the file is written at the end.
// Format reference: VTK's "VTK File Formats" (XML formats). The reader (vtu_reader.cpp) and VTK's
// own reader in Python read these files in tests/engine/io/test_output_files.cpp. In binary an array
// is compressed as it is given, so the writer holds the compressed bytes only, not a second copy of
// every array (at 53k tets the raw copies were ~10 MB of the run's peak memory).
#include <cstdint>
#include <string>
#include <vector>

namespace xcut {

class VtuWriter {
public:
    explicit VtuWriter(bool ascii) : ascii_(ascii) {}

    /// Points [m], 3 per point.
    void points(const std::vector<double>& xyz);
    /// Cells: connectivity, end offsets, VTK cell types.
    void cells(const std::vector<int32_t>& connectivity, const std::vector<int32_t>& offsets,
               const std::vector<uint8_t>& types);
    void point_data(const std::string& name, int components, const std::vector<double>& values);
    void point_data(const std::string& name, const std::vector<uint8_t>& values);
    void point_data(const std::string& name, const std::vector<int32_t>& values);
    void cell_data(const std::string& name, int components, const std::vector<double>& values);
    void cell_data(const std::string& name, const std::vector<int32_t>& values);
    void cell_data(const std::string& name, const std::vector<uint8_t>& values);
    /// A string kept with the file (FieldData), e.g. the units of the arrays.
    void field(const std::string& name, const std::string& text);
    /// Writes the file; throws std::runtime_error if it cannot.
    void write(const std::string& path) const;

private:
    struct Array {
        std::string name, type;  ///< VTK type: Float64, Int32, UInt8
        int components = 1;
        std::string bytes;       ///< little-endian values; compressed when the file is binary (not a field)
        size_t count = 0;        ///< values
    };
    template <class T>
    Array make(const std::string& name, const char* type, int components, const std::vector<T>& values,
               bool pack = true) const;
    void open_array(std::string& xml, const Array& a, size_t& offset) const;

    bool ascii_;
    Array points_;
    std::vector<Array> cells_, point_data_, cell_data_, fields_;
    size_t cell_count_ = 0, point_count_ = 0;
};

}  // namespace xcut
