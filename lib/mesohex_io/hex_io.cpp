// Hex mesh formats: MEDIT .mesh, legacy VTK .vtk, VTK XML .vtu (ASCII), Gmsh .msh 4.1 (ASCII), Abaqus .inp (write),
// Exodus II .exo / .e (write, in exodus_io.cpp). All of them use the VTK hex vertex order (MEDIT, Gmsh, Abaqus C3D8
// and Exodus HEX8 number the hexahedron like VTK), so no permutation happens here.
// Readers parse the whole file as text, track line numbers, and throw mesohex::Error
// "path:line: message" on anything they do not understand.
#include "mesohex_io/hex_io.h"
#include "mesohex_io/exodus_io.h"
#include "mesohex_io/text_input.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>
#include <type_traits>
#include <utility>

#include <filesystem>

#include <fcntl.h>
#include <signal.h>

#include <unistd.h>

#include "mesohex/core/error.h"

namespace mesohex {
namespace {

// ---------------------------------------------------------------------------------------------------------------
// Small text utilities.

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

bool iequals(std::string_view a, std::string_view b) { return lower(a) == lower(b); }

// ".mesh", ".vtk", ...: lower-case, with the dot; "" when there is none.
std::string extension_of(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext.empty() ? ext : "." + ext;
}

[[noreturn]] void fail_at(const std::string& path, int line, const std::string& message) {
    throw Error(ErrorCode::InvalidInput, path + ":" + std::to_string(line) + ": " + message,
                {ElementRef::Kind::FileLine, line});
}

void append_double(std::string& out, double x) {
    char buf[32];
    const std::to_chars_result r = std::to_chars(buf, buf + sizeof buf, x);  // shortest exact representation
    out.append(buf, r.ptr);
}
void append_int(std::string& out, long x) {
    char buf[24];
    const std::to_chars_result r = std::to_chars(buf, buf + sizeof buf, x);
    out.append(buf, r.ptr);
}

// "x y z" with the shortest round-trip text of each coordinate.
void append_xyz(std::string& out, const Vec3& p) {
    append_double(out, p.x);
    out += ' ';
    append_double(out, p.y);
    out += ' ';
    append_double(out, p.z);
}

// Whitespace-separated tokens with line numbers. `comment` starts a comment running to the end of the line.
class Lexer {
public:
    Lexer(const std::string& path, std::string_view text, int first_line = 1, char comment = 0)
        : path_(path),
          text_(text),
          line_(first_line),
          token_line_(first_line),
          last_content_line_(first_line),
          comment_(comment) {}

