// Triangle surface IO: OFF, OBJ, STL (ASCII / binary), PLY (ASCII / binary LE / BE). See surface_io.h.
#include "mesohex_io/surface_io.h"
#include "mesohex_io/text_input.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <numeric>
#include <sstream>
#include <string_view>
#include <vector>

#include "mesohex/core/error.h"
#include "mesohex_io/hex_io.h"

namespace mesohex {
namespace {

// Line-by-line reader over the file content with 1-based line numbers and error helpers.
class Lines {
public:
    Lines(const std::string& file, std::string_view content) : file_(file), content_(content) {}

    // Next line (without '\n' / '\r'); false at the end.
    bool next(std::string_view& line) {
        if (pos_ > content_.size() || (pos_ == content_.size() && pos_ != 0 && content_.back() == '\n')) return false;
        if (content_.empty()) return false;
        std::size_t end = content_.find('\n', pos_);
        if (end == std::string::npos) end = content_.size();
        line = std::string_view(content_.data() + pos_, end - pos_);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        pos_ = end + 1;
        ++number_;
        return true;
    }
    // Next line with at least one token that is not a comment (text after '#' is dropped).
    bool next_tokens(std::vector<std::string_view>& tokens) {
        std::string_view line;
        while (next(line)) {
            const std::size_t hash = line.find('#');
            if (hash != std::string_view::npos) line = line.substr(0, hash);
            tokens = split_whitespace(line);
            if (!tokens.empty()) return true;
        }
        return false;
    }
    int number() const { return number_; }
    std::size_t position() const { return pos_; }

