// Gmsh .msh reader: format 1 ($NOD/$ELM), 2.2 and 4.1, each ASCII or binary (4.1 binary with 4- or
// 8-byte sizes). Tetrahedra, else triangles as a 2D mesh; second- and higher-order cells are read as
// their corners (Gmsh numbers the corners first), with a note. Physical groups become regions
// (MeshData::cell_region, named from $PhysicalNames). Nodes and elements are named in messages by
// their tags. Format reference: the Gmsh manual, section "MSH file format" (4.1) and its
// "Legacy formats" appendix (1 and 2.2).
#include <fmt/format.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <map>
#include <unordered_map>
#include <vector>

#include "engine/error.h"
#include "engine/io/byte_cursor.h"
#include "engine/io/input_file.h"
#include "engine/io/mesh_io.h"

namespace xcut {
namespace {

using mesh_io_detail::ByteCursor;

/// Nodes per element for the Gmsh types a file may hold (its manual's table); -1 if unknown.
int gmsh_type_nodes(long long type) {
    static const std::map<long long, int> kNodes = {
        {1, 2},   {2, 3},   {3, 4},   {4, 4},   {5, 8},   {6, 6},   {7, 5},   {8, 3},   {9, 6},   {10, 9},
        {11, 10}, {12, 27}, {13, 18}, {14, 14}, {15, 1},  {16, 8},  {17, 20}, {18, 15}, {19, 13}, {20, 9},
        {21, 10}, {22, 12}, {23, 15}, {24, 15}, {25, 21}, {26, 4},  {27, 5},  {28, 6},  {29, 20}, {30, 35},
        {31, 56}, {92, 64}, {93, 125}};
    const auto it = kNodes.find(type);
    return it == kNodes.end() ? -1 : it->second;
}
/// Tetrahedra of any order (4: linear, 11: 10-node, 29/30/31: third to fifth order) and triangles.
bool is_tet(long long type) { return type == 4 || type == 11 || type == 29 || type == 30 || type == 31; }
bool is_tri(long long type) { return type == 2 || type == 9 || (type >= 20 && type <= 25); }

class GmshReader {
public:
    GmshReader(const std::string& path, std::string_view text) : c_(path, text) { mesh_.source = path; }
    MeshData read();

private:
    // The header and the section loop (format 2.2 and 4.1).
    void read_format_header();
    void skip_section(std::string_view name);
    void read_physical_names();
    void read_entities();
    void read_nodes2();
    void read_elements2();
    /// The counts that open a 4.1 section: entity blocks and `item`s (nodes, elements).
    std::pair<long long, long long> read_section_header4(const char* item, size_t min_bytes_each);
    void read_nodes4();
    void read_elements4();
    void read_format1();
    // Values: ASCII tokens or binary, as the file stores them.
    long long read_int(const char* what) { return binary_ ? c_.binary<int32_t>(what, big_) : c_.integer(what); }
    long long read_size(const char* what) {
        if (!binary_) return c_.integer(what);
        const unsigned long long v = size_bytes_ == 8 ? c_.binary<uint64_t>(what, big_) : c_.binary<uint32_t>(what, big_);
        if (v > (1ull << 62)) c_.fail(fmt::format("{} {} is out of range", what, v));
        return static_cast<long long>(v);
    }
    double read_real(const char* what) { return binary_ ? c_.binary<double>(what, big_) : c_.real(what); }
    void add_node(long long tag, const Eigen::Vector3d& p);
    void add_element(long long type, long long tag, const long long* node_tags, int region);
    int node_index(long long tag) const;
    MeshData finish();