    // Next token, or an empty view at the end of the text.
    std::string_view next() {
        skip_space();
        if (pos_ >= text_.size()) {
            token_line_ = last_content_line_;  // "end of file" is reported on the last line with content
            return {};
        }
        const std::size_t start = pos_;
        while (pos_ < text_.size() && !is_space(text_[pos_]) && text_[pos_] != comment_) ++pos_;
        token_line_ = line_;
        last_content_line_ = line_;
        return text_.substr(start, pos_ - start);
    }
    bool at_end() {
        skip_space();
        return pos_ >= text_.size();
    }
    std::string_view expect(const std::string& what) {
        const std::string_view t = next();
        if (t.empty()) fail("unexpected end of file, expected " + what);
        return t;
    }
    void expect_keyword(std::string_view keyword) {
        const std::string_view t = expect(std::string(keyword));
        if (!iequals(t, keyword)) fail("expected '" + std::string(keyword) + "', found '" + quote_excerpt(t) + "'");
    }
    long expect_int(const std::string& what) {
        const std::string_view t = expect(what);
        long value = 0;
        const std::from_chars_result r = std::from_chars(t.data(), t.data() + t.size(), value);
        if (r.ec != std::errc() || r.ptr != t.data() + t.size())
            fail("expected an integer (" + what + "), found '" + quote_excerpt(t) + "'");
        return value;
    }
    // A count of at most max_value items, each taking at least one byte of the rest of the text (a larger count is a
    // corrupt header, refused at its line). What a reader reserves for them is capped by reservable().
    long expect_count(const std::string& what, long max_value = 2000000000L) {
        const long n = expect_int(what);
        if (n < 0 || n > max_value) fail("invalid " + what + " " + std::to_string(n));
        if (static_cast<std::size_t>(n) > text_.size() - pos_)
            fail(what + " " + std::to_string(n) + " is more than the rest of the file can hold (truncated file?)");
        return n;
    }
    // How many of `n` items, each at least `min_bytes` bytes of text, the rest of the text can hold: what a reader
    // may reserve (memory stays a small multiple of the file size; a short file then fails where its data ends).
    std::size_t reservable(long n, std::size_t min_bytes) const {
        return std::min(static_cast<std::size_t>(std::max(n, 0L)),
                        (text_.size() - pos_) / std::max<std::size_t>(min_bytes, 1));
    }
    double expect_double(const std::string& what) {
        const std::string_view t = expect(what);
        double value = 0;
        const char* begin = t.data();
        if (!t.empty() && t[0] == '+') ++begin;  // from_chars does not accept a leading '+'
        const std::from_chars_result r = std::from_chars(begin, t.data() + t.size(), value);
        if (r.ec == std::errc::result_out_of_range)
            fail("number out of range (" + what + "): '" + quote_excerpt(t) + "'");
        if (r.ec != std::errc() || r.ptr != t.data() + t.size())
            fail("expected a number (" + what + "), found '" + quote_excerpt(t) + "'");
        if (!std::isfinite(value)) fail("non-finite " + what + " '" + quote_excerpt(t) + "'");
        return value;
    }
    // The rest of the current line (after the last token), without the line break; moves to the next line.
    std::string_view rest_of_line() {
        const std::size_t start = pos_;
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
        std::string_view s = text_.substr(start, pos_ - start);
        if (pos_ < text_.size()) {
            ++pos_;
            ++line_;
        }
        while (!s.empty() && (s.back() == '\r' || s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
        while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
        return s;
    }
    std::size_t position() const { return pos_; }
    int line() const { return token_line_; }
    [[noreturn]] void fail(const std::string& message) const { fail_at(path_, token_line_, message); }

private:
    static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }
    void skip_space() {
        while (pos_ < text_.size()) {
            const char c = text_[pos_];
            if (c == '\n') {
                ++line_;
                ++pos_;
            } else if (is_space(c)) {
                ++pos_;
            } else if (comment_ != 0 && c == comment_) {
                while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
            } else {
                break;
            }
        }
    }

    const std::string& path_;
    std::string_view text_;
    std::size_t pos_ = 0;
    int line_;
    int token_line_;
    int last_content_line_;
    char comment_;
};

// 0-based or 1-based vertex index read from a file, checked against the number of vertices.
int read_vertex_index(Lexer& lex, long base, long num_points, long cell, const char* cell_name) {
    const long raw = lex.expect_int("vertex index");
    if (raw < base || raw - base >= num_points)  // (raw - base only once raw >= base: no overflow at LONG_MIN)
        lex.fail(std::string(cell_name) + " " + std::to_string(cell + base) + ": vertex index " + std::to_string(raw) +
                 " out of range (" + std::to_string(base) + ".." + std::to_string(num_points - 1 + base) + ")");
    return static_cast<int>(raw - base);
}

void check_writable(const std::string& path, const HexMesh& mesh, const std::vector<double>& cell_scalars,
                    const std::vector<int>& partition) {
    const long n = static_cast<long>(mesh.points.size());
    for (std::size_t h = 0; h < mesh.hexes.size(); ++h)
        for (int v : mesh.hexes[h])
            if (v < 0 || v >= n)
                throw Error(ErrorCode::InvalidInput,
                            path + ": cannot write: hex " + std::to_string(h) + " refers to vertex " +
                                std::to_string(v) + " (there are " + std::to_string(n) + " vertices)",
                            {ElementRef::Kind::Hex, static_cast<int>(h)});
    if (!cell_scalars.empty() && cell_scalars.size() != mesh.hexes.size())
        throw Error(ErrorCode::InvalidInput, path + ": cannot write: " + std::to_string(cell_scalars.size()) +
                                                 " cell values for " + std::to_string(mesh.hexes.size()) + " hexes");
    if (!partition.empty() && partition.size() != mesh.hexes.size())
        throw Error(ErrorCode::InvalidInput, path + ": cannot write: " + std::to_string(partition.size()) +
                                                 " partition ids for " + std::to_string(mesh.hexes.size()) + " hexes");
    for (std::size_t h = 0; h < partition.size(); ++h)
        if (partition[h] < 0)
            throw Error(
                ErrorCode::InvalidInput,
                path + ": cannot write: hex " + std::to_string(h) + " has partition id " + std::to_string(partition[h]),
                {ElementRef::Kind::Hex, static_cast<int>(h)});
}

// Hex reference of MEDIT and partition cell data: part + 1 in MEDIT (0 = no partition), the part elsewhere.
int medit_reference(const std::vector<int>& partition, std::size_t h) {
    return partition.empty() ? 0 : partition[h] + 1;
}

// ---------------------------------------------------------------------------------------------------------------
// MEDIT .mesh

HexMesh read_medit(const std::string& path, std::string_view text) {
    Lexer lex(path, text, 1, '#');
    HexMesh mesh;
    bool have_version = false, have_vertices = false, have_hexes = false, have_end = false;
    while (!lex.at_end()) {
        const std::string key = lower(lex.next());
        const int key_line = lex.line();
        if (key == "meshversionformatted") {
            const long version = lex.expect_int("mesh version");
            if (version < 1 || version > 4) lex.fail("unsupported MeshVersionFormatted " + std::to_string(version));
            have_version = true;
        } else if (key == "meshversionunformatted") {
            lex.fail("binary MEDIT files are not supported (use ASCII, MeshVersionFormatted)");
        } else if (key == "dimension") {
            const long dim = lex.expect_int("dimension");
            if (dim != 3) lex.fail("only Dimension 3 is supported, found " + std::to_string(dim));
        } else if (key == "vertices") {
            if (have_vertices) lex.fail("second Vertices section");
            const long n = lex.expect_count("number of vertices");
            mesh.points.reserve(lex.reservable(n, 8));  // "x y z ref" takes 8 bytes at least
            for (long v = 0; v < n; ++v) {
                Vec3 p;
                p.x = lex.expect_double("x coordinate of vertex " + std::to_string(v + 1));
                p.y = lex.expect_double("y coordinate of vertex " + std::to_string(v + 1));
                p.z = lex.expect_double("z coordinate of vertex " + std::to_string(v + 1));
                lex.expect_int("reference of vertex " + std::to_string(v + 1));
                mesh.points.push_back(p);
            }
            have_vertices = true;
        } else if (key == "hexahedra") {
            if (!have_vertices) lex.fail("Hexahedra before Vertices");
            if (have_hexes) lex.fail("second Hexahedra section");
            const long n = lex.expect_count("number of hexahedra");
            mesh.hexes.reserve(lex.reservable(n, 18));  // 9 integers
            const long np = static_cast<long>(mesh.points.size());
            for (long h = 0; h < n; ++h) {
                std::array<int, 8> hex{};
                for (int lv = 0; lv < 8; ++lv)
                    hex[static_cast<std::size_t>(lv)] = read_vertex_index(lex, 1, np, h, "hexahedron");
                lex.expect_int("reference of hexahedron " + std::to_string(h + 1));
                mesh.hexes.push_back(hex);
            }
            have_hexes = true;
        } else if (key == "edges" || key == "triangles" || key == "quadrilaterals" || key == "corners" ||
                   key == "ridges" || key == "requiredvertices" || key == "requirededges" ||
                   key == "requiredtriangles" || key == "requiredquadrilaterals") {
            // Lower-dimensional entities (boundary patches, features): skipped.
            const int per = key == "edges" ? 3 : key == "triangles" ? 4 : key == "quadrilaterals" ? 5 : 1;
            const long n = lex.expect_count("number of " + key);
            for (long i = 0; i < n * per; ++i) lex.expect_int("entry of " + key);
        } else if (key == "tetrahedra" || key == "prisms" || key == "pyramids" || key == "hexahedra2" ||
                   key == "tetrahedra2") {
            const long n = lex.expect_count("number of " + key);
            if (n > 0)
                fail_at(path, key_line,
                        "the mesh contains " + quote_excerpt(key) + ": only hexahedral meshes are supported");
        } else if (key == "end") {
            have_end = true;
            break;
        } else {
            fail_at(path, key_line, "unknown MEDIT keyword '" + quote_excerpt(key) + "'");
        }
    }
    if (!have_version) fail_at(path, 1, "not a MEDIT file: MeshVersionFormatted missing");
    if (!have_vertices || !have_hexes)
        fail_at(path, lex.line(),
                std::string("truncated or incomplete MEDIT file: no ") + (have_vertices ? "Hexahedra" : "Vertices") +
                    " section");
    if (!have_end) fail_at(path, lex.line(), "truncated MEDIT file: 'End' missing");
    return mesh;
}

std::string write_medit(const HexMesh& mesh, const std::vector<int>& partition) {
    std::string out = "MeshVersionFormatted 2\nDimension 3\n\nVertices\n";
    append_int(out, static_cast<long>(mesh.points.size()));
    out += '\n';
    for (const Vec3& p : mesh.points) {
        append_xyz(out, p);
        out += " 0\n";
    }
    out += "\nHexahedra\n";
    append_int(out, static_cast<long>(mesh.hexes.size()));
    out += '\n';
    for (std::size_t h = 0; h < mesh.hexes.size(); ++h) {
        for (int v : mesh.hexes[h]) {
            append_int(out, v + 1);
            out += ' ';
        }
        append_int(out, medit_reference(partition, h));
        out += '\n';
    }
    out += "\nEnd\n";
    return out;
}

// ---------------------------------------------------------------------------------------------------------------
// Legacy VTK (.vtk), ASCII. Reads versions 2.0-4.2 (CELLS n size) and 5.1 (OFFSETS / CONNECTIVITY).

HexMesh read_vtk(const std::string& path, std::string_view text) {
    Lexer lex(path, text);
    const std::string_view header = lex.rest_of_line();
    if (lower(header).rfind("# vtk datafile version", 0) != 0)
        fail_at(path, 1, "not a legacy VTK file: first line must be '# vtk DataFile Version x.x'");
    lex.rest_of_line();  // title
    const std::string format = lower(lex.rest_of_line());
    if (format == "binary") fail_at(path, 3, "binary VTK files are not supported (write ASCII)");
    if (format != "ascii") fail_at(path, 3, "expected 'ASCII' on line 3");
    lex.expect_keyword("DATASET");
    const std::string_view type = lex.expect("dataset type");
    if (!iequals(type, "UNSTRUCTURED_GRID"))
        lex.fail("dataset type '" + quote_excerpt(type) + "' is not supported (only UNSTRUCTURED_GRID)");

    HexMesh mesh;
    bool have_points = false, have_cells = false;
    std::vector<long> offsets;
    std::vector<int> connectivity;
    while (true) {
        const std::string_view tok = lex.next();
        if (tok.empty()) {
            lex.fail(have_points
                         ? (have_cells ? "truncated VTK file: CELL_TYPES missing" : "truncated VTK file: CELLS missing")
                         : "truncated VTK file: POINTS missing");
        }
        const std::string key = lower(tok);
        if (key == "points") {
            if (have_points) lex.fail("second POINTS section");
            const long n = lex.expect_count("number of points");
            const std::string dtype = lower(lex.expect("point data type"));
            if (dtype != "float" && dtype != "double")
                lex.fail("unsupported point type '" + quote_excerpt(dtype) + "'");
            mesh.points.reserve(lex.reservable(n, 6));  // "x y z " takes 6 bytes at least
            for (long v = 0; v < n; ++v) {
                Vec3 p;
                for (int c = 0; c < 3; ++c) p[c] = lex.expect_double("coordinate of point " + std::to_string(v));
                mesh.points.push_back(p);
            }
            have_points = true;
        } else if (key == "metadata") {
            // VTK 5.x writes METADATA blocks ended by a blank line: skip them.
            lex.rest_of_line();
            while (true) {
                const std::size_t before = lex.position();
                const std::string_view line = lex.rest_of_line();
                if (line.empty() || lex.position() == before) break;
            }
        } else if (key == "cells") {
            if (!have_points) lex.fail("CELLS before POINTS");
            if (have_cells) lex.fail("second CELLS section");
            const long a = lex.expect_count("number of cells");
            const long b = lex.expect_count("cell list size");
            const long np = static_cast<long>(mesh.points.size());
            // Peek: VTK 5.1 has "OFFSETS type" next.
            Lexer peek = lex;
            const std::string_view next = peek.next();
            if (iequals(next, "OFFSETS")) {
                lex.next();
                lex.expect("offsets type");
                offsets.reserve(lex.reservable(a, 2));
                for (long i = 0; i < a; ++i) {
                    // Each cell's vertices are connectivity[offsets[c], offsets[c + 1]): offsets start at 0, never
                    // decrease and stay within the b connectivity entries (else a cell would index past them).
                    const long o = lex.expect_int("offset");
                    if ((i == 0 && o != 0) || (i > 0 && o < offsets.back()) || o > b)
                        lex.fail("offset " + std::to_string(o) + " (entry " + std::to_string(i) +
                                 "): OFFSETS must start at 0, never decrease and stay within the connectivity size " +
                                 std::to_string(b));
                    offsets.push_back(o);
                }
                lex.expect_keyword("CONNECTIVITY");
                lex.expect("connectivity type");
                connectivity.reserve(lex.reservable(b, 2));
                for (long i = 0; i < b; ++i) {
                    const long cell =
                        static_cast<long>(std::upper_bound(offsets.begin(), offsets.end(), i) - offsets.begin()) - 1;
                    connectivity.push_back(read_vertex_index(lex, 0, np, cell, "cell"));
                }
                if (a < 1 || offsets.front() != 0 || offsets.back() != b)
                    lex.fail("inconsistent OFFSETS / CONNECTIVITY");
            } else {
                offsets.assign(1, 0);
                for (long c = 0; c < a; ++c) {
                    const long k = lex.expect_count("number of vertices of cell " + std::to_string(c), 1000);
                    if (k != 8)
                        lex.fail("cell " + std::to_string(c) + " has " + std::to_string(k) +
                                 " vertices, not a hexahedron (8)");
                    for (long i = 0; i < k; ++i) connectivity.push_back(read_vertex_index(lex, 0, np, c, "cell"));
                    offsets.push_back(static_cast<long>(connectivity.size()));
                }
                if (b != a * 9)
                    lex.fail("CELLS size " + std::to_string(b) + " does not match " + std::to_string(a) +
                             " hexahedra (expected " + std::to_string(a * 9) + ")");
            }
            const std::size_t cells = offsets.size() - 1;
            mesh.hexes.resize(cells);
            for (std::size_t c = 0; c < cells; ++c) {
                if (offsets[c + 1] - offsets[c] != 8)
                    lex.fail("cell " + std::to_string(c) + " has " + std::to_string(offsets[c + 1] - offsets[c]) +
                             " vertices, not a hexahedron (8)");
                for (std::size_t lv = 0; lv < 8; ++lv)
                    mesh.hexes[c][lv] = connectivity[static_cast<std::size_t>(offsets[c]) + lv];
            }
            have_cells = true;
        } else if (key == "cell_types") {
            if (!have_cells) lex.fail("CELL_TYPES before CELLS");
            const long n = lex.expect_count("number of cell types");
            if (n != static_cast<long>(mesh.hexes.size()))
                lex.fail("CELL_TYPES count " + std::to_string(n) + " differs from the number of cells " +
                         std::to_string(mesh.hexes.size()));
            for (long c = 0; c < n; ++c) {
                const long t = lex.expect_int("cell type");
                if (t != 12)
                    lex.fail("cell " + std::to_string(c) + " has VTK type " + std::to_string(t) +
                             ", not a hexahedron (12)");
            }
            return mesh;  // point and cell data that follow are not needed
        } else {
            lex.fail("unexpected keyword '" + quote_excerpt(tok) + "' in VTK file");
        }
    }
}

std::string write_vtk(const HexMesh& mesh, const std::vector<double>& cell_scalars, const std::vector<int>& partition) {
    std::string out = "# vtk DataFile Version 2.0\nmesohex hex mesh\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS ";
    append_int(out, static_cast<long>(mesh.points.size()));
    out += " double\n";
    for (const Vec3& p : mesh.points) {
        append_xyz(out, p);
        out += '\n';
    }
    out += "CELLS ";
    append_int(out, static_cast<long>(mesh.hexes.size()));
    out += ' ';
    append_int(out, static_cast<long>(mesh.hexes.size()) * 9);
    out += '\n';
    for (const std::array<int, 8>& hex : mesh.hexes) {
        out += '8';
        for (int v : hex) {
            out += ' ';
            append_int(out, v);
        }
        out += '\n';
    }
    out += "CELL_TYPES ";
    append_int(out, static_cast<long>(mesh.hexes.size()));
    out += '\n';
    for (std::size_t h = 0; h < mesh.hexes.size(); ++h) out += "12\n";
    if (!cell_scalars.empty() || !partition.empty()) {
        out += "CELL_DATA ";
        append_int(out, static_cast<long>(mesh.hexes.size()));
        out += '\n';
    }
    if (!cell_scalars.empty()) {
        out += "SCALARS scaled_jacobian double 1\nLOOKUP_TABLE default\n";
        for (double s : cell_scalars) {
            append_double(out, s);
            out += '\n';
        }
    }
    if (!partition.empty()) {
        out += "SCALARS partition int 1\nLOOKUP_TABLE default\n";
        for (int p : partition) {
            append_int(out, p);
            out += '\n';
        }
    }
    return out;
}

// ---------------------------------------------------------------------------------------------------------------
// VTK XML unstructured grid (.vtu), ASCII data arrays only.

struct XmlTag {
    std::string name;  // without '/'
    bool closing = false, self_closing = false;
    std::vector<std::pair<std::string, std::string>> attributes;
    std::size_t end = 0;  // position after '>'
    int line = 1;
    std::string attribute(const std::string& key) const {
        for (const auto& [k, v] : attributes)
            if (k == key) return v;
        return "";
    }
};

// The tags of an XML text in order, with their line numbers; comments and declarations are skipped.
class XmlScanner {
public:
    XmlScanner(const std::string& path, std::string_view text) : path_(path), text_(text) {}

