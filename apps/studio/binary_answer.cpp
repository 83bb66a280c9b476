#include "binary_answer.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace mesohex::studio {

namespace {

constexpr char kMagic[4] = {'M', 'H', 'X', 'B'};

std::uint32_t get_u32_le(const std::string& in, std::size_t at) {
    return static_cast<std::uint32_t>(static_cast<unsigned char>(in[at])) |
           static_cast<std::uint32_t>(static_cast<unsigned char>(in[at + 1])) << 8 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(in[at + 2])) << 16 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(in[at + 3])) << 24;
}

std::uint32_t f32_bits(double x) { return std::bit_cast<std::uint32_t>(static_cast<float>(x)); }

[[noreturn]] void malformed(const std::string& what) { throw std::invalid_argument("binary answer: " + what); }

}  // namespace

void put_u32_le(std::string& out, std::uint32_t x) {
    const char b[4] = {static_cast<char>(x & 0xffu), static_cast<char>((x >> 8) & 0xffu),
                       static_cast<char>((x >> 16) & 0xffu), static_cast<char>((x >> 24) & 0xffu)};
    out.append(b, 4);
}

char* grow(std::string& out, std::size_t n) {
    const std::size_t at = out.size();
    out.resize(at + n);
    return out.data() + at;
}

void append_f32(BinaryArrays& arrays, const std::string& name, const std::vector<double>& values) {
    char* at = grow(arrays.bytes, 4 * values.size());
    for (const double x : values) store_u32_le(at, f32_bits(x)), at += 4;
    arrays.list.push_back({{"name", name}, {"type", "f32"}, {"count", values.size()}});
}

void append_f32(BinaryArrays& arrays, const std::string& name, const std::vector<Vec3>& points) {
    char* at = grow(arrays.bytes, 12 * points.size());
    for (const Vec3& p : points) {
        store_u32_le(at, f32_bits(p.x)), store_u32_le(at + 4, f32_bits(p.y)), store_u32_le(at + 8, f32_bits(p.z));
        at += 12;
    }
    arrays.list.push_back({{"name", name}, {"type", "f32"}, {"count", 3 * points.size()}});
}

void append_enum(BinaryArrays& arrays, const std::string& name, const std::vector<const char*>& strings) {
    std::vector<std::string> names;
    char* at = grow(arrays.bytes, 4 * strings.size());
    for (const char* str : strings) {
        std::size_t code = 0;
        while (code < names.size() && names[code] != str) ++code;  // a handful of names
        if (code == names.size()) names.emplace_back(str);
        store_u32_le(at, static_cast<std::uint32_t>(code)), at += 4;
    }
    arrays.list.push_back({{"name", name}, {"type", "enum"}, {"count", strings.size()}, {"names", names}});
}

std::string binary_answer(nlohmann::json header, const BinaryArrays& arrays) {
    header.erase("arrays");
    return binary_answer_text(header.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), arrays);
}

std::string binary_answer_text(std::string text, const BinaryArrays& arrays) {
    while (!text.empty() && text.back() != '}') text.pop_back();
    if (text.size() < 2 || text.front() != '{') throw std::invalid_argument("binary answer: header is not an object");
    text.pop_back();
    if (text.find_first_not_of(" \t\r\n", 1) != std::string::npos) text += ',';
    text += "\"arrays\":" + arrays.list.dump() + '}';
    text.append((4 - text.size() % 4) % 4, ' ');
    std::string out;
    out.reserve(12 + text.size() + arrays.bytes.size());
    out.append(kMagic, 4);
    put_u32_le(out, kBinaryAnswerVersion);
    put_u32_le(out, static_cast<std::uint32_t>(text.size()));
    out += text;
    out += arrays.bytes;
    return out;
}

namespace {
std::size_t index_of_name(const DecodedAnswer& d, const std::string& name) {
    for (std::size_t i = 0; i < d.names.size(); ++i)
        if (d.names[i] == name) return i;
    return d.names.size();
}
}  // namespace