    [[noreturn]] void fail(const std::string& what) const { fail_at(number_, what); }
    [[noreturn]] void fail_at(int line, const std::string& what) const {
        throw Error(ErrorCode::InvalidInput, file_ + ":" + std::to_string(line) + ": " + what,
                    ElementRef{ElementRef::Kind::FileLine, line});
    }
    double real(std::string_view tok, const char* what) const {
        std::string_view t = tok;
        if (!t.empty() && t.front() == '+') t.remove_prefix(1);
        double value = 0;
        const std::from_chars_result r = std::from_chars(t.data(), t.data() + t.size(), value);
        if (t.empty() || r.ec != std::errc() || r.ptr != t.data() + t.size())
            fail(std::string("expected a number for ") + what + ", got '" + quote_excerpt(tok) + "'");
        if (!std::isfinite(value)) fail(std::string("non-finite ") + what + " '" + quote_excerpt(tok) + "'");
        return value;
    }
    long long integer(std::string_view tok, const char* what) const {
        std::string_view t = tok;
        if (!t.empty() && t.front() == '+') t.remove_prefix(1);
        long long value = 0;
        const std::from_chars_result r = std::from_chars(t.data(), t.data() + t.size(), value);
        if (t.empty() || r.ec != std::errc() || r.ptr != t.data() + t.size())
            fail(std::string("expected an integer for ") + what + ", got '" + quote_excerpt(tok) + "'");
        return value;
    }

private:
    const std::string& file_;
    std::string_view content_;
    std::size_t pos_ = 0;
    int number_ = 0;
};

// Appends the fan triangulation of a polygon; indices must be validated by the caller.
void add_polygon(TriangleMesh& mesh, const std::vector<int>& poly) {
    for (std::size_t i = 1; i + 1 < poly.size(); ++i) mesh.triangles.push_back({poly[0], poly[i], poly[i + 1]});
}

// ------------------------------------------------------------------------------------------------ OFF

TriangleMesh read_off(const std::string& path, std::string_view content) {
    Lines in(path, content);
    std::vector<std::string_view> tok;
    if (!in.next_tokens(tok)) in.fail("empty file (expected the OFF header)");
    const std::string_view head = tok[0];
    if (head.size() < 3 || head.substr(head.size() - 3) != "OFF")
        in.fail("expected an OFF header ('OFF', 'COFF', 'NOFF', ...), got '" + quote_excerpt(head) + "'");
    if (head.find("4") != std::string_view::npos || head.find("n") != std::string_view::npos)
        in.fail("unsupported OFF variant '" + quote_excerpt(head) + "' (only 3D OFF)");
    if (tok.size() > 1 && tok[1] == "BINARY") in.fail("binary OFF is not supported");
    std::vector<std::string_view> counts(tok.begin() + 1, tok.end());
    if (counts.empty()) {
        if (!in.next_tokens(counts)) in.fail("missing the vertex / face counts");
    }
    if (counts.size() < 2) in.fail("expected 'nv nf [ne]'");
    const long long nv = in.integer(counts[0], "the vertex count");
    const long long nf = in.integer(counts[1], "the face count");
    if (nv < 0 || nf < 0 || nv > 1'000'000'000 || nf > 1'000'000'000) in.fail("invalid vertex / face counts");
    TriangleMesh mesh;
    // Counts are checked against the file size before reserving (a corrupt header must not allocate gigabytes).
    // What is reserved is capped by what the rest of the file can hold ("0 0 0\n" per vertex, "3 0 1 2\n" per face):
    // a corrupt header allocates nothing big, and a short file fails where its data ends ("... missing").
    const std::size_t left = content.size() - std::min(in.position(), content.size());
    mesh.points.reserve(std::min(static_cast<std::size_t>(nv), left / 6));
    mesh.triangles.reserve(std::min(static_cast<std::size_t>(nf), left / 8));
    for (long long v = 0; v < nv; ++v) {
        if (!in.next_tokens(tok)) in.fail("unexpected end of file: " + std::to_string(nv - v) + " vertices missing");
        if (tok.size() < 3) in.fail("a vertex needs 3 coordinates");
        mesh.points.push_back({in.real(tok[0], "x"), in.real(tok[1], "y"), in.real(tok[2], "z")});
    }
    std::vector<int> poly;
    for (long long f = 0; f < nf; ++f) {
        if (!in.next_tokens(tok)) in.fail("unexpected end of file: " + std::to_string(nf - f) + " faces missing");
        const long long n = in.integer(tok[0], "the face size");
        if (n < 3) in.fail("a face needs at least 3 vertices, got " + std::to_string(n));
        if (n > static_cast<long long>(tok.size()) - 1)  // (not n + 1 > size: n may be the largest long long)
            in.fail("face lists fewer than " + std::to_string(n) + " vertices");
        poly.clear();
        for (long long i = 1; i <= n; ++i) {
            const long long id = in.integer(tok[static_cast<std::size_t>(i)], "a vertex index");
            if (id < 0 || id >= nv)
                in.fail("vertex index " + std::to_string(id) + " out of range [0, " + std::to_string(nv) + ")");
            poly.push_back(static_cast<int>(id));
        }
        add_polygon(mesh, poly);
    }
    return mesh;
}

// ------------------------------------------------------------------------------------------------ OBJ

TriangleMesh read_obj(const std::string& path, std::string_view content) {
    Lines in(path, content);
    std::vector<std::string_view> tok;
    TriangleMesh mesh;
    std::vector<int> poly;
    while (in.next_tokens(tok)) {
        if (tok[0] == "v") {
            if (tok.size() < 4) in.fail("a vertex needs 3 coordinates");
            mesh.points.push_back({in.real(tok[1], "x"), in.real(tok[2], "y"), in.real(tok[3], "z")});
        } else if (tok[0] == "f") {
            if (tok.size() < 4) in.fail("a face needs at least 3 vertices");
            poly.clear();
            for (std::size_t i = 1; i < tok.size(); ++i) {
                std::string_view t = tok[i];
                const std::size_t slash = t.find('/');
                if (slash != std::string_view::npos) t = t.substr(0, slash);
                const long long raw = in.integer(t, "a vertex index");
                const long long nv = static_cast<long long>(mesh.points.size());
                const long long id = raw > 0 ? raw - 1 : nv + raw;  // negative: relative to the end
                if (raw == 0 || id < 0 || id >= nv)
                    in.fail("vertex index " + std::to_string(raw) + " out of range (" + std::to_string(nv) +
                            " vertices so far)");
                poly.push_back(static_cast<int>(id));
            }
            add_polygon(mesh, poly);
        }
        // vt, vn, vp, l, g, o, s, usemtl, mtllib, ...: ignored.
    }
    return mesh;
}

// ------------------------------------------------------------------------------------------------ STL

// Merges identical positions (exact comparison); vertex ids follow the order of first appearance.
TriangleMesh merge_soup(const std::vector<Vec3>& corners) {
    const std::size_t n = corners.size();
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t{0});
    const auto less = [&](std::size_t a, std::size_t b) {
        const Vec3& p = corners[a];
        const Vec3& q = corners[b];
        if (p.x != q.x) return p.x < q.x;
        if (p.y != q.y) return p.y < q.y;
        if (p.z != q.z) return p.z < q.z;
        return a < b;
    };
    std::sort(order.begin(), order.end(), less);
    std::vector<std::size_t> representative(n);  // first corner (smallest index) with the same position
    for (std::size_t i = 0; i < n; ++i) {
        const bool same = i > 0 && corners[order[i]] == corners[order[i - 1]];
        representative[order[i]] = same ? representative[order[i - 1]] : order[i];
    }
    TriangleMesh mesh;
    std::vector<int> id(n, -1);
    for (std::size_t c = 0; c < n; ++c) {
        const std::size_t r = representative[c];
        if (id[r] < 0) {
            id[r] = static_cast<int>(mesh.points.size());
            mesh.points.push_back(corners[r]);
        }
        id[c] = id[r];
    }
    for (std::size_t t = 0; t + 2 < n; t += 3) mesh.triangles.push_back({id[t], id[t + 1], id[t + 2]});
    return mesh;
}

template <typename T>
T load_le(const char* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    if constexpr (std::endian::native == std::endian::big) {
        char b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        std::reverse(b, b + sizeof(T));
        std::memcpy(&v, b, sizeof(T));
    }
    return v;
}

TriangleMesh read_stl(const std::string& path, std::string_view content) {
    const bool binary_size =
        content.size() >= 84 &&
        content.size() == 84 + 50 * static_cast<std::size_t>(load_le<std::uint32_t>(content.data() + 80));
    // Binary files may start with "solid" too: a NUL byte early on also means binary.
    const bool has_nul = content.find('\0') < std::min<std::size_t>(content.size(), 1024);
    const bool starts_solid = content.compare(0, 5, "solid") == 0 && !has_nul;
    std::vector<Vec3> corners;
    if (binary_size || !starts_solid) {
        if (content.size() < 84)
            throw Error(ErrorCode::InvalidInput, path + ": binary STL shorter than its 84-byte header");
        const std::size_t n = load_le<std::uint32_t>(content.data() + 80);
        if (content.size() < 84 + 50 * n)
            throw Error(ErrorCode::InvalidInput, path + ": binary STL truncated: " + std::to_string(n) +
                                                     " triangles announced, " +
                                                     std::to_string((content.size() - 84) / 50) + " present");
        corners.reserve(3 * n);
        for (std::size_t t = 0; t < n; ++t) {
            const char* rec = content.data() + 84 + 50 * t + 12;  // skip the normal
            for (int c = 0; c < 3; ++c) {
                const Vec3 p{load_le<float>(rec + 12 * c), load_le<float>(rec + 12 * c + 4),
                             load_le<float>(rec + 12 * c + 8)};
                if (!is_finite(p))
                    throw Error(ErrorCode::InvalidInput, path + ": byte " + std::to_string(84 + 50 * t + 12 + 12 * c) +
                                                             ": non-finite coordinate in triangle " +
                                                             std::to_string(t));
                corners.push_back(p);
            }
        }
        return merge_soup(corners);
    }
    Lines in(path, content);
    std::vector<std::string_view> tok;
    int in_facet = 0;  // corners read in the current facet
    bool in_loop = false;
    while (in.next_tokens(tok)) {
        const std::string_view k = tok[0];
        if (k == "solid" || k == "endsolid") continue;
        if (k == "facet") {
            if (in_loop) in.fail("'facet' inside an open facet");
            in_facet = 0;
        } else if (k == "outer") {
            in_loop = true;
        } else if (k == "vertex") {
            if (!in_loop) in.fail("'vertex' outside 'outer loop'");
            if (tok.size() < 4) in.fail("a vertex needs 3 coordinates");
            if (++in_facet > 3) in.fail("a facet with more than 3 vertices");
            corners.push_back({in.real(tok[1], "x"), in.real(tok[2], "y"), in.real(tok[3], "z")});
        } else if (k == "endloop") {
            if (in_facet != 3) in.fail("a facet needs exactly 3 vertices, got " + std::to_string(in_facet));
            in_loop = false;
        } else if (k == "endfacet") {
            if (in_loop) in.fail("'endfacet' before 'endloop'");
        } else {
            in.fail("unexpected keyword '" + quote_excerpt(k) + "' in ASCII STL");
        }
    }
    if (in_loop) in.fail("unexpected end of file inside a facet");
    return merge_soup(corners);
}

// ------------------------------------------------------------------------------------------------ PLY

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64, Invalid };