    // Next tag at or after the current position; false at the end of the text.
    bool next(XmlTag& tag) {
        while (true) {
            const std::size_t lt = text_.find('<', pos_);
            if (lt == std::string_view::npos) return false;
            tag = XmlTag{};
            tag.line = line_at(lt);
            if (text_.compare(lt, 4, "<!--") == 0 || text_.compare(lt, 2, "<?") == 0) {
                const std::string_view close = text_.compare(lt, 4, "<!--") == 0 ? "-->" : "?>";
                const std::size_t e = text_.find(close, lt);
                if (e == std::string_view::npos) fail_at(path_, tag.line, "unterminated XML comment or declaration");
                pos_ = e + close.size();
                continue;
            }
            const std::size_t gt = text_.find('>', lt);
            if (gt == std::string_view::npos) fail_at(path_, tag.line, "truncated XML tag");
            parse_tag_body(text_.substr(lt + 1, gt - lt - 1), tag);
            tag.end = gt + 1;
            pos_ = gt + 1;
            return true;
        }
    }
    // Line of position p (positions asked for never decrease).
    int line_at(std::size_t p) {
        line_ += static_cast<int>(std::count(text_.begin() + static_cast<std::ptrdiff_t>(counted_),
                                             text_.begin() + static_cast<std::ptrdiff_t>(p), '\n'));
        counted_ = p;
        return line_;
    }
    // Line of the last character that is not white space.
    int last_line() {
        std::size_t end = text_.size();
        while (end > 0 && std::isspace(static_cast<unsigned char>(text_[end - 1]))) --end;
        return line_at(std::max(end, counted_));
    }
    void skip_to(std::size_t p) { pos_ = p; }
    std::string_view text() const { return text_; }

private:
    // "name attr='v' ..." (between '<' and '>') into tag.
    void parse_tag_body(std::string_view body, XmlTag& tag) const {
        if (!body.empty() && body.front() == '/') {
            tag.closing = true;
            body.remove_prefix(1);
        }
        if (!body.empty() && body.back() == '/') {
            tag.self_closing = true;
            body.remove_suffix(1);
        }
        std::size_t i = 0;
        while (i < body.size() && !std::isspace(static_cast<unsigned char>(body[i]))) ++i;
        tag.name = std::string(body.substr(0, i));
        while (true) {
            while (i < body.size() && std::isspace(static_cast<unsigned char>(body[i]))) ++i;
            if (i >= body.size()) break;
            const std::size_t eq = body.find('=', i);
            if (eq == std::string_view::npos)
                fail_at(path_, tag.line, "malformed attribute in <" + quote_excerpt(tag.name) + ">");
            std::string key(body.substr(i, eq - i));
            while (!key.empty() && std::isspace(static_cast<unsigned char>(key.back()))) key.pop_back();
            std::size_t q = eq + 1;
            while (q < body.size() && std::isspace(static_cast<unsigned char>(body[q]))) ++q;
            if (q >= body.size() || (body[q] != '"' && body[q] != '\''))
                fail_at(path_, tag.line,
                        "malformed attribute '" + quote_excerpt(key) + "' in <" + quote_excerpt(tag.name) + ">");
            const std::size_t qe = body.find(body[q], q + 1);
            if (qe == std::string_view::npos)
                fail_at(path_, tag.line, "unterminated attribute '" + quote_excerpt(key) + "'");
            tag.attributes.emplace_back(key, std::string(body.substr(q + 1, qe - q - 1)));
            i = qe + 1;
        }
    }

