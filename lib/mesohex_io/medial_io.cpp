#include "mesohex_io/medial_io.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <utility>

#include "mesohex/core/error.h"
#include "mesohex_io/hex_io.h"

namespace mesohex {
namespace {

class LineReader {
public:
    explicit LineReader(const std::string& path) : path_(path), in_(path) {
        if (!in_) throw Error(ErrorCode::IoError, path + ": cannot open medial mesh");
    }
    // Next non-blank, non-comment line; false at end of file.
    bool next(std::istringstream& out) {
        std::string line;
        while (std::getline(in_, line)) {
            ++line_no_;
            const size_t first = line.find_first_not_of(" \t\r");
            if (first == std::string::npos || line[first] == '#') continue;
            out.clear();
            out.str(line);
            return true;
        }
        return false;
    }
    [[noreturn]] void fail(const std::string& what) const {
        throw Error(ErrorCode::IoError, path_ + ":" + std::to_string(line_no_) + ": " + what,
                    {ElementRef::Kind::FileLine, line_no_});
    }

private:
    std::string path_;
    std::ifstream in_;
    int line_no_ = 0;
};

// Reads the tag and n values; fails unless the line is exactly that.
template <typename T, size_t N>
void parse_record(LineReader& r, std::istringstream& ls, const char* tag, std::array<T, N>& out) {
    std::string t;
    ls >> t;
    if (t != tag) r.fail(std::string("expected a '") + tag + "' line, found '" + t + "'");
    for (size_t i = 0; i < N; ++i)
        if (!(ls >> out[i])) r.fail(std::string("malformed '") + tag + "' line (expected " + std::to_string(N) + " values)");
    std::string extra;
    if (ls >> extra) r.fail(std::string("trailing data on a '") + tag + "' line: '" + extra + "'");
}

}  // namespace

Skeleton read_medial_mesh(const std::string& path) {
    LineReader r(path);
    std::istringstream ls;
    if (!r.next(ls)) r.fail("empty file (expected the header 'nv ne nf')");
    long nv = -1, ne = -1, nf = -1;
    std::string extra;
    if (!(ls >> nv >> ne >> nf) || (ls >> extra) || nv < 0 || ne < 0 || nf < 0)
        r.fail("bad header (expected three non-negative counts 'nv ne nf')");
    Skeleton s;
    s.points.reserve(static_cast<size_t>(nv));
    s.radii.reserve(static_cast<size_t>(nv));
    for (long i = 0; i < nv; ++i) {
        if (!r.next(ls)) r.fail("file ends after " + std::to_string(i) + " of " + std::to_string(nv) + " vertices");
        std::array<double, 4> v{};
        parse_record(r, ls, "v", v);
        const Vec3 p{v[0], v[1], v[2]};
        if (!is_finite(p)) r.fail("non-finite vertex coordinate");
        if (!std::isfinite(v[3]) || !(v[3] > 0)) r.fail("vertex radius must be finite and > 0");
        s.points.push_back(p);
        s.radii.push_back(v[3]);
    }
    auto check_index = [&](long i) {
        if (i < 0 || i >= nv) r.fail("vertex index " + std::to_string(i) + " out of range [0, " + std::to_string(nv) + ")");
    };
    std::set<std::pair<long, long>> seen;
    for (long i = 0; i < ne; ++i) {
        if (!r.next(ls)) r.fail("file ends after " + std::to_string(i) + " of " + std::to_string(ne) + " edges");
        std::array<long, 2> e{};
        parse_record(r, ls, "e", e);
        check_index(e[0]);
        check_index(e[1]);
        if (e[0] == e[1]) r.fail("edge joins vertex " + std::to_string(e[0]) + " to itself");
        if (!seen.insert(std::minmax(e[0], e[1])).second)
            r.fail("duplicated edge (" + std::to_string(e[0]) + ", " + std::to_string(e[1]) + ")");
        s.edges.push_back({static_cast<int>(e[0]), static_cast<int>(e[1])});
    }
    for (long i = 0; i < nf; ++i) {
        if (!r.next(ls)) r.fail("file ends after " + std::to_string(i) + " of " + std::to_string(nf) + " triangles");
        std::array<long, 3> f{};
        parse_record(r, ls, "f", f);
        for (long x : f) check_index(x);
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) r.fail("triangle with a repeated vertex");
        s.faces.push_back({static_cast<int>(f[0]), static_cast<int>(f[1]), static_cast<int>(f[2])});
    }
    if (r.next(ls)) r.fail("unexpected data after the " + std::to_string(nf) + " triangles announced by the header");
    add_face_edges(s);
    return s;
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