PlyType ply_type(std::string_view s) {
    if (s == "char" || s == "int8") return PlyType::Int8;
    if (s == "uchar" || s == "uint8") return PlyType::UInt8;
    if (s == "short" || s == "int16") return PlyType::Int16;
    if (s == "ushort" || s == "uint16") return PlyType::UInt16;
    if (s == "int" || s == "int32") return PlyType::Int32;
    if (s == "uint" || s == "uint32") return PlyType::UInt32;
    if (s == "float" || s == "float32") return PlyType::Float32;
    if (s == "double" || s == "float64") return PlyType::Float64;
    return PlyType::Invalid;
}

std::size_t ply_size(PlyType t) {
    switch (t) {
        case PlyType::Int8:
        case PlyType::UInt8: return 1;
        case PlyType::Int16:
        case PlyType::UInt16: return 2;
        case PlyType::Int32:
        case PlyType::UInt32:
        case PlyType::Float32: return 4;
        case PlyType::Float64: return 8;
        case PlyType::Invalid: return 0;
    }
    return 0;
}

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::Invalid;
    bool is_list = false;
    PlyType count_type = PlyType::Invalid;
};

struct PlyElement {
    std::string name;
    long long count = 0;
    int header_line = 0;
    std::vector<PlyProperty> properties;
};

