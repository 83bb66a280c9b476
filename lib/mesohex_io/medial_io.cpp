#include "mesohex_io/medial_io.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <sstream>
#include <string_view>
#include <utility>

#include "mesohex/core/error.h"
#include "mesohex_io/hex_io.h"
#include "mesohex_io/text_input.h"

namespace mesohex {
namespace {

// Shortest possible record lines, newline included ("v 0 0 0 1\n", "e 0 1\n", "f 0 1 2\n"): a header count times
// this must fit in the rest of the file.
constexpr std::size_t kMinVertexLine = 10;
constexpr std::size_t kMinEdgeLine = 6;
constexpr std::size_t kMinFaceLine = 8;

// Line-by-line reader over the file content held in memory.
class LineReader {
public:
    LineReader(const std::string& path, std::string_view content) : path_(path), content_(content) {}
    // Next non-blank, non-comment line; false at end of file.
    bool next(std::istringstream& out) {
        while (pos_ < content_.size()) {
            std::size_t end = content_.find('\n', pos_);
            if (end == std::string::npos) end = content_.size();
            const std::string_view line(content_.data() + pos_, end - pos_);
            pos_ = end + 1;
            ++line_no_;
            const std::size_t first = line.find_first_not_of(" \t\r");
            if (first == std::string_view::npos || line[first] == '#') continue;
            out.clear();
            out.str(std::string(line));
            return true;
        }
        return false;
    }
    std::size_t bytes_left() const { return pos_ < content_.size() ? content_.size() - pos_ : 0; }
    int line() const { return line_no_; }
    [[noreturn]] void fail(const std::string& what) const {
        const int line = std::max(line_no_, 1);
        throw Error(ErrorCode::InvalidInput, path_ + ":" + std::to_string(line) + ": " + what,
                    {ElementRef::Kind::FileLine, line});
    }

private:
    const std::string& path_;
    std::string_view content_;
    std::size_t pos_ = 0;
    int line_no_ = 0;
};

// Reads the tag and n values; fails unless the line is exactly that.
template <typename T, size_t N>
void parse_record(LineReader& r, std::istringstream& ls, const char* tag, std::array<T, N>& out) {
    std::string t;
    ls >> t;
    if (t != tag) r.fail(std::string("expected a '") + tag + "' line, found '" + quote_excerpt(t) + "'");
    for (size_t i = 0; i < N; ++i)
        if (!(ls >> out[i]))
            r.fail(std::string("malformed '") + tag + "' line (expected " + std::to_string(N) + " values)");
    std::string extra;
    if (ls >> extra) r.fail(std::string("trailing data on a '") + tag + "' line: '" + quote_excerpt(extra) + "'");
}

Skeleton read_medial(const std::string& path, std::string_view content) {
    if (is_blank_content(content)) fail_empty_file(path, "expected the header 'nv ne nf'");
    LineReader r(path, content);
    std::istringstream ls;
    if (!r.next(ls)) r.fail("no header (expected the header 'nv ne nf')");
    long long nv = -1, ne = -1, nf = -1;
    std::string extra;
    if (!(ls >> nv >> ne >> nf) || (ls >> extra) || nv < 0 || ne < 0 || nf < 0)
        r.fail("bad header (expected three non-negative integer counts 'nv ne nf')");
    const int header_line = r.line();
    // Counts first, against what the file can hold: nothing is reserved from the header alone.
    check_count_fits(path, header_line, nv, r.bytes_left(), kMinVertexLine, "vertex count");
    check_count_fits(path, header_line, ne, r.bytes_left(), kMinEdgeLine, "edge count");
    check_count_fits(path, header_line, nf, r.bytes_left(), kMinFaceLine, "triangle count");
    Skeleton s;
    s.points.reserve(static_cast<size_t>(nv));
    s.radii.reserve(static_cast<size_t>(nv));
    for (long long i = 0; i < nv; ++i) {
        if (!r.next(ls)) r.fail("file ends after " + std::to_string(i) + " of " + std::to_string(nv) + " vertices");
        std::array<double, 4> v{};
        parse_record(r, ls, "v", v);
        const Vec3 p{v[0], v[1], v[2]};
        if (!is_finite(p)) r.fail("non-finite vertex coordinate");
        if (!std::isfinite(v[3]) || !(v[3] > 0)) r.fail("vertex radius must be finite and > 0");
        s.points.push_back(p);
        s.radii.push_back(v[3]);
    }
    auto check_index = [&](long long i) {
        if (i < 0 || i >= nv)
            r.fail("vertex index " + std::to_string(i) + " out of range [0, " + std::to_string(nv) + ")");
    };
    std::set<std::pair<long long, long long>> seen;
    s.edges.reserve(static_cast<size_t>(ne));
    for (long long i = 0; i < ne; ++i) {
        if (!r.next(ls)) r.fail("file ends after " + std::to_string(i) + " of " + std::to_string(ne) + " edges");
        std::array<long long, 2> e{};
        parse_record(r, ls, "e", e);
        check_index(e[0]);
        check_index(e[1]);
        if (e[0] == e[1]) r.fail("edge joins vertex " + std::to_string(e[0]) + " to itself");
        if (!seen.insert(std::minmax(e[0], e[1])).second)
            r.fail("duplicated edge (" + std::to_string(e[0]) + ", " + std::to_string(e[1]) + ")");
        s.edges.push_back({static_cast<int>(e[0]), static_cast<int>(e[1])});
    }
    s.faces.reserve(static_cast<size_t>(nf));
    for (long long i = 0; i < nf; ++i) {
        if (!r.next(ls)) r.fail("file ends after " + std::to_string(i) + " of " + std::to_string(nf) + " triangles");
        std::array<long long, 3> f{};
        parse_record(r, ls, "f", f);
        for (long long x : f) check_index(x);
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) r.fail("triangle with a repeated vertex");
        s.faces.push_back({static_cast<int>(f[0]), static_cast<int>(f[1]), static_cast<int>(f[2])});
    }
    if (r.next(ls)) r.fail("unexpected data after the " + std::to_string(nf) + " triangles announced by the header");
    add_face_edges(s);
    return s;
}

}  // namespace

Skeleton read_medial_mesh(const std::string& path) { return read_medial(path, read_whole_file(path)); }

Skeleton read_medial_mesh_text(std::string_view content, std::string_view name) {
    return read_medial(std::string(name), content);
}

void write_medial_mesh(const std::string& path, const Skeleton& medial) {
    if (medial.radii.size() != medial.points.size())
        throw Error(ErrorCode::InvalidInput, path + ": medial mesh needs one radius per point");
    std::ostringstream out;
    out.precision(17);
    out << medial.points.size() << ' ' << medial.edges.size() << ' ' << medial.faces.size() << '\n';
    for (size_t v = 0; v < medial.points.size(); ++v) {
        const Vec3& p = medial.points[v];
        out << "v " << p.x << ' ' << p.y << ' ' << p.z << ' ' << medial.radii[v] << '\n';
    }
    for (const std::array<int, 2>& e : medial.edges) out << "e " << e[0] << ' ' << e[1] << '\n';
    for (size_t f = 0; f < medial.faces.size(); ++f) {
        const std::vector<int>& t = medial.faces[f];
        if (t.size() != 3)
            throw Error(ErrorCode::InvalidInput, path + ": medial face " + std::to_string(f) + " is not a triangle",
                        {ElementRef::Kind::SkeletonFace, static_cast<int>(f)});
        out << "f " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    }
    write_file_atomically(path, out.str());
}

}  // namespace mesohex