const std::vector<RowLayout>& mesh_answer_row_layouts() {
    static const std::vector<RowLayout> layouts = {
        {"mesh.vertices", 3, "", 0},
        {"mesh.hexes", 8, "mesh.vertices", 8},
        {"mesh.sj", 1, "", 0},
        {"mesh.singular_edges", 3, "mesh.vertices", 2},
        {"mesh.boundary_quads", 4, "mesh.vertices", 4},
        {"mesh.boundary_hexes", 1, "mesh.hexes", 1},
        {"connection_surfaces.vertices", 3, "", 0},
        {"connection_surfaces.quads", 4, "connection_surfaces.vertices", 4},
    };
    return layouts;
}

namespace {

constexpr std::uint32_t kNoRow = 0xffffffffu;  // a literal run's source; a base row no new row copies

// Which new row each base row of a row-patched array went to (kNoRow: none); empty when the array was not
// row-patched (its row numbers then stay as they are).
struct RowMap {
    bool row_patched = false;
    std::vector<std::uint32_t> to_new;
    std::uint32_t operator()(std::uint32_t v) const {
        if (!row_patched) return v;
        return v < to_new.size() ? to_new[v] : kNoRow;
    }
};

std::vector<std::uint32_t> read_u32s(const char* at, std::size_t n) {
    std::vector<std::uint32_t> out(n);
    if constexpr (std::endian::native == std::endian::little) {
        if (n) std::memcpy(out.data(), at, 4 * n);
        return out;
    }
    for (std::size_t i = 0; i < n; ++i, at += 4)
        out[i] = static_cast<std::uint32_t>(static_cast<unsigned char>(at[0])) |
                 static_cast<std::uint32_t>(static_cast<unsigned char>(at[1])) << 8 |
                 static_cast<std::uint32_t>(static_cast<unsigned char>(at[2])) << 16 |
                 static_cast<std::uint32_t>(static_cast<unsigned char>(at[3])) << 24;
    return out;
}

std::uint64_t row_hash(const std::uint32_t* row, std::size_t w) {
    std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the words
    for (std::size_t c = 0; c < w; ++c) h = (h ^ row[c]) * 1099511628211ull;
    // FNV's low bits depend only on the words' low bits, which are all zero for coordinates on a dyadic grid (a plate
    // of unit quads): every row would probe from the same slot. A final avalanche (murmur3's fmix64) spreads them.
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    h ^= h >> 33;
    return h;
}

struct RowPatch {
    std::vector<std::uint32_t> runs;     // (length, source) pairs
    std::vector<std::uint32_t> literal;  // the literal rows' values
    RowMap map;
    std::size_t bytes() const { return 4 * (runs.size() + literal.size()); }
};

// `now` (new_rows x w values) as runs of base rows (`old`, translated by `ref` in its first ref_columns values) and
// literal rows.
RowPatch row_patch(std::vector<std::uint32_t> old, const std::vector<std::uint32_t>& now, const RowLayout& layout,
                   const RowMap& ref) {
    const std::size_t w = layout.width, old_rows = old.size() / w, new_rows = now.size() / w;
    for (std::size_t r = 0; r < old_rows; ++r)
        for (std::size_t c = 0; c < layout.ref_columns; ++c) old[r * w + c] = ref(old[r * w + c]);
    const auto same = [&](std::size_t s, std::size_t i) { return std::memcmp(&old[s * w], &now[i * w], 4 * w) == 0; };
    // The translated base rows by content: an open-addressing table (linear probing) of row numbers, the first row
    // of each content kept (an unordered_map took 8 ms for the 145 k rows of a 12 k-hex tree answer); built at the
    // first row the runs' own continuations do not find (row 0 always: there is no run to continue yet).
    std::vector<std::uint32_t> table;
    std::size_t mask = 0;
    const auto build = [&] {
        std::size_t slots = 2;
        while (slots < 2 * old_rows) slots *= 2;
        table.assign(slots, kNoRow);
        mask = slots - 1;
        for (std::size_t r = 0; r < old_rows; ++r)
            for (std::size_t k = row_hash(&old[r * w], w) & mask;; k = (k + 1) & mask) {
                if (table[k] == kNoRow) {
                    table[k] = static_cast<std::uint32_t>(r);
                    break;
                }
                if (std::memcmp(&old[table[k] * w], &old[r * w], 4 * w) == 0) break;  // the same: keep the first
            }
    };
    const auto find = [&](std::size_t i) {
        if (table.empty()) build();
        for (std::size_t k = row_hash(&now[i * w], w) & mask;; k = (k + 1) & mask)
            if (table[k] == kNoRow || same(table[k], i)) return table[k];
    };
    RowPatch p;
    p.map.row_patched = true;
    p.map.to_new.assign(old_rows, kNoRow);
    std::uint32_t previous = kNoRow;  // the source of row i - 1
    std::size_t last_copied = 0;      // the last row copied (when last_src is set) and its source
    std::uint32_t last_src = kNoRow;
    const auto fits = [&](std::size_t s, std::size_t i) { return s < old_rows && same(s, i); };
    for (std::size_t i = 0; i < new_rows; ++i) {
        // The run goes on (previous + 1), or after literal rows it resumes as if they replaced as many base rows, or
        // as if they were inserted; else the table.
        std::uint32_t src = kNoRow;
        if (previous != kNoRow) {
            if (fits(previous + std::size_t{1}, i)) src = previous + 1;
        } else if (last_src != kNoRow) {
            if (fits(last_src + (i - last_copied), i))
                src = static_cast<std::uint32_t>(last_src + (i - last_copied));
            else if (fits(last_src + std::size_t{1}, i))
                src = last_src + 1;
        }
        if (src == kNoRow) src = find(i);
        const std::size_t k = p.runs.size();
        const bool extends = k > 0 && (src == kNoRow ? p.runs[k - 1] == kNoRow
                                                     : p.runs[k - 1] != kNoRow && src == p.runs[k - 1] + p.runs[k - 2]);
        if (extends) {
            ++p.runs[k - 2];
        } else {
            p.runs.push_back(1);
            p.runs.push_back(src);
        }
        if (src == kNoRow) {
            p.literal.insert(p.literal.end(), now.begin() + static_cast<std::ptrdiff_t>(i * w),
                             now.begin() + static_cast<std::ptrdiff_t>((i + 1) * w));
        } else {
            p.map.to_new[src] = static_cast<std::uint32_t>(i);
            last_src = src, last_copied = i;
        }
        previous = src;
    }
    return p;
}

}  // namespace