// Sequential reader of the binary body.
class PlyBinary {
public:
    PlyBinary(const std::string& path, std::string_view content, std::size_t pos, bool big_endian)
        : path_(path), content_(content), pos_(pos), swap_(big_endian != (std::endian::native == std::endian::big)) {}

    double read(PlyType t, const std::string& what) {
        const std::size_t n = ply_size(t);
        if (pos_ + n > content_.size())
            throw Error(ErrorCode::InvalidInput,
                        path_ + ": byte " + std::to_string(pos_) + ": unexpected end of file while reading " + what);
        char b[8];
        std::memcpy(b, content_.data() + pos_, n);
        if (swap_) std::reverse(b, b + n);
        pos_ += n;
        switch (t) {
            case PlyType::Int8: {
                std::int8_t v;
                std::memcpy(&v, b, 1);
                return v;
            }
            case PlyType::UInt8: {
                std::uint8_t v;
                std::memcpy(&v, b, 1);
                return v;
            }
            case PlyType::Int16: {
                std::int16_t v;
                std::memcpy(&v, b, 2);
                return v;
            }
            case PlyType::UInt16: {
                std::uint16_t v;
                std::memcpy(&v, b, 2);
                return v;
            }
            case PlyType::Int32: {
                std::int32_t v;
                std::memcpy(&v, b, 4);
                return v;
            }
            case PlyType::UInt32: {
                std::uint32_t v;
                std::memcpy(&v, b, 4);
                return v;
            }
            case PlyType::Float32: {
                float v;
                std::memcpy(&v, b, 4);
                return v;
            }
            case PlyType::Float64: {
                double v;
                std::memcpy(&v, b, 8);
                return v;
            }
            case PlyType::Invalid: break;
        }
        return 0;
    }
    std::size_t position() const { return pos_; }

private:
    const std::string& path_;
    std::string_view content_;
    std::size_t pos_;
    bool swap_;
};

