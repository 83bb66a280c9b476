#include "binary_answer.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>

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

BinaryArrays patch_arrays(const BinaryArrays& base, const BinaryArrays& full) {
    // Byte offset of each array of base, by name.
    std::vector<std::size_t> base_at;
    std::size_t at = 0;
    for (const nlohmann::json& a : base.list) base_at.push_back(at), at += 4 * a["count"].get<std::size_t>();
    BinaryArrays out;
    at = 0;
    for (const nlohmann::json& a : full.list) {
        const std::size_t n = a["count"].get<std::size_t>();
        const char* values = full.bytes.data() + at;
        at += 4 * n;
        std::size_t b = 0;
        while (b < base.list.size() && base.list[b]["name"] != a["name"]) ++b;
        bool patch = b < base.list.size() && base.list[b]["type"] == a["type"] && base.list[b]["count"] == a["count"] &&
                     base.list[b].value("names", nlohmann::json()) == a.value("names", nlohmann::json());
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
        nlohmann::json entry = a;
        if (!patch) {
            out.bytes.append(values, 4 * n);
        } else {
            entry["patch"] = changed.size();
            char* w = grow(out.bytes, 8 * changed.size());
            for (const std::uint32_t i : changed) store_u32_le(w, i), w += 4;
            for (const std::uint32_t i : changed) std::memcpy(w, values + 4 * static_cast<std::size_t>(i), 4), w += 4;
        }
        out.list.push_back(std::move(entry));
    }
    return out;
}

DecodedAnswer decode_binary_answer(const std::string& in, const DecodedAnswer* previous) {
    if (in.size() < 12 || in.compare(0, 4, kMagic, 4) != 0) malformed("no MHXB magic");
    if (get_u32_le(in, 4) != kBinaryAnswerVersion) malformed("unknown version " + std::to_string(get_u32_le(in, 4)));
    const std::size_t h = get_u32_le(in, 8);
    if (h % 4 != 0 || 12 + h > in.size()) malformed("header size " + std::to_string(h));
    DecodedAnswer d;
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