BinaryArrays patch_arrays(const BinaryArrays& base, const BinaryArrays& full, const std::vector<RowLayout>& layouts) {
    // Byte offset of each array of base, by name.
    std::vector<std::size_t> base_at;
    std::size_t at = 0;
    for (const nlohmann::json& a : base.list) base_at.push_back(at), at += 4 * a["count"].get<std::size_t>();
    std::vector<std::pair<std::string, RowMap>> maps;  // of the arrays written so far
    BinaryArrays out;
    at = 0;
    for (const nlohmann::json& a : full.list) {
        const std::size_t n = a["count"].get<std::size_t>();
        const char* values = full.bytes.data() + at;
        at += 4 * n;
        std::size_t b = 0;
        while (b < base.list.size() && base.list[b]["name"] != a["name"]) ++b;
        const bool comparable = b < base.list.size() && base.list[b]["type"] == a["type"] &&
                                base.list[b].value("names", nlohmann::json()) == a.value("names", nlohmann::json());
        bool patch = comparable && base.list[b]["count"] == a["count"];
        std::vector<std::uint32_t> changed;
        if (patch) {
            const char* old = base.bytes.data() + base_at[b];
            for (std::size_t i = 0; i < n && patch; ++i)
                if (std::memcmp(old + 4 * i, values + 4 * i, 4) != 0) {
                    changed.push_back(static_cast<std::uint32_t>(i));
                    patch = 2 * changed.size() < n;
                }
            if (n == 0) patch = true;
        }
        // A row patch when the value patch is impossible or not small (more than 1/64 of the values changed).
        const std::string name = a["name"].get<std::string>();
        const RowLayout* layout = nullptr;
        for (const RowLayout& l : layouts)
            if (l.name == name) layout = &l;
        const RowMap* ref = nullptr;
        if (layout && !layout->ref.empty())
            for (const auto& [m, map] : maps)
                if (m == layout->ref) ref = &map;
        const std::size_t base_n = comparable ? base.list[b]["count"].get<std::size_t>() : 0;
        RowPatch rows;
        bool row = false;
        if (layout && comparable && (layout->ref.empty() || ref) && n % layout->width == 0 &&
            base_n % layout->width == 0 && (!patch || 64 * changed.size() > n)) {
            static const RowMap identity;
            rows = row_patch(read_u32s(base.bytes.data() + base_at[b], base_n), read_u32s(values, n), *layout,
                             ref ? *ref : identity);
            row = rows.bytes() < (patch ? 8 * changed.size() : 4 * n);
        }
        nlohmann::json entry = a;
        if (row) {
            entry["width"] = layout->width;
            entry["rows"] = rows.runs.size() / 2;
            entry["literal"] = rows.literal.size() / layout->width;
            if (!layout->ref.empty()) entry["ref"] = layout->ref, entry["ref_columns"] = layout->ref_columns;
            char* w = grow(out.bytes, rows.bytes());
            for (const std::uint32_t x : rows.runs) store_u32_le(w, x), w += 4;
            for (const std::uint32_t x : rows.literal) store_u32_le(w, x), w += 4;
            maps.emplace_back(name, std::move(rows.map));
        } else {
            maps.emplace_back(name, RowMap{});
            if (!patch) {
                out.bytes.append(values, 4 * n);
            } else {
                entry["patch"] = changed.size();
                char* w = grow(out.bytes, 8 * changed.size());
                for (const std::uint32_t i : changed) store_u32_le(w, i), w += 4;
                for (const std::uint32_t i : changed)
                    std::memcpy(w, values + 4 * static_cast<std::size_t>(i), 4), w += 4;
            }
        }
        out.list.push_back(std::move(entry));
    }
    return out;
}

