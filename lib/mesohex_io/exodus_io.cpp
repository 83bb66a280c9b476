// Exodus II writer on Debian's libexodusii (the C API of Exodus 6). Every call is checked; a failure closes the file,
// removes the temporary file (write_atomically_via) and throws IoError with the library's own message.
#include "mesohex_io/exodus_io.h"

#include <algorithm>
#include <array>
#include <string>

#include <exodusII.h>

#include "mesohex/core/error.h"
#include "mesohex/core/topology.h"
#include "mesohex_io/hex_io.h"

namespace mesohex {
namespace {

// Bytes per floating-point value in memory (we pass doubles) and in the file (stored as doubles).
constexpr int kDoubleWordSize = 8;

// An open Exodus file; closed when it goes out of scope (on errors too).
class ExodusFile {
public:
    ExodusFile(const std::string& temporary, const std::string& path) : path_(path) {
        int compute_word_size = kDoubleWordSize, io_word_size = kDoubleWordSize;
        // EX_LARGE_MODEL = NetCDF's 64-bit-offset format (NetCDF 3); EX_CLOBBER because the temporary file exists.
        id_ = ex_create(temporary.c_str(), EX_CLOBBER | EX_LARGE_MODEL, &compute_word_size, &io_word_size);
        if (id_ < 0) fail("ex_create");
    }
    ~ExodusFile() {
        if (id_ >= 0) ex_close(id_);
    }
    ExodusFile(const ExodusFile&) = delete;
    ExodusFile& operator=(const ExodusFile&) = delete;

    int id() const { return id_; }
    void check(int status, const char* call) const {
        if (status < 0) fail(call);
    }
    void close() {
        const int status = ex_close(id_);
        id_ = -1;
        check(status, "ex_close");
    }

private:
    [[noreturn]] void fail(const char* call) const {
        const char* message = nullptr;
        const char* function = nullptr;
        int code = 0;
        ex_get_err(&message, &function, &code);
        throw Error(ErrorCode::IoError, path_ + ": cannot write the Exodus II file (" + call + "): " +
                                            (message != nullptr && *message != '\0' ? message : "unknown error"));
    }