    const std::string& path_;
    std::string_view text_;
    std::size_t pos_ = 0;
    int line_ = 1;
    std::size_t counted_ = 0;  // line_ is the line of text_[counted_]
};

// The arrays of a VTU <Piece> that make the hex mesh.
struct VtuArrays {
    long num_points = -1, num_cells = -1;  // from <Piece>; -1 before it
    bool have_points = false;
    std::vector<long> connectivity, offsets, types;
};

// A non-negative integer attribute of <Piece>.
long vtu_piece_count(const std::string& path, const XmlTag& tag, const char* key) {
    const std::string s = tag.attribute(key);
    long n = -1;
    const std::from_chars_result r = std::from_chars(s.data(), s.data() + s.size(), n);
    if (s.empty() || r.ec != std::errc() || r.ptr != s.data() + s.size() || n < 0)
        fail_at(path, tag.line, std::string("missing or invalid ") + key + " in <Piece>");
    return n;
}

// Reads the ASCII values of <DataArray> `tag` (child of `parent`) when it is one the mesh needs; moves past it.
void read_vtu_data_array(const std::string& path, XmlScanner& xml, const XmlTag& tag, const std::string& parent,
                         VtuArrays& a, HexMesh& mesh) {
    const std::string name = tag.attribute("Name");
    const std::string format = tag.attribute("format");
    const bool wanted =
        parent == "Points" || (parent == "Cells" && (name == "connectivity" || name == "offsets" || name == "types"));
    if (wanted && format != "ascii")
        fail_at(path, tag.line, "DataArray format '" + quote_excerpt(format) + "' is not supported (only ascii)");
    const std::size_t close = xml.text().find("</DataArray>", tag.end);
    if (close == std::string_view::npos) fail_at(path, tag.line, "truncated file: </DataArray> missing");
    if (wanted) {
        Lexer lex(path, xml.text().substr(tag.end, close - tag.end), tag.line);
        if (parent == "Points") {
            if (a.num_points < 0) fail_at(path, tag.line, "<Points> outside <Piece>");
            if (tag.attribute("NumberOfComponents") != "3")
                fail_at(path, tag.line, "points must have NumberOfComponents=\"3\"");
            mesh.points.resize(static_cast<std::size_t>(a.num_points));
            for (long v = 0; v < a.num_points; ++v)
                for (int c = 0; c < 3; ++c)
                    mesh.points[static_cast<std::size_t>(v)][c] =
                        lex.expect_double("coordinate of point " + std::to_string(v));
            a.have_points = true;
        } else {
            std::vector<long>& dst = name == "connectivity" ? a.connectivity : name == "offsets" ? a.offsets : a.types;
            while (!lex.at_end()) dst.push_back(lex.expect_int(name + " entry"));
        }
        if (!lex.at_end()) lex.fail("more values than declared in " + quote_excerpt(name.empty() ? parent : name));
    }
    xml.skip_to(close + std::strlen("</DataArray>"));
}

// The hexes from the cell arrays (every cell a VTK hexahedron, type 12, of 8 vertices in range); errors at `line`.
void assemble_vtu_hexes(const std::string& path, int line, const VtuArrays& a, HexMesh& mesh) {
    if (static_cast<long>(a.offsets.size()) != a.num_cells || static_cast<long>(a.types.size()) != a.num_cells)
        fail_at(path, line, "VTU cell arrays do not match NumberOfCells=" + std::to_string(a.num_cells));
    mesh.hexes.resize(static_cast<std::size_t>(a.num_cells));
    long begin = 0;
    for (long c = 0; c < a.num_cells; ++c) {
        const std::size_t cu = static_cast<std::size_t>(c);
        if (a.types[cu] != 12)
            fail_at(path, line,
                    "cell " + std::to_string(c) + " has VTK type " + std::to_string(a.types[cu]) +
                        ", not a hexahedron (12)");
        if (a.offsets[cu] < begin || a.offsets[cu] - begin != 8 ||
            a.offsets[cu] > static_cast<long>(a.connectivity.size()))
            fail_at(path, line, "cell " + std::to_string(c) + " does not have 8 vertices in connectivity/offsets");
        for (std::size_t lv = 0; lv < 8; ++lv) {
            const long v = a.connectivity[static_cast<std::size_t>(begin) + lv];
            if (v < 0 || v >= a.num_points)
                fail_at(path, line,
                        "cell " + std::to_string(c) + ": vertex index " + std::to_string(v) + " out of range");
            mesh.hexes[cu][lv] = static_cast<int>(v);
        }
        begin = a.offsets[cu];
    }
    if (begin != static_cast<long>(a.connectivity.size()))
        fail_at(path, line, "connectivity has more entries than the offsets use");
}

HexMesh read_vtu(const std::string& path, std::string_view text) {
    XmlScanner xml(path, text);
    XmlTag tag;
    if (!xml.next(tag) || tag.name != "VTKFile") fail_at(path, tag.line, "not a VTK XML file: <VTKFile> expected");
    if (tag.attribute("type") != "UnstructuredGrid")
        fail_at(path, tag.line,
                "VTK XML type '" + quote_excerpt(tag.attribute("type")) + "' is not supported (only UnstructuredGrid)");
    if (!tag.attribute("compressor").empty()) fail_at(path, tag.line, "compressed VTU files are not supported");

    VtuArrays arrays;
    std::vector<std::string> stack;
    HexMesh mesh;
    bool done = false;
    while (!done && xml.next(tag)) {
        if (tag.closing) {
            if (stack.empty() || stack.back() != tag.name)
                fail_at(path, tag.line, "unexpected </" + quote_excerpt(tag.name) + ">");
            stack.pop_back();
            if (tag.name == "Piece") done = true;
            continue;
        }
        if (tag.name == "Piece") {
            if (arrays.num_points >= 0) fail_at(path, tag.line, "only one <Piece> is supported");
            arrays.num_points = vtu_piece_count(path, tag, "NumberOfPoints");
            arrays.num_cells = vtu_piece_count(path, tag, "NumberOfCells");
            if (static_cast<std::size_t>(arrays.num_points) > text.size() / 6 ||
                static_cast<std::size_t>(arrays.num_cells) > text.size() / 4)
                fail_at(path, tag.line, "NumberOfPoints / NumberOfCells larger than the file can hold");
        }
        if (tag.name == "DataArray" && !tag.self_closing) {
            read_vtu_data_array(path, xml, tag, stack.empty() ? "" : stack.back(), arrays, mesh);
            continue;
        }
        if (!tag.self_closing) stack.push_back(tag.name);
    }
    if (!done) fail_at(path, xml.last_line(), "truncated VTU file: </Piece> missing");
    if (!arrays.have_points) fail_at(path, xml.last_line(), "VTU file has no <Points>");
    assemble_vtu_hexes(path, xml.last_line(), arrays, mesh);
    return mesh;
}

std::string write_vtu(const HexMesh& mesh, const std::vector<double>& cell_scalars, const std::vector<int>& partition) {
    std::string out =
        "<?xml version=\"1.0\"?>\n"
        "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        "  <UnstructuredGrid>\n"
        "    <Piece NumberOfPoints=\"";
    append_int(out, static_cast<long>(mesh.points.size()));
    out += "\" NumberOfCells=\"";
    append_int(out, static_cast<long>(mesh.hexes.size()));
    out += "\">\n      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const Vec3& p : mesh.points) {
        append_xyz(out, p);
        out += '\n';
    }
    out +=
        "        </DataArray>\n      </Points>\n      <Cells>\n"
        "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (const std::array<int, 8>& hex : mesh.hexes) {
        for (std::size_t lv = 0; lv < 8; ++lv) {
            append_int(out, hex[lv]);
            out += lv < 7 ? ' ' : '\n';
        }
    }
    out += "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (std::size_t h = 0; h < mesh.hexes.size(); ++h) {
        append_int(out, static_cast<long>(h + 1) * 8);
        out += '\n';
    }
    out += "        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (std::size_t h = 0; h < mesh.hexes.size(); ++h) out += "12\n";
    out += "        </DataArray>\n      </Cells>\n";
    if (!cell_scalars.empty() || !partition.empty()) {
        out += cell_scalars.empty() ? "      <CellData Scalars=\"partition\">\n"
                                    : "      <CellData Scalars=\"scaled_jacobian\">\n";
        if (!cell_scalars.empty()) {
            out += "        <DataArray type=\"Float64\" Name=\"scaled_jacobian\" format=\"ascii\">\n";
            for (double s : cell_scalars) {
                append_double(out, s);
                out += '\n';
            }
            out += "        </DataArray>\n";
        }
        if (!partition.empty()) {
            out += "        <DataArray type=\"Int32\" Name=\"partition\" format=\"ascii\">\n";
            for (int p : partition) {
                append_int(out, p);
                out += '\n';
            }
            out += "        </DataArray>\n";
        }
        out += "      </CellData>\n";
    }
    out += "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
    return out;
}