    ByteCursor c_;
    MeshData mesh_;
    double version_ = 0.0;
    bool binary_ = false, big_ = false;
    int size_bytes_ = 8;
    std::unordered_map<long long, int> node_of_tag_;
    std::map<std::pair<int, int>, int> entity_physical_;  ///< (dim, entity tag) -> first physical tag
    std::map<std::pair<int, int>, std::string> physical_names_;  ///< (dim, physical tag) -> name
    std::vector<std::array<int, 4>> tets_, tris_;
    std::vector<long long> tet_tag_, tri_tag_;
    std::vector<int> tet_region_, tri_region_;
    std::map<long long, long long> high_order_, skipped_;  ///< type -> count
};

void GmshReader::add_node(long long tag, const Eigen::Vector3d& p) {
    const auto [it, fresh] = node_of_tag_.emplace(tag, static_cast<int>(mesh_.points.size()));
    if (!fresh) c_.fail(fmt::format("node {} is defined twice", tag));
    mesh_.points.push_back(p);
    mesh_.point_id.push_back(tag);
}

int GmshReader::node_index(long long tag) const {
    const auto it = node_of_tag_.find(tag);
    if (it == node_of_tag_.end()) c_.fail(fmt::format("element refers to node {}, which $Nodes does not define", tag));
    return it->second;
}

void GmshReader::add_element(long long type, long long tag, const long long* node_tags, int region) {
    const bool tet = is_tet(type), tri = is_tri(type);
    if (!tet && !tri) {
        ++skipped_[type];
        return;
    }
    if (type != 4 && type != 2) ++high_order_[type];
    std::array<int, 4> cell{-1, -1, -1, -1};
    for (int a = 0; a < (tet ? 4 : 3); ++a) cell[a] = node_index(node_tags[a]);
    (tet ? tets_ : tris_).push_back(cell);
    (tet ? tet_tag_ : tri_tag_).push_back(tag);
    (tet ? tet_region_ : tri_region_).push_back(region);
}

void GmshReader::read_format_header() {
    version_ = c_.real("format version");
    const long long file_type = c_.integer("file type");
    size_bytes_ = static_cast<int>(c_.integer("data size"));
    if (file_type != 0 && file_type != 1) c_.fail(fmt::format("file type {} (0: ASCII, 1: binary)", file_type));
    binary_ = file_type == 1;
    const bool v2 = version_ >= 2.0 && version_ < 3.0, v41 = version_ >= 4.1 && version_ < 5.0;
    if (!v2 && !v41)
        c_.fail(fmt::format("format {} is not supported (1, 2.2 or 4.1; in Gmsh: File > Export, or -format msh22)", version_));
    if (binary_) {
        if (size_bytes_ != 8 && !(v41 && size_bytes_ == 4)) c_.fail(fmt::format("data size {} (8 expected)", size_bytes_));
        c_.end_line();
        // The integer 1, written in the file's byte order: tells the order.
        const int32_t one = c_.binary<int32_t>("the byte-order integer 1", false);
        const bool host_big = ByteCursor::host_big_endian();
        if (one == 1) big_ = host_big;
        else if (one == 0x01000000) big_ = !host_big;
        else c_.fail(fmt::format("the byte-order integer reads {}, not 1", one));
    }
    c_.expect("$EndMeshFormat");
}

void GmshReader::skip_section(std::string_view name) {
    const std::string end = "$End" + std::string(name.substr(1));
    if (!c_.seek(end)) c_.fail(fmt::format("section {} has no {}", name, end));
}

void GmshReader::read_physical_names() {
    const long long n = c_.count("physical name count", 6);
    for (long long i = 0; i < n; ++i) {
        const int dim = static_cast<int>(c_.integer("physical dimension"));
        const int tag = static_cast<int>(c_.integer("physical tag"));
        std::string_view name = c_.rest_of_line();
        while (!name.empty() && (name.front() == ' ' || name.front() == '\t')) name.remove_prefix(1);
        if (name.size() >= 2 && name.front() == '"' && name.back() == '"') name = name.substr(1, name.size() - 2);
        physical_names_[{dim, tag}] = std::string(name);
    }
    c_.expect("$EndPhysicalNames");
}

void GmshReader::read_entities() {
    if (binary_) c_.end_line();
    long long counts[4];
    for (long long& n : counts) n = read_size("entity count");
    for (int dim = 0; dim < 4; ++dim) {
        c_.check_count(counts[dim], "entity count", 8);
        for (long long i = 0; i < counts[dim]; ++i) {
            const int tag = static_cast<int>(read_int("entity tag"));
            for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) read_real("entity box");
            const long long nphys = read_size("physical tag count");
            c_.check_count(nphys, "physical tag count", 1);
            for (long long k = 0; k < nphys; ++k) {
                const int phys = static_cast<int>(read_int("physical tag"));
                if (k == 0) entity_physical_[{dim, tag}] = phys;
            }
            if (dim == 0) continue;
            const long long nbound = read_size("bounding entity count");
            c_.check_count(nbound, "bounding entity count", 1);
            for (long long k = 0; k < nbound; ++k) read_int("bounding entity");
        }
    }
    c_.expect("$EndEntities");
}

void GmshReader::read_nodes2() {
    const long long n = c_.count("node count", binary_ ? 28 : 8);
    if (binary_) c_.end_line();
    for (long long i = 0; i < n; ++i) {
        const long long tag = read_int("node tag");
        Eigen::Vector3d p;
        for (int k = 0; k < 3; ++k) p[k] = read_real("coordinate");
        add_node(tag, p);
    }
    c_.expect("$EndNodes");
}

void GmshReader::read_elements2() {
    const long long m = c_.count("element count", binary_ ? 12 : 8);
    if (binary_) c_.end_line();
    std::vector<long long> nodes;
    long long read = 0;
    while (read < m) {
        // ASCII: one element a line; binary: a header (type, elements, tags) then that many elements.
        const long long type = binary_ ? read_int("element type") : 0;
        const long long in_group = binary_ ? read_int("elements in group") : 1;
        const long long ntags_group = binary_ ? read_int("tag count") : 0;
        if (in_group < 1 || in_group > m - read) c_.fail(fmt::format("element group of {} (elements left: {})", in_group, m - read));
        for (long long e = 0; e < in_group; ++e) {
            const long long tag = read_int("element tag");
            const long long t = binary_ ? type : c_.integer("element type");
            const long long ntags = binary_ ? ntags_group : c_.integer("tag count");
            if (ntags < 0 || ntags > 64) c_.fail(fmt::format("implausible tag count {}", ntags));
            int physical = 0;
            for (long long k = 0; k < ntags; ++k) {
                const long long v = read_int("element tag");
                if (k == 0) physical = static_cast<int>(v);
            }
            const int nn = gmsh_type_nodes(t);
            if (nn < 0) c_.fail(fmt::format("unknown element type {}", t));
            nodes.resize(nn);
            for (int k = 0; k < nn; ++k) nodes[k] = read_int("node tag");
            add_element(t, tag, nodes.data(), physical);
        }
        read += in_group;
    }
    c_.expect("$EndElements");
}

std::pair<long long, long long> GmshReader::read_section_header4(const char* item, size_t min_bytes_each) {
    // numEntityBlocks numItems minTag maxTag (format 4.1 $Nodes and $Elements).
    if (binary_) c_.end_line();
    const long long blocks = read_size("entity block count");
    const long long total = read_size(fmt::format("{} count", item).c_str());
    c_.check_count(blocks, "entity block count", 8);
    c_.check_count(total, fmt::format("{} count", item).c_str(), min_bytes_each);
    read_size("min tag"), read_size("max tag");
    return {blocks, total};
}

void GmshReader::read_nodes4() {
    const auto [blocks, total] = read_section_header4("node", binary_ ? 32 : 8);
    std::vector<long long> tags;
    for (long long b = 0; b < blocks; ++b) {
        const long long dim = read_int("entity dim");
        read_int("entity tag");
        const long long parametric = read_int("parametric flag");
        const long long n = read_size("nodes in block");
        c_.check_count(n, "nodes in block", binary_ ? 32 : 8);
        tags.resize(n);
        for (long long& t : tags) t = read_size("node tag");
        const long long extra = parametric ? std::clamp(dim, 0LL, 3LL) : 0;  // u (curves), u v (surfaces)
        for (long long i = 0; i < n; ++i) {
            Eigen::Vector3d p;
            for (int k = 0; k < 3; ++k) p[k] = read_real("coordinate");
            for (long long k = 0; k < extra; ++k) read_real("parametric coordinate");
            add_node(tags[i], p);
        }
    }
    if (static_cast<long long>(mesh_.points.size()) != total)
        c_.fail(fmt::format("$Nodes announces {} nodes but its blocks hold {}", total, mesh_.points.size()));
    c_.expect("$EndNodes");
}

void GmshReader::read_elements4() {
    const long long blocks = read_section_header4("element", 4).first;
    std::vector<long long> nodes;
    for (long long b = 0; b < blocks; ++b) {
        const int dim = static_cast<int>(read_int("entity dim"));
        const int entity = static_cast<int>(read_int("entity tag"));
        const long long type = read_int("element type");
        const int nn = gmsh_type_nodes(type);
        if (nn < 0) c_.fail(fmt::format("unknown element type {}", type));
        const long long n = read_size("elements in block");
        c_.check_count(n, "elements in block", binary_ ? 8 * (nn + 1) : 2 * (nn + 1));
        const auto phys = entity_physical_.find({dim, entity});
        const int region = phys == entity_physical_.end() ? 0 : phys->second;
        nodes.resize(nn);
        for (long long i = 0; i < n; ++i) {
            const long long tag = read_size("element tag");
            for (long long& t : nodes) t = read_size("node tag");
            add_element(type, tag, nodes.data(), region);
        }
    }
    c_.expect("$EndElements");
}

void GmshReader::read_format1() {
    // $NOD n, "tag x y z" lines, $ENDNOD; $ELM m, "tag type physical elementary nodes n1 n2 ..." lines, $ENDELM.
    const long long n = c_.count("node count", 8);
    for (long long i = 0; i < n; ++i) {
        const long long tag = c_.integer("node tag");
        Eigen::Vector3d p;
        for (int k = 0; k < 3; ++k) p[k] = c_.real("coordinate");
        add_node(tag, p);
    }
    c_.expect("$ENDNOD");
    if (!c_.seek("$ELM")) c_.fail("no $ELM section after $ENDNOD");
    const long long m = c_.count("element count", 10);
    std::vector<long long> nodes;
    for (long long e = 0; e < m; ++e) {
        const long long tag = c_.integer("element tag");
        const long long type = c_.integer("element type");
        const int physical = static_cast<int>(c_.integer("physical region"));
        c_.integer("elementary region");
        const long long nn = c_.integer("node count");
        const int expected = gmsh_type_nodes(type);
        if (expected < 0) c_.fail(fmt::format("unknown element type {}", type));
        if (nn != expected) c_.fail(fmt::format("element type {} has {} nodes, not {}", type, expected, nn));
        nodes.resize(nn);
        for (long long& t : nodes) t = c_.integer("node tag");
        add_element(type, tag, nodes.data(), physical);
    }
    c_.expect("$ENDELM");
}

MeshData GmshReader::read() {
    const std::string_view first = c_.token("$MeshFormat or $NOD");
    if (first == "$NOD" || first == "$NOE") {
        version_ = 1.0;
        read_format1();
        return finish();
    }
    if (first != "$MeshFormat")
        c_.fail(fmt::format("not a Gmsh file: it begins with \"{}\", not $MeshFormat (formats 2.2, 4.1) or $NOD (format 1)",
                            ByteCursor::clip(first)));
    read_format_header();
    bool nodes = false, elements = false;
    while (!c_.done()) {
        const std::string_view section = c_.token("a section");
        if (section.empty() || section[0] != '$') c_.fail(fmt::format("expected a section ($Name), found \"{}\"", ByteCursor::clip(section)));
        const bool v4 = version_ >= 4.0;
        if (section == "$PhysicalNames") read_physical_names();
        else if (section == "$Entities" && v4) read_entities();
        else if (section == "$Nodes" && !nodes) {
            v4 ? read_nodes4() : read_nodes2();
            nodes = true;
        } else if (section == "$Elements" && !elements) {
            if (!nodes) c_.fail("$Elements comes before $Nodes");
            v4 ? read_elements4() : read_elements2();
            elements = true;
        } else if (section == "$Nodes" || section == "$Elements") c_.fail(fmt::format("a second {} section", section));
        else skip_section(section);
    }
    if (!nodes) c_.fail("no $Nodes section");
    if (!elements) c_.fail("no $Elements section");
    return finish();
}

MeshData GmshReader::finish() {
    const bool three_d = !tets_.empty();
    if (!three_d && tris_.empty()) {
        std::string found;
        for (const auto& [type, n] : skipped_) found += fmt::format("{}{} of type {}", found.empty() ? "" : ", ", n, type);
        throw InputError(mesh_.source, "$Elements",
                         fmt::format("no tetrahedra or triangles (Gmsh types 4, 11 and 2, 9); the file holds {}",
                                     found.empty() ? "no elements" : found));
    }
    mesh_.dim = three_d ? 3 : 2;
    mesh_.cells = std::move(three_d ? tets_ : tris_);
    mesh_.cell_id = std::move(three_d ? tet_tag_ : tri_tag_);
    std::vector<int>& region = three_d ? tet_region_ : tri_region_;
    for (int r : region)
        if (r != 0) {
            mesh_.cell_region = std::move(region);
            break;
        }
    for (const auto& [key, name] : physical_names_)
        if (key.first == mesh_.dim) mesh_.region_names[key.second] = name;
    for (const auto& [type, n] : high_order_)
        if (is_tet(type) == three_d)
            mesh_.notes.push_back(fmt::format("{} {}-node {} (Gmsh type {}) read as linear {}: their corner nodes only", n,
                                          gmsh_type_nodes(type), three_d ? "tetrahedra" : "triangles", type,
                                          three_d ? "tetrahedra" : "triangles"));
    return std::move(mesh_);
}

}  // namespace

MeshData read_gmsh(const std::string& path) {
    const std::string text = read_input_file(path, "file", "mesh");
    return GmshReader(path, text).read();
}

}  // namespace xcut
