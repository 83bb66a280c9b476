#include "sessions.h"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "mesohex/core/error.h"

namespace mesohex::studio {

std::shared_ptr<MeshSession> MeshSessions::find(const std::string& id) {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = sessions_.begin(); it != sessions_.end(); ++it)
        if (it->first == id) {
            sessions_.splice(sessions_.begin(), sessions_, it);
            return sessions_.front().second;
        }
    return nullptr;
}

std::shared_ptr<MeshSession> MeshSessions::find_or_create(const std::string& id) {
    if (std::shared_ptr<MeshSession> found = find(id)) return found;
    const std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [name, session] : sessions_)  // made by another request meanwhile
        if (name == id) return session;
    sessions_.emplace_front(id, std::make_shared<MeshSession>());
    while (sessions_.size() > capacity_) sessions_.pop_back();
    return sessions_.front().second;
}

std::size_t MeshSessions::size() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return sessions_.size();
}

bool valid_session_id(std::string_view id) {
    if (id.empty() || id.size() > 64) return false;
    for (const char c : id)
        if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '_' ||
              c == '-'))
            return false;
    return true;
}

namespace {

constexpr std::size_t kHeaderBytes = 20;  // magic, version, V, K, flags

void put_u32(std::string& out, std::uint32_t x) {
    char b[4];
    for (int i = 0; i < 4; ++i) b[i] = static_cast<char>((x >> (8 * i)) & 0xffu);
    out.append(b, 4);
}

void put_f64(std::string& out, double x) {
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    char b[8];
    for (int i = 0; i < 8; ++i) b[i] = static_cast<char>((bits >> (8 * i)) & 0xffu);
    out.append(b, 8);
}

std::uint32_t get_u32(std::string_view bytes, std::size_t at) {
    std::uint32_t x = 0;
    for (int i = 0; i < 4; ++i) x |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + i])) << (8 * i);
    return x;
}

double get_f64(std::string_view bytes, std::size_t at) {
    std::uint64_t bits = 0;
    for (int i = 0; i < 8; ++i)
        bits |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes[at + i])) << (8 * i);
    double x;
    std::memcpy(&x, &bits, sizeof x);
    return x;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

[[noreturn]] void fail(const std::string& what, ElementRef where = {}) {
    throw Error(ErrorCode::InvalidInput, "skeleton delta (MHSD): " + what, where);
}

}  // namespace

std::string skeleton_delta_binary(const Skeleton& base, const Skeleton& changed) {
    const bool radii = !changed.radii.empty();
    std::vector<std::uint32_t> moved;
    for (std::size_t v = 0; v < changed.points.size(); ++v) {
        const Vec3& a = base.points[v];
        const Vec3& b = changed.points[v];
        const bool radius_changed = radii && !same_bits(base.radii[v], changed.radii[v]);
        if (!same_bits(a.x, b.x) || !same_bits(a.y, b.y) || !same_bits(a.z, b.z) || radius_changed)
            moved.push_back(static_cast<std::uint32_t>(v));
    }
    std::string out = "MHSD";
    put_u32(out, 1);
    put_u32(out, static_cast<std::uint32_t>(changed.points.size()));
    put_u32(out, static_cast<std::uint32_t>(moved.size()));
    put_u32(out, radii ? 1u : 0u);
    for (const std::uint32_t v : moved) put_u32(out, v);
    for (const std::uint32_t v : moved)
        put_f64(out, changed.points[v].x), put_f64(out, changed.points[v].y), put_f64(out, changed.points[v].z);
    if (radii)
        for (const std::uint32_t v : moved) put_f64(out, changed.radii[v]);
    return out;
}

Skeleton apply_skeleton_delta(const Skeleton& base, std::string_view bytes) {
    if (bytes.size() < kHeaderBytes)
        fail("shorter than its 20-byte header (" + std::to_string(bytes.size()) + " bytes)");
    if (bytes.substr(0, 4) != "MHSD") fail("does not start with MHSD");
    if (get_u32(bytes, 4) != 1) fail("version " + std::to_string(get_u32(bytes, 4)) + " (only 1 is read)");
    const std::uint64_t nv = get_u32(bytes, 8), k = get_u32(bytes, 12), flags = get_u32(bytes, 16);
    if (nv != base.points.size())
        fail("made for " + std::to_string(nv) + " vertices, the session's skeleton has " +
             std::to_string(base.points.size()));
    if (flags > 1) fail("unknown flags " + std::to_string(flags));
    const bool radii = flags == 1;
    if (radii != (base.radii.size() == base.points.size() && !base.radii.empty()))
        fail(radii ? "radii given, the session's skeleton has none"
                   : "no radii given, the session's skeleton has them");
    if (k > nv) fail(std::to_string(k) + " changed vertices of " + std::to_string(nv));
    const std::uint64_t expected = kHeaderBytes + 4 * k + 24 * k + (radii ? 8 * k : 0);
    if (bytes.size() != expected)
        fail(std::to_string(bytes.size()) + " bytes where its counts say " + std::to_string(expected));
    Skeleton s = base;
    const std::size_t points_at = kHeaderBytes + 4 * k, radii_at = points_at + 24 * k;
    long long previous = -1;
    for (std::size_t i = 0; i < k; ++i) {
        const std::uint32_t v = get_u32(bytes, kHeaderBytes + 4 * i);
        if (v >= nv || static_cast<long long>(v) <= previous)
            fail("index " + std::to_string(i) + " (" + std::to_string(v) +
                 "): indices must be increasing and below the vertex count");
        previous = v;
        const ElementRef where{ElementRef::Kind::SkeletonVertex, static_cast<int>(v)};
        const Vec3 p{get_f64(bytes, points_at + 24 * i), get_f64(bytes, points_at + 24 * i + 8),
                     get_f64(bytes, points_at + 24 * i + 16)};
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            fail("vertex " + std::to_string(v) + " has a non-finite coordinate", where);
        s.points[v] = p;
        if (radii) {
            const double r = get_f64(bytes, radii_at + 8 * i);
            if (!(r > 0) || !std::isfinite(r))
                fail("radius of vertex " + std::to_string(v) + " must be positive and finite", where);
            s.radii[v] = r;
        }
    }
    return s;
}

}  // namespace mesohex::studio
