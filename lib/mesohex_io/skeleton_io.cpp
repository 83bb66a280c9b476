#include "mesohex_io/skeleton_io.h"
#include "mesohex_io/text_input.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string_view>
#include <utility>
#include <vector>

#include "mesohex/core/error.h"
#include "mesohex/core/unordered_pairs.h"
#include "mesohex_io/hex_io.h"

// Formats and the exact rules each reader follows are documented in docs/formats.md ("Skeleton formats").
// Every reader works on the whole file held in memory, line by line; errors name "<file>:<line>: <what>".

namespace mesohex {
namespace {

// ------------------------------------------------------------------------------------------------ text helpers

struct TextLine {
    int number = 0;  // 1-based
    std::string_view text;
};

// Splits into lines ('\n', with a trailing '\r' removed). The views point into `content`.
std::vector<TextLine> split_lines(std::string_view content) {
    std::vector<TextLine> lines;
    std::size_t start = 0;
    int number = 1;
    while (start <= content.size()) {
        std::size_t end = content.find('\n', start);
        if (end == std::string::npos) end = content.size();
        std::string_view text(content.data() + start, end - start);
        if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
        lines.push_back({number++, text});
        if (end == content.size()) break;
        start = end + 1;
    }
    return lines;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

bool is_blank(std::string_view s) {
    return std::all_of(s.begin(), s.end(), [](char c) { return is_space(c); });
}

std::string_view trim_left(std::string_view s) {
    while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
    return s;
}

class Context {
public:
    explicit Context(std::string file) : file_(std::move(file)) {}
    [[noreturn]] void fail(int line, const std::string& what) const {
        throw Error(ErrorCode::InvalidInput, file_ + ":" + std::to_string(line) + ": " + what,
                    ElementRef{ElementRef::Kind::FileLine, line});
    }
    double number(std::string_view tok, int line, const char* what) const {
        std::string_view t = tok;
        if (!t.empty() && t.front() == '+') t.remove_prefix(1);
        double value = 0;
        const char* first = t.data();
        const char* last = t.data() + t.size();
        const std::from_chars_result r = std::from_chars(first, last, value);
        if (t.empty() || r.ec != std::errc() || r.ptr != last)
            fail(line, std::string("expected a number for ") + what + ", got '" + quote_excerpt(tok) + "'");
        if (!std::isfinite(value)) fail(line, std::string("non-finite ") + what + " '" + quote_excerpt(tok) + "'");
        return value;
    }
    long long integer(std::string_view tok, int line, const char* what) const {
        std::string_view t = tok;
        if (!t.empty() && t.front() == '+') t.remove_prefix(1);
        long long value = 0;
        const char* first = t.data();
        const char* last = t.data() + t.size();
        const std::from_chars_result r = std::from_chars(first, last, value);
        if (t.empty() || r.ec != std::errc() || r.ptr != last)
            fail(line, std::string("expected an integer for ") + what + ", got '" + quote_excerpt(tok) + "'");
        return value;
    }
    // A count or index that must fit in [0, 2^31).
    int non_negative(std::string_view tok, int line, const char* what) const {
        const long long v = integer(tok, line, what);
        if (v < 0 || v > 2147483647LL) fail(line, std::string(what) + " out of range: " + quote_excerpt(tok));
        return static_cast<int>(v);
    }
    const std::string& file() const { return file_; }

private:
    std::string file_;
};

// Where each element came from, for error messages raised after parsing.
struct Parsed {
    Skeleton s;
    std::vector<int> edge_line;
    std::vector<int> face_line;
    std::vector<int> radius_line;  // one per radius value
};

// "# mesohex radius <index> <r>" comment lines (index base given by the format). Returns true if `comment` (the text
// after '#') is such a line, and stores the value. `tok`: scratch for the tokens.
bool parse_radius_comment(const Context& ctx, std::string_view comment, int line, int index_base,
                          std::map<int, std::pair<double, int>>& radius_of, std::vector<std::string_view>& tok) {
    split_whitespace(comment, tok);
    if (tok.size() < 2 || tok[0] != "mesohex" || tok[1] != "radius") return false;
    if (tok.size() != 4) ctx.fail(line, "radius comment must be '# mesohex radius <vertex> <radius>'");
    const long long raw = ctx.integer(tok[2], line, "radius vertex index");
    if (raw < index_base || raw - index_base > 2147483647LL)  // (no subtraction below index_base: no overflow)
        ctx.fail(line, "radius vertex index out of range: " + quote_excerpt(tok[2]));
    const long long idx = raw - index_base;
    const double r = ctx.number(tok[3], line, "radius");
    if (!radius_of.emplace(static_cast<int>(idx), std::make_pair(r, line)).second)
        ctx.fail(line, "second radius for vertex " + quote_excerpt(tok[2]));
    return true;
}

// Moves radius comments into p (all vertices or none).
void apply_radius_comments(const Context& ctx, const std::map<int, std::pair<double, int>>& radius_of, Parsed& p,
                           int last_line, int index_base) {
    if (radius_of.empty()) return;
    const int n = static_cast<int>(p.s.points.size());
    for (const auto& [v, value] : radius_of)
        if (v >= n)
            ctx.fail(value.second, "radius given for vertex " + std::to_string(v + index_base) + " but the file has " +
                                       std::to_string(n) + " vertices");
    if (static_cast<int>(radius_of.size()) != n)
        ctx.fail(last_line, "radius comments cover " + std::to_string(radius_of.size()) + " of " + std::to_string(n) +
                                " vertices (give all or none)");
    p.s.radii.resize(n);
    p.radius_line.resize(n);
    for (const auto& [v, value] : radius_of) {
        p.s.radii[v] = value.first;
        p.radius_line[v] = value.second;
    }
}

// The edges without the repeats (either direction) of an earlier one, in their order. Ids in [0, n).
std::vector<std::array<int, 2>> without_repeated_edges(const std::vector<std::array<int, 2>>& edges, int n) {
    const std::vector<char> first = first_of_each_pair(edges, n);
    std::vector<std::array<int, 2>> out;
    out.reserve(edges.size());
    for (std::size_t e = 0; e < edges.size(); ++e)
        if (first[e]) out.push_back(edges[e]);
    return out;
}

bool repeats_a_vertex(const std::vector<int>& face) {
    if (face.size() <= 8) {  // the usual quad or triangle: no copy
        for (std::size_t i = 0; i < face.size(); ++i)
            for (std::size_t j = i + 1; j < face.size(); ++j)
                if (face[i] == face[j]) return true;
        return false;
    }
    std::vector<int> sorted = face;
    std::sort(sorted.begin(), sorted.end());
    return std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
}

// Checks shared by every reader; drops duplicate edges (documented); adds missing face sides.
Skeleton finalize(const Context& ctx, Parsed p) {
    Skeleton& s = p.s;
    const int n = static_cast<int>(s.points.size());
    for (std::size_t v = 0; v < s.radii.size(); ++v)
        if (!(s.radii[v] > 0))
            ctx.fail(p.radius_line[v],
                     "radius of vertex " + std::to_string(v) + " must be positive, got " + std::to_string(s.radii[v]));
    for (std::size_t e = 0; e < s.edges.size(); ++e) {
        const auto [a, b] = s.edges[e];
        const int line = p.edge_line[e];
        if (a < 0 || a >= n || b < 0 || b >= n)
            ctx.fail(line, "edge names vertex " + std::to_string(a < 0 || a >= n ? a : b) + " but there are " +
                               std::to_string(n) + " vertices (0-based)");
        if (a == b) ctx.fail(line, "self-loop edge on vertex " + std::to_string(a));
    }
    s.edges = without_repeated_edges(s.edges, n);
    for (std::size_t f = 0; f < s.faces.size(); ++f) {
        const std::vector<int>& face = s.faces[f];
        const int line = p.face_line[f];
        if (face.size() < 3) ctx.fail(line, "face with fewer than 3 vertices");
        for (const int v : face)
            if (v < 0 || v >= n)
                ctx.fail(line, "face names vertex " + std::to_string(v) + " but there are " + std::to_string(n) +
                                   " vertices (0-based)");
        if (repeats_a_vertex(face)) ctx.fail(line, "face repeats a vertex");
    }
    add_face_edges(s);
    return std::move(p.s);
}

int last_line_number(const std::vector<TextLine>& lines) {
    for (auto it = lines.rbegin(); it != lines.rend(); ++it)
        if (!is_blank(it->text)) return it->number;
    return 1;
}

void require_content(const Context& ctx, const std::vector<TextLine>& lines) {
    if (std::all_of(lines.begin(), lines.end(), [](const TextLine& l) { return is_blank(l.text); }))
        ctx.fail(1, "empty file");
}

// ------------------------------------------------------------------------------------------------ .cg / .cgr

Skeleton read_cg(const Context& ctx, const std::vector<TextLine>& lines, bool radius_required) {
    require_content(ctx, lines);
    std::size_t i = 0;
    while (is_blank(lines[i].text)) ++i;
    const TextLine& header = lines[i++];
    std::string h(header.text);
    std::replace(h.begin(), h.end(), ':', ' ');
    const std::vector<std::string_view> ht = split_whitespace(h);
    int nv = -1, ne = -1;
    if (ht.empty() || ht[0].front() != '#') ctx.fail(header.number, "malformed header: expected '# D:3 NV:<n> NE:<m>'");
    for (std::size_t k = 0; k + 1 < ht.size(); ++k) {
        if (ht[k] == "NV") nv = ctx.non_negative(ht[k + 1], header.number, "NV");
        if (ht[k] == "NE") ne = ctx.non_negative(ht[k + 1], header.number, "NE");
    }
    if (nv < 0 || ne < 0) ctx.fail(header.number, "malformed header: expected '# D:3 NV:<n> NE:<m>'");

    Parsed p;
    // .cgr: a radius on every 'v' line. .cg: a 4th value is taken as the radius only if every 'v' line has one (real
    // .cg files mix 3- and 4-value lines; then the 4th values are ignored).
    bool all_have_radius = true;
    std::vector<std::string_view> tok;  // the tokens of the current line
    for (; i < lines.size(); ++i) {
        const TextLine& l = lines[i];
        const std::string_view t = trim_left(l.text);
        if (t.empty() || t.front() == '#') continue;
        split_whitespace(t, tok);
        if (tok[0] == "v") {
            if (tok.size() != 4 && tok.size() != 5)
                ctx.fail(l.number, radius_required ? "expected 'v x y z r'" : "expected 'v x y z [r]'");
            if (radius_required && tok.size() != 5) ctx.fail(l.number, "expected 'v x y z r' (radius missing)");
            p.s.points.push_back({ctx.number(tok[1], l.number, "x"), ctx.number(tok[2], l.number, "y"),
                                  ctx.number(tok[3], l.number, "z")});
            if (tok.size() == 5) {
                p.s.radii.push_back(ctx.number(tok[4], l.number, "radius"));
                p.radius_line.push_back(l.number);
            } else {
                all_have_radius = false;
            }
        } else if (tok[0] == "e") {
            if (tok.size() != 3) ctx.fail(l.number, "expected 'e i j'");
            p.s.edges.push_back({ctx.non_negative(tok[1], l.number, "vertex index"),
                                 ctx.non_negative(tok[2], l.number, "vertex index")});
            p.edge_line.push_back(l.number);
        } else {
            ctx.fail(l.number, "unknown line '" + quote_excerpt(tok[0]) + "' (expected 'v' or 'e')");
        }
    }
    if (!all_have_radius) p.s.radii.clear(), p.radius_line.clear();
    const int last = last_line_number(lines);
    if (static_cast<int>(p.s.points.size()) != nv)
        ctx.fail(last, "header declares NV " + std::to_string(nv) + " but the file has " +
                           std::to_string(p.s.points.size()) + " 'v' lines");
    if (static_cast<int>(p.s.edges.size()) != ne)
        ctx.fail(last, "header declares NE " + std::to_string(ne) + " but the file has " +
                           std::to_string(p.s.edges.size()) + " 'e' lines");
    return finalize(ctx, std::move(p));
}

// ------------------------------------------------------------------------------------------------ .skel

Skeleton read_skel(const Context& ctx, const std::vector<TextLine>& lines) {
    require_content(ctx, lines);
    // Line 1 is a free-text header (ignored: real files have it truncated). Then the count, then one line per node.
    std::size_t i = 1;
    while (i < lines.size() && is_blank(lines[i].text)) ++i;
    if (i >= lines.size()) ctx.fail(last_line_number(lines), "truncated file: missing the node count");
    const TextLine& count_line = lines[i++];
    const std::vector<std::string_view> ct = split_whitespace(count_line.text);
    if (ct.size() != 1) ctx.fail(count_line.number, "expected the node count alone on the line");
    const int count = ctx.non_negative(ct[0], count_line.number, "node count");

    struct Node {
        long long id;
        int line;
        std::vector<long long> neighbours;
    };
    std::vector<Node> nodes;
    Parsed p;
    std::map<long long, int> row_of;
    for (; i < lines.size(); ++i) {
        const TextLine& l = lines[i];
        if (is_blank(l.text)) continue;
        const std::vector<std::string_view> tok = split_whitespace(l.text);
        if (static_cast<int>(nodes.size()) == count)
            ctx.fail(l.number, "more node lines than the declared count " + std::to_string(count));
        if (tok.size() < 6) ctx.fail(l.number, "expected 'id x y z radius k n1 ... nk'");
        Node node{ctx.integer(tok[0], l.number, "node id"), l.number, {}};
        const Vec3 x{ctx.number(tok[1], l.number, "x"), ctx.number(tok[2], l.number, "y"),
                     ctx.number(tok[3], l.number, "z")};
        const double r = ctx.number(tok[4], l.number, "radius");
        const int k = ctx.non_negative(tok[5], l.number, "neighbour count");
        if (tok.size() != 6 + static_cast<std::size_t>(k))
            ctx.fail(l.number, "neighbour count says " + std::to_string(k) + " but the line lists " +
                                   std::to_string(tok.size() - 6));
        for (int j = 0; j < k; ++j) node.neighbours.push_back(ctx.integer(tok[6 + j], l.number, "neighbour id"));
        if (!row_of.emplace(node.id, static_cast<int>(nodes.size())).second)
            ctx.fail(l.number, "duplicate node id " + std::to_string(node.id));
        p.s.points.push_back(x);
        p.s.radii.push_back(r);
        p.radius_line.push_back(l.number);
        nodes.push_back(std::move(node));
    }
    if (static_cast<int>(nodes.size()) != count)
        ctx.fail(last_line_number(lines), "truncated file: the count says " + std::to_string(count) + " nodes but " +
                                              std::to_string(nodes.size()) + " are listed");
    for (std::size_t v = 0; v < nodes.size(); ++v) {
        for (const long long nb : nodes[v].neighbours) {
            const auto it = row_of.find(nb);
            if (it == row_of.end())
                ctx.fail(nodes[v].line, "neighbour id " + std::to_string(nb) + " is not the id of any node");
            if (it->second == static_cast<int>(v))
                ctx.fail(nodes[v].line, "node " + std::to_string(nodes[v].id) + " lists itself as a neighbour");
            p.s.edges.push_back({static_cast<int>(v), it->second});  // duplicates dropped in finalize
            p.edge_line.push_back(nodes[v].line);
        }
    }
    return finalize(ctx, std::move(p));
}

// ------------------------------------------------------------------------------------------------ .ig

struct Token {
    std::string_view text;
    int line;
};

// Sorts a face's edges into a closed cycle and returns its vertices. The face is traversed so that its first listed
// edge comes first and the second listed edge follows it (when the edges are listed in cycle order, that order is
// kept); the remaining edges are chained from there. Linear in the face size: each step looks up the unused face
// edges at the current vertex in a (vertex, local edge) table sorted once, instead of rescanning the whole face.
std::vector<int> face_cycle(const Context& ctx, const std::vector<std::array<int, 2>>& edges,
                            const std::vector<int>& face_edges, int line) {
    const std::size_t k = face_edges.size();
    std::array<int, 2> first = edges[face_edges[0]];
    const std::array<int, 2> second = edges[face_edges[1]];
    const auto touches = [](const std::array<int, 2>& e, int v) { return e[0] == v || e[1] == v; };
    if (touches(second, first[0]) && !touches(second, first[1])) std::swap(first[0], first[1]);
    // (vertex, local edge j) for both ends of every face edge; sorted so that the edges at a vertex are contiguous
    // and in listing order (the first unused one is taken, as the listing-order scan did).
    std::vector<std::pair<int, int>> at;
    at.reserve(2 * k);
    for (std::size_t j = 0; j < k; ++j)
        for (const int v : edges[face_edges[j]]) at.emplace_back(v, static_cast<int>(j));
    std::sort(at.begin(), at.end());
    std::vector<std::size_t> cursor(at.size());  // per vertex group start: next candidate to look at
    std::vector<bool> used(k, false);
    used[0] = true;
    std::vector<int> cycle{first[0], first[1]};
    int current = first[1];
    for (std::size_t step = 1; step < k; ++step) {
        std::size_t i =
            static_cast<std::size_t>(std::lower_bound(at.begin(), at.end(), std::make_pair(current, -1)) - at.begin());
        const std::size_t group = i;
        i = std::max(i, cursor[group]);
        while (i < at.size() && at[i].first == current && used[static_cast<std::size_t>(at[i].second)]) ++i;
        cursor[group] = i;  // every entry before i at this vertex is used: never looked at again
        if (i == at.size() || at[i].first != current) ctx.fail(line, "face edges do not form a single closed cycle");
        const std::size_t j = static_cast<std::size_t>(at[i].second);
        used[j] = true;
        const std::array<int, 2>& e = edges[face_edges[j]];
        current = e[0] == current ? e[1] : e[0];
        if (step + 1 < k) cycle.push_back(current);
    }
    if (current != first[0]) ctx.fail(line, "face edges do not form a single closed cycle");
    return cycle;  // repeated vertices are reported by finalize()
}

Skeleton read_ig(const Context& ctx, const std::vector<TextLine>& lines) {
    require_content(ctx, lines);
    std::vector<Token> tokens;
    std::map<int, std::pair<double, int>> radius_of;
    std::vector<std::string_view> scratch;
    for (const TextLine& l : lines) {
        std::string_view t = l.text;
        const std::size_t hash = t.find('#');
        if (hash != std::string_view::npos) {
            parse_radius_comment(ctx, t.substr(hash + 1), l.number, 0, radius_of, scratch);
            t = t.substr(0, hash);
        }
        for (const std::string_view tok : split_whitespace(t)) tokens.push_back({tok, l.number});
    }
    const int last = last_line_number(lines);
    std::size_t pos = 0;
    const auto next = [&](const char* what) -> const Token& {
        if (pos >= tokens.size()) ctx.fail(last, std::string("unexpected end of file: expected ") + what);
        return tokens[pos++];
    };
    const Token& magic = next("'IG'");
    if (magic.text != "IG") ctx.fail(magic.line, "expected 'IG' at the start of the file");
    const Token& tnv = next("the vertex count");
    const int nv = ctx.non_negative(tnv.text, tnv.line, "vertex count");
    const Token& tne = next("the edge count");
    const int ne = ctx.non_negative(tne.text, tne.line, "edge count");
    const Token& tnf = next("the face count");
    const int nf = ctx.non_negative(tnf.text, tnf.line, "face count");

    Parsed p;
    for (int v = 0; v < nv; ++v) {
        Vec3 x;
        for (int c = 0; c < 3; ++c) {
            const Token& t = next("a vertex coordinate");
            x[c] = ctx.number(t.text, t.line, "coordinate");
        }
        p.s.points.push_back(x);
    }
    for (int e = 0; e < ne; ++e) {
        const Token& a = next("an edge vertex");
        const Token& b = next("an edge vertex");
        p.s.edges.push_back(
            {ctx.non_negative(a.text, a.line, "vertex index"), ctx.non_negative(b.text, b.line, "vertex index")});
        p.edge_line.push_back(b.line);
    }
    // Range-check edges now: faces refer to them.
    for (std::size_t e = 0; e < p.s.edges.size(); ++e)
        for (const int v : p.s.edges[e])
            if (v >= nv)
                ctx.fail(p.edge_line[e], "edge names vertex " + std::to_string(v) + " but there are " +
                                             std::to_string(nv) + " vertices (0-based)");
    for (int f = 0; f < nf; ++f) {
        const Token& tk = next("a face edge count");
        const int k = ctx.non_negative(tk.text, tk.line, "face edge count");
        if (k < 3) ctx.fail(tk.line, "face with fewer than 3 edges");
        std::vector<int> face_edges;
        for (int j = 0; j < k; ++j) {
            const Token& t = next("a face edge index");
            const int e = ctx.non_negative(t.text, t.line, "edge index");
            if (e >= ne)
                ctx.fail(t.line, "face names edge " + std::to_string(e) + " but there are " + std::to_string(ne) +
                                     " edges (0-based)");
            face_edges.push_back(e);
        }
        p.s.faces.push_back(face_cycle(ctx, p.s.edges, face_edges, tk.line));
        p.face_line.push_back(tk.line);
    }
    if (pos < tokens.size())
        ctx.fail(tokens[pos].line, "unexpected content after the last face ('" + quote_excerpt(tokens[pos].text) +
                                       "'): do the counts in the header match the file?");
    apply_radius_comments(ctx, radius_of, p, last, 0);
    return finalize(ctx, std::move(p));
}

// ------------------------------------------------------------------------------------------------ .obj

Skeleton read_obj(const Context& ctx, const std::vector<TextLine>& lines) {
    require_content(ctx, lines);
    Parsed p;
    std::map<int, std::pair<double, int>> radius_of;
    // Resolves an OBJ vertex reference ("7", "7/2", "7//3", "-1/...") to a 0-based index.
    const auto index = [&](std::string_view tok, int line) {
        const std::string_view head = tok.substr(0, tok.find('/'));
        const long long i = ctx.integer(head, line, "vertex index");
        const long long n = static_cast<long long>(p.s.points.size());
        if (i == 0) ctx.fail(line, "vertex index 0 (OBJ indices start at 1)");
        const long long v = i > 0 ? i - 1 : n + i;
        if (v < 0 || v > 2147483647LL)
            ctx.fail(line, "vertex index " + quote_excerpt(head) + " does not name a vertex");
        return static_cast<int>(v);
    };
    std::vector<std::string_view> tok;  // the tokens of the current line
    for (const TextLine& l : lines) {
        const std::string_view t = trim_left(l.text);
        if (t.empty()) continue;
        if (t.front() == '#') {
            parse_radius_comment(ctx, t.substr(1), l.number, 1, radius_of, tok);
            continue;
        }
        split_whitespace(t, tok);
        if (tok[0] == "v") {
            if (tok.size() < 4) ctx.fail(l.number, "expected 'v x y z'");
            p.s.points.push_back({ctx.number(tok[1], l.number, "x"), ctx.number(tok[2], l.number, "y"),
                                  ctx.number(tok[3], l.number, "z")});
        } else if (tok[0] == "l") {
            if (tok.size() < 3) ctx.fail(l.number, "a polyline needs at least 2 vertices");
            int prev = index(tok[1], l.number);
            for (std::size_t j = 2; j < tok.size(); ++j) {
                const int v = index(tok[j], l.number);
                p.s.edges.push_back({prev, v});
                p.edge_line.push_back(l.number);
                prev = v;
            }
        } else if (tok[0] == "f") {
            if (tok.size() < 4) ctx.fail(l.number, "a face needs at least 3 vertices");
            std::vector<int> face;
            face.reserve(tok.size() - 1);
            for (std::size_t j = 1; j < tok.size(); ++j) face.push_back(index(tok[j], l.number));
            p.s.faces.push_back(std::move(face));
            p.face_line.push_back(l.number);
        }
        // Every other statement (vt, vn, o, g, s, usemtl, mtllib, ...) is ignored.
    }
    if (p.s.points.empty()) ctx.fail(last_line_number(lines), "no 'v' line: the file holds no vertex");
    apply_radius_comments(ctx, radius_of, p, last_line_number(lines), 1);
    // finalize() reports out-of-range indices 0-based; make OBJ messages 1-based by checking here first.
    const int n = static_cast<int>(p.s.points.size());
    for (std::size_t e = 0; e < p.s.edges.size(); ++e)
        for (const int v : p.s.edges[e])
            if (v >= n)
                ctx.fail(p.edge_line[e], "polyline names vertex " + std::to_string(v + 1) + " but there are " +
                                             std::to_string(n) + " vertices");
    for (std::size_t f = 0; f < p.s.faces.size(); ++f)
        for (const int v : p.s.faces[f])
            if (v >= n)
                ctx.fail(p.face_line[f], "face names vertex " + std::to_string(v + 1) + " but there are " +
                                             std::to_string(n) + " vertices");
    return finalize(ctx, std::move(p));
}

// ------------------------------------------------------------------------------------------------ writers

// Shortest text that reads back to exactly the same double.
void put(std::string& out, double x) {
    char buf[64];
    const std::to_chars_result r = std::to_chars(buf, buf + sizeof buf, x);
    out.append(buf, r.ptr);
}

void check_writable(const std::string& path, const Skeleton& s) {
    const int n = static_cast<int>(s.points.size());
    const auto bad = [&](const std::string& what) { throw Error(ErrorCode::InvalidInput, path + ": " + what); };
    if (!s.radii.empty() && static_cast<int>(s.radii.size()) != n) bad("radius count differs from vertex count");
    for (const Vec3& x : s.points)
        if (!is_finite(x)) bad("non-finite vertex position");
    for (const double r : s.radii)
        if (!std::isfinite(r)) bad("non-finite radius");
    for (const std::array<int, 2>& e : s.edges)
        if (e[0] < 0 || e[0] >= n || e[1] < 0 || e[1] >= n) bad("edge index out of range");
    for (const std::vector<int>& f : s.faces)
        for (const int v : f)
            if (v < 0 || v >= n) bad("face index out of range");
}

void put_radius_comments(std::string& out, const Skeleton& s, int index_base) {
    for (std::size_t v = 0; v < s.radii.size(); ++v) {
        out += "# mesohex radius ";
        out += std::to_string(static_cast<long long>(v) + index_base);
        out += ' ';
        put(out, s.radii[v]);
        out += '\n';
    }
}

std::string format_ig(const std::string& path, const Skeleton& s) {
    std::map<std::pair<int, int>, int> edge_of;
    for (std::size_t e = 0; e < s.edges.size(); ++e)
        edge_of.emplace(std::minmax(s.edges[e][0], s.edges[e][1]), static_cast<int>(e));
    std::string out = "IG\n";
    out += std::to_string(s.points.size()) + " " + std::to_string(s.edges.size()) + " " +
           std::to_string(s.faces.size()) + "\n";
    for (const Vec3& x : s.points) {
        put(out, x.x), out += ' ', put(out, x.y), out += ' ', put(out, x.z);
        out += '\n';
    }
    put_radius_comments(out, s, 0);
    for (const std::array<int, 2>& e : s.edges) out += std::to_string(e[0]) + " " + std::to_string(e[1]) + "\n";
    for (const std::vector<int>& f : s.faces) {
        out += std::to_string(f.size());
        for (std::size_t i = 0; i < f.size(); ++i) {
            const auto it = edge_of.find(std::minmax(f[i], f[(i + 1) % f.size()]));
            if (it == edge_of.end())
                throw Error(ErrorCode::InvalidInput, path +
                                                         ": a face side is not in the edge list (.ig stores "
                                                         "faces as edge indices)");
            out += ' ' + std::to_string(it->second);
        }
        out += '\n';
    }
    return out;
}

std::string format_obj(const Skeleton& s) {
    std::string out = "# mesohex skeleton: 'l' = edges (leaflet sides included), 'f' = leaflet faces\n";
    for (const Vec3& x : s.points) {
        out += "v ";
        put(out, x.x), out += ' ', put(out, x.y), out += ' ', put(out, x.z);
        out += '\n';
    }
    put_radius_comments(out, s, 1);
    for (const std::array<int, 2>& e : s.edges)
        out += "l " + std::to_string(e[0] + 1) + " " + std::to_string(e[1] + 1) + "\n";
    for (const std::vector<int>& f : s.faces) {
        out += 'f';
        for (const int v : f) out += ' ' + std::to_string(v + 1);
        out += '\n';
    }
    return out;
}

// ------------------------------------------------------------------------------------------------ binary (MHSK)

constexpr char kBinaryMagic[4] = {'M', 'H', 'S', 'K'};
constexpr std::uint32_t kBinaryVersion = 1;
constexpr std::size_t kBinaryHeader = 32;  // magic + 7 uint32

std::uint32_t load_u32(const char* at) {
    std::uint32_t x = 0;
    for (int k = 3; k >= 0; --k) x = x << 8 | static_cast<unsigned char>(at[k]);
    return x;
}

double load_f64(const char* at) {
    std::uint64_t x = 0;
    for (int k = 7; k >= 0; --k) x = x << 8 | static_cast<unsigned char>(at[k]);
    return std::bit_cast<double>(x);
}

void store_u32(std::string& out, std::uint32_t x) {
    for (int k = 0; k < 4; ++k) out += static_cast<char>((x >> (8 * k)) & 0xffu);
}

void store_f64(std::string& out, double v) {
    const std::uint64_t x = std::bit_cast<std::uint64_t>(v);
    for (int k = 0; k < 8; ++k) out += static_cast<char>((x >> (8 * k)) & 0xffu);
}

[[noreturn]] void binary_fail(std::string_view name, const std::string& what, ElementRef where = {}) {
    throw Error(ErrorCode::InvalidInput, std::string(name) + ": " + what, where);
}

// The counts of the header, checked against the length before anything is allocated.
struct BinaryCounts {
    std::uint32_t v = 0, r = 0, e = 0, f = 0, s = 0;
};

BinaryCounts binary_counts(std::string_view bytes, std::string_view name) {
    if (bytes.size() < kBinaryHeader || std::memcmp(bytes.data(), kBinaryMagic, 4) != 0)
        binary_fail(name, "not a binary skeleton (expected the 32-byte MHSK header)");
    const char* h = bytes.data();
    if (load_u32(h + 4) != kBinaryVersion)
        binary_fail(name, "byte 4: unknown binary skeleton version " + std::to_string(load_u32(h + 4)));
    BinaryCounts c{load_u32(h + 8), load_u32(h + 12), load_u32(h + 16), load_u32(h + 20), load_u32(h + 24)};
    if (load_u32(h + 28) != 0) binary_fail(name, "byte 28: reserved word is not 0");
    if (c.v > 2147483647u) binary_fail(name, "byte 8: vertex count out of range");
    if (c.r != 0 && c.r != c.v)
        binary_fail(name, "byte 12: " + std::to_string(c.r) + " radii for " + std::to_string(c.v) +
                              " vertices (expected none or one per vertex)");
    const std::uint64_t need = kBinaryHeader + 24ull * c.v + 8ull * c.r + 8ull * c.e + 4ull * c.f + 4ull * c.s;
    if (need != bytes.size())
        binary_fail(name, "length " + std::to_string(bytes.size()) + " bytes, the header's counts need " +
                              std::to_string(need));
    return c;
}

int binary_index(const char* at, std::uint32_t n_points, std::string_view name, const char* what, ElementRef where) {
    const std::uint32_t i = load_u32(at);
    if (i >= n_points)
        binary_fail(name,
                    std::string(what) + " names vertex " + std::to_string(i) + " but there are " +
                        std::to_string(n_points) + " vertices (0-based)",
                    where);
    return static_cast<int>(i);
}

}  // namespace

Skeleton read_skeleton_binary(std::string_view bytes, std::string_view name) {
    const BinaryCounts c = binary_counts(bytes, name);
    const char* at = bytes.data() + kBinaryHeader;
    Skeleton s;
    s.points.resize(c.v);
    for (std::uint32_t v = 0; v < c.v; ++v, at += 24) {
        const Vec3 p{load_f64(at), load_f64(at + 8), load_f64(at + 16)};
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            binary_fail(name, "vertex " + std::to_string(v) + " has a non-finite coordinate",
                        {ElementRef::Kind::SkeletonVertex, static_cast<int>(v)});
        s.points[v] = p;
    }
    s.radii.resize(c.r);
    for (std::uint32_t v = 0; v < c.r; ++v, at += 8) {
        s.radii[v] = load_f64(at);
        if (!(s.radii[v] > 0) || !std::isfinite(s.radii[v]))
            binary_fail(name, "radius of vertex " + std::to_string(v) + " must be positive and finite",
                        {ElementRef::Kind::SkeletonVertex, static_cast<int>(v)});
    }
    s.edges.resize(c.e);
    for (std::uint32_t e = 0; e < c.e; ++e, at += 8) {
        const ElementRef where{ElementRef::Kind::SkeletonEdge, static_cast<int>(e)};
        const std::string what = "edge " + std::to_string(e);
        s.edges[e] = {binary_index(at, c.v, name, what.c_str(), where),
                      binary_index(at + 4, c.v, name, what.c_str(), where)};
        if (s.edges[e][0] == s.edges[e][1]) binary_fail(name, what + " is a self-loop", where);
    }
    s.edges = without_repeated_edges(s.edges, static_cast<int>(c.v));
    const char* verts = at + 4ull * c.f;
    std::uint64_t used = 0;
    s.faces.resize(c.f);
    for (std::uint32_t f = 0; f < c.f; ++f, at += 4) {
        const ElementRef where{ElementRef::Kind::SkeletonFace, static_cast<int>(f)};
        const std::string what = "face " + std::to_string(f);
        const std::uint32_t size = load_u32(at);
        if (size < 3) binary_fail(name, what + " has fewer than 3 vertices", where);
        if (size > c.s - used)
            binary_fail(name, "face sizes add up to more than the header's " + std::to_string(c.s) + " face vertices",
                        where);
        s.faces[f].resize(size);
        for (std::uint32_t k = 0; k < size; ++k)
            s.faces[f][k] = binary_index(verts + 4 * (used + k), c.v, name, what.c_str(), where);
        used += size;
        if (repeats_a_vertex(s.faces[f])) binary_fail(name, what + " repeats a vertex", where);
    }
    if (used != c.s)
        binary_fail(name, "face sizes add up to " + std::to_string(used) + ", the header says " + std::to_string(c.s));
    add_face_edges(s);
    return s;
}

std::string skeleton_binary(const Skeleton& skeleton) {
    std::uint64_t corners = 0;
    for (const std::vector<int>& f : skeleton.faces) corners += f.size();
    std::string out(kBinaryMagic, 4);
    out.reserve(kBinaryHeader + 24 * skeleton.points.size() + 8 * skeleton.radii.size() + 8 * skeleton.edges.size() +
                4 * (skeleton.faces.size() + corners));
    for (const std::uint64_t x :
         {std::uint64_t{kBinaryVersion}, std::uint64_t{skeleton.points.size()}, std::uint64_t{skeleton.radii.size()},
          std::uint64_t{skeleton.edges.size()}, std::uint64_t{skeleton.faces.size()}, corners, std::uint64_t{0}})
        store_u32(out, static_cast<std::uint32_t>(x));
    for (const Vec3& p : skeleton.points) store_f64(out, p.x), store_f64(out, p.y), store_f64(out, p.z);
    for (const double r : skeleton.radii) store_f64(out, r);
    for (const std::array<int, 2>& e : skeleton.edges)
        store_u32(out, static_cast<std::uint32_t>(e[0])), store_u32(out, static_cast<std::uint32_t>(e[1]));
    for (const std::vector<int>& f : skeleton.faces) store_u32(out, static_cast<std::uint32_t>(f.size()));
    for (const std::vector<int>& f : skeleton.faces)
        for (const int v : f) store_u32(out, static_cast<std::uint32_t>(v));
    return out;
}

namespace {

bool is_skeleton_format(const std::string& ext) {
    return ext == "ig" || ext == "cg" || ext == "cgr" || ext == "skel" || ext == "obj";
}

// The text of a skeleton file in format `ext` (one of is_skeleton_format), named by `ctx` in messages.
Skeleton parse_skeleton(const Context& ctx, const std::string& ext, std::string_view content) {
    if (is_blank_content(content)) fail_empty_file(ctx.file(), "expected a skeleton");
    if (content.find('\0') != std::string_view::npos) ctx.fail(1, "binary content (NUL byte) in a text format");
    const std::vector<TextLine> lines = split_lines(content);
    if (ext == "ig") return read_ig(ctx, lines);
    if (ext == "cg") return read_cg(ctx, lines, false);
    if (ext == "cgr") return read_cg(ctx, lines, true);
    if (ext == "skel") return read_skel(ctx, lines);
    return read_obj(ctx, lines);
}

}  // namespace

Skeleton read_skeleton(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (!is_skeleton_format(ext))
        throw Error(ErrorCode::InvalidInput,
                    path + ": unknown skeleton format '." + ext + "' (expected .ig, .cg, .cgr, .skel or .obj)");
    return parse_skeleton(Context(path), ext, read_whole_file(path));
}

void write_skeleton(const std::string& path, const Skeleton& skeleton) {
    const std::string ext = lower_extension(path);
    if (ext != "ig" && ext != "obj")
        throw Error(ErrorCode::InvalidInput, path + ": cannot write skeleton format '." + ext + "' (use .ig or .obj)");
    check_writable(path, skeleton);
    write_file_atomically(path, ext == "ig" ? format_ig(path, skeleton) : format_obj(skeleton));
}

Skeleton read_skeleton_text(std::string_view content, std::string_view format, std::string_view name) {
    std::string ext(format);
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == "mhsk") return read_skeleton_binary(content, name);
    if (!is_skeleton_format(ext))
        throw Error(ErrorCode::InvalidInput, std::string(name) + ": unknown skeleton format '" + quote_excerpt(format) +
                                                 "' (expected ig, cg, cgr, skel, obj or mhsk)");
    return parse_skeleton(Context(std::string(name)), ext, content);
}

std::string skeleton_text(const Skeleton& skeleton, const std::string& format, const std::string& name) {
    const std::string ext = lower_extension("." + format);
    if (ext != "ig" && ext != "obj")
        throw Error(ErrorCode::InvalidInput, name + ": cannot write skeleton format '" + format + "' (use ig or obj)");
    check_writable(name, skeleton);
    return ext == "ig" ? format_ig(name, skeleton) : format_obj(skeleton);
}

}  // namespace mesohex
