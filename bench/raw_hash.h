#pragma once
// FNV-1a hash of a raw mesh's points and hexes (bit for bit): compares the raw meshes of two builds or option sets,
// input by input (bench/random_raw.cpp, bench/raw_chain.cpp).
#include <cstddef>
#include <cstdint>

#include "mesohex/stages/raw_mesh.h"

namespace mesohex::bench {

inline std::uint64_t fnv(std::uint64_t h, const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ULL;
    return h;
}

inline std::uint64_t raw_hash(const RawMesh& raw) {
    std::uint64_t h = 14695981039346656037ULL;
    for (const Vec3& p : raw.mesh.points) h = fnv(h, &p, sizeof p);
    for (const auto& hex : raw.mesh.hexes) h = fnv(h, hex.data(), sizeof hex);
    return h;
}

}  // namespace mesohex::bench