// ---------------------------------------------------------------------------------------------------------------
// Gmsh .msh 4.1 ASCII.

// Nodes per element of the Gmsh element types we may meet (0 = unknown).
int gmsh_nodes_per_element(long type) {
    switch (type) {
        case 1: return 2;    // line
        case 2: return 3;    // triangle
        case 3: return 4;    // quadrangle
        case 4: return 4;    // tetrahedron
        case 5: return 8;    // hexahedron
        case 6: return 6;    // prism
        case 7: return 5;    // pyramid
        case 8: return 3;    // line3
        case 9: return 6;    // triangle6
        case 10: return 9;   // quad9
        case 11: return 10;  // tet10
        case 12: return 27;  // hex27
        case 13: return 18;  // prism18
        case 14: return 14;  // pyramid14
        case 15: return 1;   // point
        case 16: return 8;   // quad8
        case 17: return 20;  // hex20
        case 18: return 15;  // prism15
        case 19: return 13;  // pyramid13
        default: return 0;
    }
}

void skip_gmsh_section(Lexer& lex, const std::string& name) {
    const std::string end = "$end" + lower(name.substr(1));
    while (true) {
        const std::string_view t = lex.next();
        if (t.empty()) lex.fail("truncated file: " + std::string("$End") + quote_excerpt(name.substr(1)) + " missing");
        if (lower(t) == end) return;
    }
}