enum class PlyFormat { Ascii, BinaryLE, BinaryBE };

struct PlyHeader {
    PlyFormat format = PlyFormat::Ascii;
    std::vector<PlyElement> elements;
};

// One "property ..." header line (tokens) of the current element.
PlyProperty parse_ply_property(const Lines& in, const std::vector<std::string_view>& tok) {
    PlyProperty p;
    if (tok.size() >= 5 && tok[1] == "list") {
        p.is_list = true;
        p.count_type = ply_type(tok[2]);
        p.type = ply_type(tok[3]);
        p.name = quote_excerpt(tok[4]);
        if (p.count_type == PlyType::Invalid || p.type == PlyType::Invalid || p.count_type == PlyType::Float32 ||
            p.count_type == PlyType::Float64)
            in.fail("invalid list property types");
    } else if (tok.size() >= 3 && tok[1] != "list") {
        p.type = ply_type(tok[1]);
        p.name = quote_excerpt(tok[2]);
        if (p.type == PlyType::Invalid) in.fail("unknown property type '" + quote_excerpt(tok[1]) + "'");
    } else {
        in.fail("malformed 'property' line");
    }
    return p;
}

// The header, from the "ply" line to "end_header" (in is left at the first byte of the body).
PlyHeader parse_ply_header(Lines& in) {
    std::string_view line;
    if (!in.next(line) || line != "ply") in.fail("expected 'ply' on the first line");
    PlyHeader h;
    bool have_format = false, ended = false;
    while (in.next(line)) {
        const std::vector<std::string_view> tok = split_whitespace(line);
        if (tok.empty() || tok[0] == "comment" || tok[0] == "obj_info") continue;
        if (tok[0] == "end_header") {
            ended = true;
            break;
        }
        if (tok[0] == "format") {
            if (tok.size() < 2) in.fail("incomplete 'format' line");
            if (tok[1] == "ascii")
                h.format = PlyFormat::Ascii;
            else if (tok[1] == "binary_little_endian")
                h.format = PlyFormat::BinaryLE;
            else if (tok[1] == "binary_big_endian")
                h.format = PlyFormat::BinaryBE;
            else
                in.fail("unknown PLY format '" + quote_excerpt(tok[1]) + "'");
            have_format = true;
        } else if (tok[0] == "element") {
            if (tok.size() < 3) in.fail("'element' needs a name and a count");
            const long long n = in.integer(tok[2], "the element count");
            if (n < 0 || n > 2'000'000'000) in.fail("invalid element count");
            h.elements.push_back({quote_excerpt(tok[1]), n, in.number(), {}});
        } else if (tok[0] == "property") {
            if (h.elements.empty()) in.fail("'property' before any 'element'");
            h.elements.back().properties.push_back(parse_ply_property(in, tok));
        } else {
            in.fail("unexpected header keyword '" + quote_excerpt(tok[0]) + "'");
        }
    }
    if (!ended) in.fail("missing 'end_header'");
    if (!have_format) in.fail("missing 'format' line");
    return h;
}

// Which properties of an element hold the coordinates / the face list.
struct PlyLayout {
    bool is_vertex, is_face;
    int ix, iy, iz, ilist;
};

// A vertex element without x, y, z or a face element without a vertex list is an error at its header line.
PlyLayout ply_layout(const Lines& in, const PlyElement& el) {
    const auto property_index = [&](const char* name) {
        for (std::size_t i = 0; i < el.properties.size(); ++i)
            if (el.properties[i].name == name) return static_cast<int>(i);
        return -1;
    };
    PlyLayout l{el.name == "vertex", el.name == "face",   property_index("x"),
                property_index("y"), property_index("z"), property_index("vertex_indices")};
    if (l.ilist < 0) l.ilist = property_index("vertex_index");
    if (l.is_vertex && (l.ix < 0 || l.iy < 0 || l.iz < 0)) in.fail_at(el.header_line, "vertex element without x, y, z");
    if (l.is_face && l.ilist < 0) in.fail_at(el.header_line, "face element without 'vertex_indices'");
    return l;
}

// The ASCII body: one record per line; nv vertices are declared (face indices are checked against it).
void read_ply_ascii(Lines& in, const std::vector<PlyElement>& elements, long long nv, TriangleMesh& mesh) {
    std::vector<std::string_view> tok;
    std::vector<int> poly;
    for (const PlyElement& el : elements) {
        const PlyLayout l = ply_layout(in, el);
        for (long long i = 0; i < el.count; ++i) {
            if (!in.next_tokens(tok))
                in.fail("unexpected end of file: " + std::to_string(el.count - i) + " '" + el.name + "' missing");
            std::size_t t = 0;
            Vec3 p;
            poly.clear();
            for (std::size_t k = 0; k < el.properties.size(); ++k) {
                const PlyProperty& prop = el.properties[k];
                if (t >= tok.size()) in.fail("too few values for element '" + el.name + "'");
                if (!prop.is_list) {
                    const double v = in.real(tok[t++], prop.name.c_str());
                    if (l.is_vertex && static_cast<int>(k) == l.ix) p.x = v;
                    if (l.is_vertex && static_cast<int>(k) == l.iy) p.y = v;
                    if (l.is_vertex && static_cast<int>(k) == l.iz) p.z = v;
                    continue;
                }
                const long long n = in.integer(tok[t++], "a list length");
                if (n < 0 || t + static_cast<std::size_t>(n) > tok.size()) in.fail("list longer than the line");
                for (long long j = 0; j < n; ++j) {
                    const std::string_view s = tok[t++];
                    if (l.is_face && static_cast<int>(k) == l.ilist) {
                        const long long id = in.integer(s, "a vertex index");
                        if (id < 0 || id >= nv)
                            in.fail("vertex index " + std::to_string(id) + " out of range [0, " + std::to_string(nv) +
                                    ")");
                        poly.push_back(static_cast<int>(id));
                    }
                }
            }
            if (l.is_vertex) mesh.points.push_back(p);
            if (l.is_face) {
                if (poly.size() < 3) in.fail("a face needs at least 3 vertices");
                add_polygon(mesh, poly);
            }
        }
    }
}

// Record i of element `el`, read from the current position of `body`, into mesh (errors name its first byte).
void read_ply_binary_record(const std::string& path, PlyBinary& body, const PlyElement& el, const PlyLayout& l,
                            long long i, long long nv, std::vector<int>& poly, TriangleMesh& mesh) {
    const std::size_t start = body.position();
    Vec3 p;
    poly.clear();
    for (std::size_t k = 0; k < el.properties.size(); ++k) {
        const PlyProperty& prop = el.properties[k];
        if (!prop.is_list) {
            const double v = body.read(prop.type, el.name + " " + std::to_string(i));
            if (l.is_vertex && static_cast<int>(k) == l.ix) p.x = v;
            if (l.is_vertex && static_cast<int>(k) == l.iy) p.y = v;
            if (l.is_vertex && static_cast<int>(k) == l.iz) p.z = v;
            continue;
        }
        const double n = body.read(prop.count_type, el.name + " " + std::to_string(i));
        if (n < 0)
            throw Error(ErrorCode::InvalidInput, path + ": byte " + std::to_string(start) + ": negative list length");
        for (long long j = 0; j < static_cast<long long>(n); ++j) {
            const double id = body.read(prop.type, el.name + " " + std::to_string(i));
            if (l.is_face && static_cast<int>(k) == l.ilist) {
                if (!(id >= 0 && id < static_cast<double>(nv)) || id != std::floor(id))
                    throw Error(ErrorCode::InvalidInput, path + ": byte " + std::to_string(start) + ": face " +
                                                             std::to_string(i) + ": vertex index " +
                                                             std::to_string(id) + " out of range");
                poly.push_back(static_cast<int>(id));
            }
        }
    }
    if (l.is_vertex) {
        if (!is_finite(p))
            throw Error(ErrorCode::InvalidInput,
                        path + ": byte " + std::to_string(start) + ": vertex " + std::to_string(i) + " is not finite");
        mesh.points.push_back(p);
    }
    if (l.is_face) {
        if (poly.size() < 3)
            throw Error(ErrorCode::InvalidInput, path + ": byte " + std::to_string(start) + ": face " +
                                                     std::to_string(i) + " has fewer than 3 vertices");
        add_polygon(mesh, poly);
    }
}

// The binary body: from where the header (read by `in`) ends to the end of `content`.
void read_ply_binary(const std::string& path, std::string_view content, const Lines& in, const PlyHeader& header,
                     long long nv, TriangleMesh& mesh) {
    PlyBinary body(path, content, in.position(), header.format == PlyFormat::BinaryBE);
    std::vector<int> poly;
    for (const PlyElement& el : header.elements) {
        const PlyLayout l = ply_layout(in, el);
        // Each record takes at least the sizes of its scalars and list counts: a count the rest of the file cannot
        // hold is refused at once, and an element without properties (0 bytes per record) is skipped in O(1)
        // instead of being "read" count times (work stays linear in the file size).
        std::size_t min_record = 0;
        for (const PlyProperty& prop : el.properties)
            min_record += ply_size(prop.is_list ? prop.count_type : prop.type);
        if (min_record == 0) continue;
        check_count_fits(path, el.header_line, el.count, content.size() - std::min(body.position(), content.size()),
                         min_record, "'" + quote_excerpt(el.name) + "' element count");
        for (long long i = 0; i < el.count; ++i) read_ply_binary_record(path, body, el, l, i, nv, poly, mesh);
    }
}

TriangleMesh read_ply(const std::string& path, std::string_view content) {
    Lines in(path, content);
    const PlyHeader header = parse_ply_header(in);
    long long nv = -1;
    for (const PlyElement& el : header.elements)
        if (el.name == "vertex") nv = el.count;
    if (nv < 0) in.fail_at(1, "no 'vertex' element in the header");
    TriangleMesh mesh;
    if (header.format == PlyFormat::Ascii)
        read_ply_ascii(in, header.elements, nv, mesh);
    else
        read_ply_binary(path, content, in, header, nv, mesh);
    return mesh;
}

// ------------------------------------------------------------------------------------------------ writers

std::string format_real(double v) {
    char buf[32];
    const std::to_chars_result r = std::to_chars(buf, buf + sizeof(buf), v);  // shortest round-trip form
    return std::string(buf, r.ptr);
}

std::string write_off(const TriangleMesh& m) {
    std::string s = "OFF\n" + std::to_string(m.points.size()) + " " + std::to_string(m.triangles.size()) + " 0\n";
    for (const Vec3& p : m.points) s += format_real(p.x) + " " + format_real(p.y) + " " + format_real(p.z) + "\n";
    for (const std::array<int, 3>& t : m.triangles)
        s += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
    return s;
}

std::string write_obj(const TriangleMesh& m) {
    std::string s = "# mesohex triangle surface\n";
    for (const Vec3& p : m.points)
        s += "v " + format_real(p.x) + " " + format_real(p.y) + " " + format_real(p.z) + "\n";
    for (const std::array<int, 3>& t : m.triangles)
        s += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + "\n";
    return s;
}

void append_le_float(std::string& s, float v) {
    char b[4];
    std::memcpy(b, &v, 4);
    if constexpr (std::endian::native == std::endian::big) std::reverse(b, b + 4);
    s.append(b, 4);
}

std::string write_stl(const TriangleMesh& m) {
    std::string s(80, ' ');
    const std::string title = "binary STL written by mesohex";
    s.replace(0, title.size(), title);
    const std::uint32_t n = static_cast<std::uint32_t>(m.triangles.size());
    char b[4];
    std::memcpy(b, &n, 4);
    if constexpr (std::endian::native == std::endian::big) std::reverse(b, b + 4);
    s.append(b, 4);
    s.reserve(84 + 50 * m.triangles.size());
    for (const std::array<int, 3>& t : m.triangles) {
        const Vec3& a = m.points[static_cast<std::size_t>(t[0])];
        const Vec3& bb = m.points[static_cast<std::size_t>(t[1])];
        const Vec3& c = m.points[static_cast<std::size_t>(t[2])];
        const Vec3 nrm = normalized(cross(bb - a, c - a));
        for (const Vec3& p : {nrm, a, bb, c}) {
            append_le_float(s, static_cast<float>(p.x));
            append_le_float(s, static_cast<float>(p.y));
            append_le_float(s, static_cast<float>(p.z));
        }
        s.append(2, '\0');
    }
    return s;
}

bool is_readable_surface_format(const std::string& ext) {
    return ext == "off" || ext == "obj" || ext == "stl" || ext == "ply";
}

// `content` in format `ext` (one of is_readable_surface_format), named `name` in messages.
TriangleMesh parse_surface(const std::string& name, const std::string& ext, std::string_view content) {
    if (is_blank_content(content)) fail_empty_file(name, "expected a triangle surface");
    TriangleMesh mesh;
    if (ext == "off")
        mesh = read_off(name, content);
    else if (ext == "obj")
        mesh = read_obj(name, content);
    else if (ext == "stl")
        mesh = read_stl(name, content);
    else
        mesh = read_ply(name, content);
    if (mesh.triangles.empty()) throw Error(ErrorCode::InvalidInput, name + ": the surface has no triangle");
    return mesh;
}

}  // namespace