    std::string path_;
    int id_ = -1;
};

// Hexes in file order: grouped by part (stable, so hex order inside a part), or all hexes in order.
struct ElementOrder {
    std::vector<int> hex_of_element;  // file element e (0-based) -> hex
    std::vector<int> element_of_hex;  // hex -> file element (0-based)
    std::vector<long> block_size;     // elements per block; block b has id b + 1
};

ElementOrder element_order(std::size_t num_hexes, const std::vector<int>& partition) {
    ElementOrder order;
    order.hex_of_element.resize(num_hexes);
    for (std::size_t h = 0; h < num_hexes; ++h) order.hex_of_element[h] = static_cast<int>(h);
    if (partition.empty()) {
        order.block_size.assign(1, static_cast<long>(num_hexes));
    } else {
        std::stable_sort(order.hex_of_element.begin(), order.hex_of_element.end(), [&](int a, int b) {
            return partition[static_cast<std::size_t>(a)] < partition[static_cast<std::size_t>(b)];
        });
        const int parts = *std::max_element(partition.begin(), partition.end()) + 1;
        order.block_size.assign(static_cast<std::size_t>(parts), 0);
        for (int p : partition) ++order.block_size[static_cast<std::size_t>(p)];
    }
    order.element_of_hex.resize(num_hexes);
    for (std::size_t e = 0; e < num_hexes; ++e)
        order.element_of_hex[static_cast<std::size_t>(order.hex_of_element[e])] = static_cast<int>(e);
    return order;
}

void write_nodes(ExodusFile& file, const HexMesh& mesh) {
    std::vector<double> x(mesh.points.size()), y(mesh.points.size()), z(mesh.points.size());
    for (std::size_t v = 0; v < mesh.points.size(); ++v) {
        x[v] = mesh.points[v].x;
        y[v] = mesh.points[v].y;
        z[v] = mesh.points[v].z;
    }
    file.check(ex_put_coord(file.id(), x.data(), y.data(), z.data()), "ex_put_coord");
    std::array<char, 2> nx{'x', '\0'}, ny{'y', '\0'}, nz{'z', '\0'};
    char* names[3] = {nx.data(), ny.data(), nz.data()};
    file.check(ex_put_coord_names(file.id(), names), "ex_put_coord_names");
}

void write_blocks(ExodusFile& file, const HexMesh& mesh, const ElementOrder& order, bool partitioned) {
    std::size_t first = 0;
    for (std::size_t b = 0; b < order.block_size.size(); ++b) {
        const ex_entity_id id = static_cast<ex_entity_id>(b + 1);
        const std::size_t n = static_cast<std::size_t>(order.block_size[b]);
        file.check(ex_put_block(file.id(), EX_ELEM_BLOCK, id, "HEX8", static_cast<int64_t>(n), 8, 0, 0, 0),
                   "ex_put_block");
        const std::string name = partitioned ? "partition_" + std::to_string(b) : "hexes";
        file.check(ex_put_name(file.id(), EX_ELEM_BLOCK, id, name.c_str()), "ex_put_name");
        if (n > 0) {
            std::vector<int> connectivity;
            connectivity.reserve(n * 8);
            for (std::size_t e = first; e < first + n; ++e)
                for (int v : mesh.hexes[static_cast<std::size_t>(order.hex_of_element[e])])
                    connectivity.push_back(v + 1);
            file.check(ex_put_conn(file.id(), EX_ELEM_BLOCK, id, connectivity.data(), nullptr, nullptr), "ex_put_conn");
        }
        first += n;
    }
    std::vector<int> element_ids(order.hex_of_element.size());
    for (std::size_t e = 0; e < element_ids.size(); ++e) element_ids[e] = order.hex_of_element[e] + 1;
    file.check(ex_put_id_map(file.id(), EX_ELEM_MAP, element_ids.data()), "ex_put_id_map");
}

void write_boundary_side_set(ExodusFile& file, const HexMesh& mesh, const ElementOrder& order) {
    const HexTopology topo = compute_hex_topology(mesh);
    std::vector<int> elements, sides;
    elements.reserve(topo.boundary_face.size());
    sides.reserve(topo.boundary_face.size());
    for (int f : topo.boundary_face) {
        const int h = topo.face_hexes[static_cast<std::size_t>(f)][0];
        const std::array<int, 6>& faces = topo.hex_faces[static_cast<std::size_t>(h)];
        const int lf = static_cast<int>(std::find(faces.begin(), faces.end(), f) - faces.begin());
        MESOHEX_CHECK(lf < 6, "a boundary face belongs to its hex");
        elements.push_back(order.element_of_hex[static_cast<std::size_t>(h)] + 1);
        sides.push_back(kExodusSideOfHexFace[lf]);
    }
    constexpr ex_entity_id kBoundaryId = 1;
    file.check(ex_put_set_param(file.id(), EX_SIDE_SET, kBoundaryId, static_cast<int64_t>(elements.size()), 0),
               "ex_put_set_param");
    if (!elements.empty())
        file.check(ex_put_set(file.id(), EX_SIDE_SET, kBoundaryId, elements.data(), sides.data()), "ex_put_set");
    file.check(ex_put_name(file.id(), EX_SIDE_SET, kBoundaryId, "boundary"), "ex_put_name");
}

void write_scaled_jacobian(ExodusFile& file, const std::vector<double>& cell_scalars, const ElementOrder& order) {
    file.check(ex_put_variable_param(file.id(), EX_ELEM_BLOCK, 1), "ex_put_variable_param");
    file.check(ex_put_variable_name(file.id(), EX_ELEM_BLOCK, 1, "scaled_jacobian"), "ex_put_variable_name");
    const double time = 0.0;
    file.check(ex_put_time(file.id(), 1, &time), "ex_put_time");
    std::size_t first = 0;
    for (std::size_t b = 0; b < order.block_size.size(); ++b) {
        const std::size_t n = static_cast<std::size_t>(order.block_size[b]);
        if (n == 0) continue;
        std::vector<double> values(n);
        for (std::size_t i = 0; i < n; ++i)
            values[i] = cell_scalars[static_cast<std::size_t>(order.hex_of_element[first + i])];
        file.check(ex_put_var(file.id(), 1, EX_ELEM_BLOCK, 1, static_cast<ex_entity_id>(b + 1), static_cast<int64_t>(n),
                              values.data()),
                   "ex_put_var");
        first += n;
    }
}

}  // namespace

void write_exodus(const std::string& path, const HexMesh& mesh, const std::vector<double>& cell_scalars,
                  const std::vector<int>& partition) {
    if (mesh.hexes.empty())
        throw Error(ErrorCode::InvalidInput, path + ": cannot write an Exodus II file without hexes");
    const ElementOrder order = element_order(mesh.hexes.size(), partition);
    write_atomically_via(path, [&](const std::string& temporary) {
        ExodusFile file(temporary, path);
        file.check(
            ex_put_init(file.id(), "mesohex hex mesh", 3, static_cast<int64_t>(mesh.points.size()),
                        static_cast<int64_t>(mesh.hexes.size()), static_cast<int64_t>(order.block_size.size()), 0, 1),
            "ex_put_init");
        write_nodes(file, mesh);
        write_blocks(file, mesh, order, !partition.empty());
        write_boundary_side_set(file, mesh, order);
        if (!cell_scalars.empty()) write_scaled_jacobian(file, cell_scalars, order);
        file.close();
    });
}

}  // namespace mesohex