HexMesh read_msh(const std::string& path, std::string_view text) {
    Lexer lex(path, text);
    HexMesh mesh;
    std::vector<std::pair<long, int>> node_index;  // (tag, index), sorted by tag after $Nodes
    bool have_format = false, have_nodes = false, have_elements = false;
    while (!lex.at_end()) {
        const std::string section(lex.next());
        const std::string key = lower(section);
        if (key == "$meshformat") {
            const std::string_view version = lex.expect("format version");
            if (version != "4.1")
                lex.fail("Gmsh format version " + quote_excerpt(version) + " is not supported (only 4.1)");
            const long file_type = lex.expect_int("file type");
            if (file_type != 0) lex.fail("binary Gmsh files are not supported (only ASCII)");
            lex.expect_int("data size");
            lex.expect_keyword("$EndMeshFormat");
            have_format = true;
        } else if (!have_format) {
            lex.fail("not a Gmsh file: $MeshFormat expected first, found '" + quote_excerpt(section) + "'");
        } else if (key == "$nodes") {
            const long blocks = lex.expect_count("number of node blocks");
            const long total = lex.expect_count("number of nodes");
            lex.expect_int("min node tag");
            lex.expect_int("max node tag");
            mesh.points.reserve(lex.reservable(total, 8));  // "tag x y z" takes 8 bytes at least
            node_index.reserve(lex.reservable(total, 8));
            for (long b = 0; b < blocks; ++b) {
                const long dim = lex.expect_int("entity dimension");
                lex.expect_int("entity tag");
                const long parametric = lex.expect_int("parametric flag");
                const long n = lex.expect_count("number of nodes in block");
                if (static_cast<long>(mesh.points.size()) + n > total)
                    lex.fail("more nodes than declared (" + std::to_string(total) + ")");
                const std::size_t first = mesh.points.size();
                for (long i = 0; i < n; ++i) {
                    const long tag = lex.expect_int("node tag");
                    node_index.emplace_back(tag, static_cast<int>(first + static_cast<std::size_t>(i)));
                }
                for (long i = 0; i < n; ++i) {
                    Vec3 p;
                    for (int c = 0; c < 3; ++c) p[c] = lex.expect_double("node coordinate");
                    if (parametric != 0)
                        for (long k = 0; k < dim && k < 3; ++k) lex.expect_double("node parametric coordinate");
                    mesh.points.push_back(p);
                }
            }
            if (static_cast<long>(mesh.points.size()) != total)
                lex.fail("$Nodes declares " + std::to_string(total) + " nodes but has " +
                         std::to_string(mesh.points.size()));
            lex.expect_keyword("$EndNodes");
            std::sort(node_index.begin(), node_index.end());
            for (std::size_t i = 1; i < node_index.size(); ++i)
                if (node_index[i].first == node_index[i - 1].first)
                    lex.fail("duplicate node tag " + std::to_string(node_index[i].first));
            have_nodes = true;
        } else if (key == "$elements") {
            if (!have_nodes) lex.fail("$Elements before $Nodes");
            const long blocks = lex.expect_count("number of element blocks");
            const long total = lex.expect_count("number of elements");
            lex.expect_int("min element tag");
            lex.expect_int("max element tag");
            long seen = 0;
            for (long b = 0; b < blocks; ++b) {
                const long dim = lex.expect_int("entity dimension");
                lex.expect_int("entity tag");
                const long type = lex.expect_int("element type");
                const long n = lex.expect_count("number of elements in block");
                const int per = gmsh_nodes_per_element(type);
                if (per == 0) lex.fail("unknown Gmsh element type " + std::to_string(type));
                if (dim == 3 && type != 5)
                    lex.fail("element type " + std::to_string(type) +
                             " is a volume element but not a hexahedron (type 5)");
                for (long i = 0; i < n; ++i) {
                    const long tag = lex.expect_int("element tag");
                    std::array<int, 8> hex{};
                    for (int k = 0; k < per; ++k) {
                        const long node = lex.expect_int("node tag");
                        const auto it =
                            std::lower_bound(node_index.begin(), node_index.end(), std::make_pair(node, -1));
                        if (it == node_index.end() || it->first != node)
                            lex.fail("element " + std::to_string(tag) + " refers to unknown node " +
                                     std::to_string(node));
                        if (type == 5) hex[static_cast<std::size_t>(k)] = it->second;
                    }
                    if (type == 5) mesh.hexes.push_back(hex);  // lower-dimensional elements (boundary) are skipped
                }
                seen += n;
            }
            if (seen != total)
                lex.fail("$Elements declares " + std::to_string(total) + " elements but has " + std::to_string(seen));
            lex.expect_keyword("$EndElements");
            have_elements = true;
        } else if (!section.empty() && section[0] == '$') {
            skip_gmsh_section(lex, section);  // $Entities, $PhysicalNames, $ElementData, ...
        } else {
            lex.fail("unexpected '" + quote_excerpt(section) + "' outside a section");
        }
    }
    if (!have_format) fail_at(path, 1, "not a Gmsh file: $MeshFormat missing");
    if (!have_nodes || !have_elements)
        fail_at(path, lex.line(),
                std::string("truncated Gmsh file: ") + (have_nodes ? "$Elements" : "$Nodes") + " missing");
    return mesh;
}

