#pragma once
// The binary form of an answer (docs/studio.md, "Binary answers"): a JSON header and typed little-endian arrays, so
// that the page gets a 10 k-hex mesh without printing and parsing megabytes of decimal text.
//
//   bytes 0-3    "MHXB"
//   bytes 4-7    uint32 version (1)
//   bytes 8-11   uint32 H: bytes of the header
//   12 .. 12+H   the header, JSON text (UTF-8), padded with spaces so that H is a multiple of 4
//   then         the arrays listed in header["arrays"] = [{"name", "type": "f32" | "u32" | "enum", "count"}, ...],
//                in that order, each count x 4 bytes, little-endian (so every array starts 4-byte aligned)
//
// Integers are uint32 (indices and valences are >= 0); reals are IEEE float32 (rounded to nearest). An "enum" array
// is an array of strings drawn from a few names (the analysis' vertex classes and edge kinds): its entry also has
// "names": [...], and each value is the uint32 index of its string in "names".
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mesohex/core/vec.h"

namespace mesohex::studio {

inline constexpr std::uint32_t kBinaryAnswerVersion = 1;

// The arrays of an answer, appended in order: names, types and counts, and the bytes already encoded.
struct BinaryArrays {
    nlohmann::json list = nlohmann::json::array();  // [{"name", "type", "count"}, ...]
    std::string bytes;                              // the encoded arrays, one after the other
};

void append_f32(BinaryArrays& arrays, const std::string& name, const std::vector<double>& values);
void append_f32(BinaryArrays& arrays, const std::string& name, const std::vector<Vec3>& points);  // x,y,z,...
// Strings as an "enum" array: `names` in order of first appearance, one code per string.
void append_enum(BinaryArrays& arrays, const std::string& name, const std::vector<const char*>& strings);
// Every int of every cell (cells: std::array<int, N> or std::vector<int>), flat. Precondition: all >= 0.
template <typename Cells>
void append_u32_cells(BinaryArrays& arrays, const std::string& name, const Cells& cells);

// The whole answer: header (an object; "arrays" is set from `arrays`) then the arrays.
std::string binary_answer(nlohmann::json header, const BinaryArrays& arrays);
// The same with the header given as the text of a JSON object without "arrays" (`{...}`, e.g. written by hand so that
// large members are serialized once); "arrays" is appended as its last member.
std::string binary_answer_text(std::string header_object, const BinaryArrays& arrays);

// A patch answer (docs/studio.md, "Sessions and deltas"): `full` as changes to `base`, the arrays of the previous
// answer the reader holds. Each array of `full` that `base` has with the same name, type, count (and names, for an
// enum) and of which fewer than half the values differ becomes {"name", "type", "count", "patch": M} (+ "names"),
// its data M uint32 value indices (increasing) then the M new values (4 bytes each); the others stay whole. The
// header should say which answer it patches ("patch_of").
//
// Row patches, for arrays of rows that `layouts` names (an edit that renumbers the mesh: a branch resampled with one
// vertex more shifts every later vertex, hex and quad): the array is read as rows of `width` values, and the first
// `ref_columns` values of a row are row numbers of the array `ref` (an earlier array). Its entry becomes
// {"name", "type", "count", "width": W, "rows": K, "literal": L} (+ "ref", "ref_columns": R), its data K runs of
// two uint32 (length, source: the first row of base copied, or 0xFFFFFFFF for literal rows) then the L literal rows
// (L x W values), the new rows in order. A copied row is base's row with its first R values translated: v -> the last
// new row copied from base's row v of `ref` when `ref` is row-patched (0xFFFFFFFF when none is), v itself
// otherwise. The server finds runs by continuing the previous one or by a hash of the translated base rows, and keeps
// a run only where the translated row equals the new one bit for bit: the result is exact. A row patch is tried only
// when the value patch is impossible or changes more than 1/64 of the values, and sent only when it is the smaller.
struct RowLayout {
    std::string name;
    std::size_t width = 1;
    std::string ref;  // empty: no column refers to another array
    std::size_t ref_columns = 0;
};
// The row layouts of a raw mesh answer: mesh.vertices (3), mesh.hexes (8, all of mesh.vertices), mesh.sj (1),
// mesh.singular_edges (3, 2 of mesh.vertices), mesh.boundary_quads (4 of mesh.vertices), mesh.boundary_hexes (1 of
// mesh.hexes), connection_surfaces.vertices (3), connection_surfaces.quads (4 of connection_surfaces.vertices).
const std::vector<RowLayout>& mesh_answer_row_layouts();
BinaryArrays patch_arrays(const BinaryArrays& base, const BinaryArrays& full,
                          const std::vector<RowLayout>& layouts = {});

// Reading it back (tests, scripts): the header and every array as doubles (f32) or uint32 (u32, enum codes), by name;
// an enum array is also written into the header at its dotted name as the JSON array of its strings, so that the
// header has the JSON answer's members.
// Throws std::invalid_argument on a malformed answer (bad magic or version, sizes that do not add up).
struct DecodedAnswer {
    nlohmann::json header;
    std::vector<std::string> names;               // in order
    std::vector<std::vector<double>> f32;         // per array (empty for u32 arrays)
    std::vector<std::vector<std::uint32_t>> u32;  // per array (empty for f32 arrays; the codes of an enum array)
    const std::vector<double>& reals(const std::string& name) const;
    const std::vector<std::uint32_t>& ints(const std::string& name) const;
    bool has(const std::string& name) const;
};
// `previous`: the decoded answer a patch answer patches (required when an entry has "patch" or "rows"; the patched
// arrays are its arrays with the changes applied).
DecodedAnswer decode_binary_answer(const std::string& bytes, const DecodedAnswer* previous = nullptr);

// ------------------------------------------------------------------------------------------- implementation

void put_u32_le(std::string& out, std::uint32_t x);

// x as 4 little-endian bytes at `at` (compilers make this one store on a little-endian machine).
inline void store_u32_le(char* at, std::uint32_t x) {
    at[0] = static_cast<char>(x & 0xffu);
    at[1] = static_cast<char>((x >> 8) & 0xffu);
    at[2] = static_cast<char>((x >> 16) & 0xffu);
    at[3] = static_cast<char>((x >> 24) & 0xffu);
}

// Appends n bytes (zeros) to `out`; returns where they start.
char* grow(std::string& out, std::size_t n);

template <typename Cells>
void append_u32_cells(BinaryArrays& arrays, const std::string& name, const Cells& cells) {
    std::size_t count = 0;
    for (const auto& cell : cells) count += cell.size();
    char* at = grow(arrays.bytes, 4 * count);
    for (const auto& cell : cells)
        for (const int v : cell) store_u32_le(at, static_cast<std::uint32_t>(v)), at += 4;
    arrays.list.push_back({{"name", name}, {"type", "u32"}, {"count", count}});
}

}  // namespace mesohex::studio