namespace {

// Decodes the row patch of entry `a` at `at` (advanced past it) into the last array of d (already named); records
// its row map (base row -> the last new row copied from it) in row_maps.
void read_row_patch(const std::string& in, std::size_t& at, const nlohmann::json& a, const DecodedAnswer* previous,
                    std::vector<std::pair<std::string, std::vector<std::uint32_t>>>& row_maps, DecodedAnswer& d) {
    const std::string& name = d.names.back();
    const auto number = [&](const char* key) {
        if (!a.contains(key) || !a[key].is_number_unsigned())
            malformed("row patch without \"" + std::string(key) + "\"");
        return a[key].get<std::size_t>();
    };
    const std::size_t n = number("count"), w = number("width"), k = number("rows"), lit = number("literal");
    const std::size_t r = a.contains("ref") ? number("ref_columns") : 0;
    const bool reals = a["type"] == "f32";
    if (!reals && a["type"] != "u32") malformed("row patch of a " + a["type"].dump() + " array");
    if (!previous || !previous->has(name))
        malformed("row patch of an array the previous answer does not have: " + name);
    if (w == 0 || n % w != 0 || r > w || (reals && r > 0)) malformed("row patch layout " + a.dump());
    // Divisions only (4 * w would wrap for a hostile width).
    if (k > (in.size() - at) / 8 || lit > (in.size() - at - 8 * k) / 4 / w) malformed(name + " runs past the end");
    const std::vector<std::uint32_t>* ref = nullptr;
    if (r > 0) {
        for (const auto& [m, map] : row_maps)
            if (a["ref"].is_string() && m == a["ref"].get<std::string>()) ref = &map;
        if (!ref && !(a["ref"].is_string() && d.has(a["ref"].get<std::string>())))
            malformed("row patch ref " + a.dump());
    }
    const std::size_t p = index_of_name(*previous, name);
    const std::vector<double>& old_reals = previous->f32[p];
    const std::vector<std::uint32_t>& old_ints = previous->u32[p];
    const std::size_t old_rows = (reals ? old_reals.size() : old_ints.size()) / w;
    std::vector<std::uint32_t> map(old_rows, kNoRow);
    std::vector<double>& out_reals = d.f32.back();
    std::vector<std::uint32_t>& out_ints = d.u32.back();
    const std::size_t literal_at = at + 8 * k;
    std::size_t row = 0, literal = 0;
    for (std::size_t run = 0; run < k; ++run) {
        const std::size_t len = get_u32_le(in, at + 8 * run), src = get_u32_le(in, at + 8 * run + 4);
        if (len > n / w - row) malformed("row patch of " + name + ": runs longer than the array");
        for (std::size_t j = 0; j < len; ++j, ++row) {
            if (src == kNoRow) {
                if (literal == lit) malformed("row patch of " + name + ": more literal rows than given");
                for (std::size_t c = 0; c < w; ++c) {
                    const std::uint32_t bits = get_u32_le(in, literal_at + 4 * (literal * w + c));
                    if (reals)
                        out_reals.push_back(static_cast<double>(std::bit_cast<float>(bits)));
                    else
                        out_ints.push_back(bits);
                }
                ++literal;
                continue;
            }
            if (src + j >= old_rows) malformed("row patch of " + name + ": source row out of range");
            map[src + j] = static_cast<std::uint32_t>(row);
            for (std::size_t c = 0; c < w; ++c) {
                if (reals) {
                    out_reals.push_back(old_reals[(src + j) * w + c]);
                    continue;
                }
                std::uint32_t v = old_ints[(src + j) * w + c];
                if (c < r && ref) v = v < ref->size() ? (*ref)[v] : kNoRow;
                out_ints.push_back(v);
            }
        }
    }
    if (row != n / w || literal != lit) malformed("row patch of " + name + ": rows do not add up");
    at = literal_at + 4 * w * lit;
    row_maps.emplace_back(name, std::move(map));
}

}  // namespace