// One $ElementData section (a single time step 0) named `name`, one value per hex.
template <class T>
void append_msh_element_data(std::string& out, const char* name, const std::vector<T>& values) {
    out += "$ElementData\n1\n\"";
    out += name;
    out += "\"\n1\n0\n3\n0\n1\n";
    append_int(out, static_cast<long>(values.size()));
    out += '\n';
    for (std::size_t h = 0; h < values.size(); ++h) {
        append_int(out, static_cast<long>(h) + 1);
        out += ' ';
        if constexpr (std::is_integral_v<T>)
            append_int(out, values[h]);
        else
            append_double(out, values[h]);
        out += '\n';
    }
    out += "$EndElementData\n";
}

std::string write_msh(const HexMesh& mesh, const std::vector<double>& cell_scalars, const std::vector<int>& partition) {
    const long np = static_cast<long>(mesh.points.size()), nh = static_cast<long>(mesh.hexes.size());
    std::string out = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n";
    auto line4 = [&](long a, long b, long c, long d) {
        append_int(out, a);
        out += ' ';
        append_int(out, b);
        out += ' ';
        append_int(out, c);
        out += ' ';
        append_int(out, d);
        out += '\n';
    };
    line4(np > 0 ? 1 : 0, np, np > 0 ? 1 : 0, np);
    if (np > 0) {
        line4(3, 1, 0, np);
        for (long v = 1; v <= np; ++v) {
            append_int(out, v);
            out += '\n';
        }
        for (const Vec3& p : mesh.points) {
            append_xyz(out, p);
            out += '\n';
        }
    }
    out += "$EndNodes\n$Elements\n";
    line4(nh > 0 ? 1 : 0, nh, nh > 0 ? 1 : 0, nh);
    if (nh > 0) {
        line4(3, 1, 5, nh);
        for (long h = 0; h < nh; ++h) {
            append_int(out, h + 1);
            for (int v : mesh.hexes[static_cast<std::size_t>(h)]) {
                out += ' ';
                append_int(out, v + 1);
            }
            out += '\n';
        }
    }
    out += "$EndElements\n";
    if (!cell_scalars.empty()) append_msh_element_data(out, "scaled_jacobian", cell_scalars);
    if (!partition.empty()) append_msh_element_data(out, "partition", partition);
    return out;
}

// ---------------------------------------------------------------------------------------------------------------
// Abaqus .inp (write only): C3D8 elements, node order as VTK.

std::string write_inp(const HexMesh& mesh, const std::vector<int>& partition) {
    std::string out = "*HEADING\nmesohex hex mesh\n*NODE\n";
    for (std::size_t v = 0; v < mesh.points.size(); ++v) {
        append_int(out, static_cast<long>(v) + 1);
        for (int c = 0; c < 3; ++c) {
            out += ", ";
            append_double(out, mesh.points[v][c]);
        }
        out += '\n';
    }
    out += "*ELEMENT, TYPE=C3D8, ELSET=EALL\n";
    for (std::size_t h = 0; h < mesh.hexes.size(); ++h) {
        append_int(out, static_cast<long>(h) + 1);
        for (int v : mesh.hexes[h]) {
            out += ", ";
            append_int(out, v + 1);
        }
        out += '\n';
    }
    // One element set PART_<p> per part (ids 16 to a line, as Abaqus asks).
    const int parts = partition.empty() ? 0 : *std::max_element(partition.begin(), partition.end()) + 1;
    for (int p = 0; p < parts; ++p) {
        out += "*ELSET, ELSET=PART_";
        append_int(out, p);
        int on_line = 0;
        for (std::size_t h = 0; h < partition.size(); ++h) {
            if (partition[h] != p) continue;
            out += on_line == 0 ? "\n" : ", ";
            append_int(out, static_cast<long>(h) + 1);
            on_line = (on_line + 1) % 16;
        }
        out += '\n';
    }
    return out;
}

}  // namespace