TriangleMesh read_surface(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (!is_readable_surface_format(ext))
        throw Error(ErrorCode::InvalidInput,
                    path + ": unknown surface format '." + ext + "' (use .off, .obj, .stl or .ply)");
    return parse_surface(path, ext, read_whole_file(path));
}

TriangleMesh read_surface_text(std::string_view text, std::string_view format, std::string_view name) {
    const std::string display(name);
    std::string ext(format);
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (!is_readable_surface_format(ext))
        throw Error(ErrorCode::InvalidInput,
                    display + ": unknown surface format '" + quote_excerpt(format) + "' (use off, obj, stl or ply)");
    return parse_surface(display, ext, text);
}

void write_surface(const std::string& path, const TriangleMesh& mesh) {
    const std::string ext = lower_extension(path);
    for (const std::array<int, 3>& t : mesh.triangles)
        for (int v : t)
            if (v < 0 || static_cast<std::size_t>(v) >= mesh.points.size())
                throw Error(ErrorCode::InvalidInput, path + ": cannot write: a triangle index is out of range");
    if (ext == "off")
        write_file_atomically(path, write_off(mesh));
    else if (ext == "obj")
        write_file_atomically(path, write_obj(mesh));
    else if (ext == "stl")
        write_file_atomically(path, write_stl(mesh));
    else
        throw Error(ErrorCode::InvalidInput,
                    path + ": cannot write surface format '." + ext + "' (use .off, .obj or .stl)");
}

}  // namespace mesohex