DecodedAnswer decode_binary_answer(const std::string& in, const DecodedAnswer* previous) {
    if (in.size() < 12 || in.compare(0, 4, kMagic, 4) != 0) malformed("no MHXB magic");
    if (get_u32_le(in, 4) != kBinaryAnswerVersion) malformed("unknown version " + std::to_string(get_u32_le(in, 4)));
    const std::size_t h = get_u32_le(in, 8);
    if (h % 4 != 0 || 12 + h > in.size()) malformed("header size " + std::to_string(h));
    DecodedAnswer d;
    std::vector<std::pair<std::string, std::vector<std::uint32_t>>> row_maps;  // of the row-patched arrays
    d.header = nlohmann::json::parse(in.substr(12, h), nullptr, false);
    if (!d.header.is_object() || !d.header.contains("arrays") || !d.header["arrays"].is_array())
        malformed("header is not an object with \"arrays\"");
    std::size_t at = 12 + h;
    for (const nlohmann::json& a : d.header["arrays"]) {
        if (!a.is_object() || !a.contains("name") || !a.contains("type") || !a.contains("count") ||
            !a["count"].is_number_unsigned())
            malformed("array entry " + a.dump());
        const std::size_t n = a["count"].get<std::size_t>();
        d.names.push_back(a["name"].get<std::string>());
        d.f32.emplace_back();
        d.u32.emplace_back();
        if (a.contains("rows")) {  // runs of the previous answer's rows (translated) and literal rows
            read_row_patch(in, at, a, previous, row_maps, d);
            continue;
        }
        if (a.contains("patch")) {  // the previous answer's array with M values replaced
            if (!previous || !previous->has(d.names.back()) || !a["patch"].is_number_unsigned())
                malformed("patch of an array the previous answer does not have: " + a.dump());
            const std::size_t m = a["patch"].get<std::size_t>();
            if (m > (in.size() - at) / 8) malformed("array " + a.dump() + " runs past the end");
            const std::size_t p = index_of_name(*previous, d.names.back());
            std::vector<double> reals = previous->f32[p];
            std::vector<std::uint32_t> ints = previous->u32[p];
            if ((a["type"] == "f32" ? reals.size() : ints.size()) != n) malformed("patch of another size: " + a.dump());
            for (std::size_t k = 0; k < m; ++k) {
                const std::uint32_t i = get_u32_le(in, at + 4 * k), bits = get_u32_le(in, at + 4 * (m + k));
                if (i >= n) malformed("patch index out of range in " + a.dump());
                if (a["type"] == "f32")
                    reals[i] = static_cast<double>(std::bit_cast<float>(bits));
                else
                    ints[i] = bits;
            }
            at += 8 * m;
            if (a["type"] == "enum") {
                if (!a.contains("names") || !a["names"].is_array()) malformed("enum array without names " + a.dump());
                nlohmann::json strings = nlohmann::json::array();
                for (const std::uint32_t code : ints) {
                    if (code >= a["names"].size()) malformed("enum code " + std::to_string(code) + " in " + a.dump());
                    strings.push_back(a["names"][code]);
                }
                std::string pointer = "/" + d.names.back();
                std::replace(pointer.begin(), pointer.end(), '.', '/');
                d.header[nlohmann::json::json_pointer(pointer)] = std::move(strings);
            }
            d.f32.back() = std::move(reals);
            d.u32.back() = std::move(ints);
            continue;
        }
        if (n > (in.size() - at) / 4) malformed("array " + a.dump() + " runs past the end");
        if (a["type"] == "f32") {
            d.f32.back().reserve(n);
            for (std::size_t i = 0; i < n; ++i, at += 4)
                d.f32.back().push_back(static_cast<double>(std::bit_cast<float>(get_u32_le(in, at))));
        } else if (a["type"] == "u32") {
            d.u32.back().reserve(n);
            for (std::size_t i = 0; i < n; ++i, at += 4) d.u32.back().push_back(get_u32_le(in, at));
        } else if (a["type"] == "enum") {
            if (!a.contains("names") || !a["names"].is_array()) malformed("enum array without names " + a.dump());
            const nlohmann::json& names = a["names"];
            nlohmann::json strings = nlohmann::json::array();
            for (std::size_t i = 0; i < n; ++i, at += 4) {
                const std::uint32_t code = get_u32_le(in, at);
                if (code >= names.size()) malformed("enum code " + std::to_string(code) + " in " + a["name"].dump());
                d.u32.back().push_back(code);
                strings.push_back(names[code]);
            }
            std::string pointer = "/" + d.names.back();  // "analysis.vertex_class" -> "/analysis/vertex_class"
            std::replace(pointer.begin(), pointer.end(), '.', '/');
            d.header[nlohmann::json::json_pointer(pointer)] = std::move(strings);
        } else {
            malformed("array type " + a["type"].dump());
        }
    }
    if (at != in.size()) malformed(std::to_string(in.size() - at) + " bytes after the last array");
    return d;
}

namespace {
std::size_t index_of(const DecodedAnswer& d, const std::string& name) {
    for (std::size_t i = 0; i < d.names.size(); ++i)
        if (d.names[i] == name) return i;
    throw std::invalid_argument("binary answer: no array \"" + name + "\"");
}
}  // namespace

const std::vector<double>& DecodedAnswer::reals(const std::string& name) const { return f32[index_of(*this, name)]; }
const std::vector<std::uint32_t>& DecodedAnswer::ints(const std::string& name) const {
    return u32[index_of(*this, name)];
}
bool DecodedAnswer::has(const std::string& name) const {
    for (const std::string& n : names)
        if (n == name) return true;
    return false;
}

}  // namespace mesohex::studio