namespace {

bool is_readable_hex_extension(const std::string& ext) {
    return ext == ".mesh" || ext == ".vtk" || ext == ".vtu" || ext == ".msh";
}

// `text` in the format of extension `ext` (one of is_readable_hex_extension), named `name` in messages.
HexMesh parse_hex_mesh(const std::string& name, const std::string& ext, std::string_view text) {
    if (is_blank_content(text)) fail_empty_file(name, "expected a hex mesh");
    if (ext == ".mesh") return read_medit(name, text);
    if (ext == ".vtk") return read_vtk(name, text);
    if (ext == ".vtu") return read_vtu(name, text);
    return read_msh(name, text);
}

}  // namespace

HexMesh read_hex_mesh(const std::string& path) {
    const std::string ext = extension_of(path);
    if (!is_readable_hex_extension(ext)) {
        throw Error(ErrorCode::UnsupportedConfiguration,
                    path + ": unknown hex mesh extension '" + ext + "' (readable: .mesh .vtk .vtu .msh)");
    }
    return parse_hex_mesh(path, ext, read_whole_file(path));
}

HexMesh read_hex_mesh_text(std::string_view text, std::string_view format, std::string_view name) {
    const std::string display(name);
    const std::string ext = "." + lower(format);
    if (!is_readable_hex_extension(ext)) {
        throw Error(ErrorCode::UnsupportedConfiguration,
                    display + ": unknown hex mesh format '" + quote_excerpt(format) + "' (readable: mesh vtk vtu msh)");
    }
    return parse_hex_mesh(display, ext, text);
}

void write_hex_mesh(const std::string& path, const HexMesh& mesh, const std::vector<double>& cell_scalars,
                    const std::vector<int>& partition) {
    const std::string ext = extension_of(path);
    if (ext != ".mesh" && ext != ".vtk" && ext != ".vtu" && ext != ".msh" && ext != ".inp" && ext != ".exo" &&
        ext != ".e") {
        throw Error(ErrorCode::UnsupportedConfiguration,
                    path + ": unknown hex mesh extension '" + ext + "' (writable: .mesh .vtk .vtu .msh .inp .exo .e)");
    }
    check_writable(path, mesh, cell_scalars, partition);
    if (ext == ".mesh")
        write_file_atomically(path, write_medit(mesh, partition));
    else if (ext == ".vtk")
        write_file_atomically(path, write_vtk(mesh, cell_scalars, partition));
    else if (ext == ".vtu")
        write_file_atomically(path, write_vtu(mesh, cell_scalars, partition));
    else if (ext == ".msh")
        write_file_atomically(path, write_msh(mesh, cell_scalars, partition));
    else if (ext == ".inp")
        write_file_atomically(path, write_inp(mesh, partition));
    else
        write_exodus(path, mesh, cell_scalars, partition);
}

namespace {

// True for "<name>.tmp.<pid>.<n>" (pid and n decimal) and then sets `pid`.
bool is_our_temporary(const std::string& entry, const std::string& name, long& pid) {
    const std::string prefix = name + ".tmp.";
    if (entry.size() <= prefix.size() || entry.compare(0, prefix.size(), prefix) != 0) return false;
    const std::string_view rest = std::string_view(entry).substr(prefix.size());
    const std::size_t dot = rest.find('.');
    if (dot == std::string_view::npos || dot == 0 || dot + 1 >= rest.size()) return false;
    const auto all_digits = [](std::string_view s) {
        return !s.empty() && s.size() <= 18 &&
               std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
    };
    if (!all_digits(rest.substr(0, dot)) || !all_digits(rest.substr(dot + 1))) return false;
    pid = std::stol(std::string(rest.substr(0, dot)));
    return pid > 0;
}

}  // namespace

int remove_stale_temporaries(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path target(path);
    const std::string name = target.filename().string();
    if (name.empty()) return 0;
    const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    int removed = 0;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string entry = it->path().filename().string();
        long pid = 0;
        if (!is_our_temporary(entry, name, pid) || pid == static_cast<long>(::getpid())) continue;
        // kill(pid, 0) fails with ESRCH only when no such process exists: a live writer's file is left alone.
        if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
        if (fs::is_regular_file(it->symlink_status(ec)) && ::unlink(it->path().c_str()) == 0) ++removed;
    }
    return removed;
}

namespace {

// Creates a new empty file with a unique name beside `path` (same file system, so rename is atomic) and returns its
// name and open descriptor. O_EXCL guards against collisions and mode 0666 lets the umask decide the permissions as
// for any new file.
std::pair<std::string, int> create_temporary_beside(const std::string& path) {
    remove_stale_temporaries(path);  // what a run killed while writing the same target left
    static std::atomic<unsigned> counter{0};
    std::string tmp;
    int fd = -1;
    for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
        tmp = path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter.fetch_add(1));
        fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 && errno != EEXIST) break;
    }
    if (fd < 0)
        throw Error(ErrorCode::IoError, path + ": cannot create a temporary file beside it: " + std::strerror(errno));
    return {tmp, fd};
}

void rename_into_place(const std::string& tmp, const std::string& path) {
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const std::string reason = std::strerror(errno);
        ::unlink(tmp.c_str());
        throw Error(ErrorCode::IoError, path + ": cannot rename the temporary file into place: " + reason);
    }
}

}  // namespace

void write_atomically_via(const std::string& path, const std::function<void(const std::string& temporary)>& write_to) {
    const auto [tmp, fd] = create_temporary_beside(path);
    ::close(fd);
    try {
        write_to(tmp);
    } catch (...) {
        ::unlink(tmp.c_str());
        throw;
    }
    rename_into_place(tmp, path);
}

void write_file_atomically(const std::string& path, const std::string& text) {
    const auto [tmp, fd] = create_temporary_beside(path);
    std::size_t written = 0;
    while (written < text.size()) {
        const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
        if (n < 0) {
            if (errno == EINTR) continue;
            const std::string reason = std::strerror(errno);
            ::close(fd);
            ::unlink(tmp.c_str());
            throw Error(ErrorCode::IoError, path + ": write failed: " + reason);
        }
        written += static_cast<std::size_t>(n);
    }
    if (::close(fd) != 0) {
        const std::string reason = std::strerror(errno);
        ::unlink(tmp.c_str());
        throw Error(ErrorCode::IoError, path + ": write failed: " + reason);
    }
    rename_into_place(tmp, path);
}

}  // namespace mesohex
