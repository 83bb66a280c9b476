#pragma once
// Editing sessions of the studio's raw meshes (POST /api/mesh?stage=raw&session=ID, docs/studio.md "Sessions and
// deltas"): per session the last skeleton received (with the revision number the page gave it) and what its raw mesh
// left for the next one (RawRunCache), so that the page can send only the vertices an edit moved (an MHSD delta) and
// the server remesh incrementally. A fixed number of sessions, the least recently used dropped first.
#include <cstddef>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>

#include "binary_answer.h"
#include "mesohex/core/skeleton.h"
#include "mesohex/mesh.h"

namespace mesohex::studio {

struct MeshSession {
    std::mutex mutex;  // one request of a session at a time (held while meshing)
    bool has_skeleton = false;
    long long revision = -1;  // the page's number for `skeleton`
    Skeleton skeleton;        // the last skeleton received (read from the body, or the last one with a delta applied)
    RawRunCache cache;        // what the raw mesh of `skeleton` left (empty after an error)
    // The arrays of the session's last binary answer (the base of a patch answer, `since=`), and its revision.
    long long answer_revision = -1;
    BinaryArrays answer;
};

class MeshSessions {
public:
    explicit MeshSessions(std::size_t capacity) : capacity_(capacity < 1 ? 1 : capacity) {}
    // The session `id`, or null when there is none (never made, or dropped); marks it as just used.
    std::shared_ptr<MeshSession> find(const std::string& id);
    // The session `id`, made when there is none; the least recently used beyond the capacity are dropped (a request
    // still holding one finishes with it; the next request naming it finds nothing).
    std::shared_ptr<MeshSession> find_or_create(const std::string& id);
    std::size_t size() const;

private:
    std::size_t capacity_;
    mutable std::mutex mutex_;
    std::list<std::pair<std::string, std::shared_ptr<MeshSession>>> sessions_;  // most recently used first
};

// A session id: 1 to 64 characters of [A-Za-z0-9._-].
bool valid_session_id(std::string_view id);

// The MHSD delta (docs/formats.md): the vertices of `base` whose position or radius changed, with their new values.
// Little-endian: "MHSD", uint32 version 1, V (vertices of the skeleton, = base's), K (changed vertices), flags (bit 0:
// radii given, = base has radii; other bits 0); uint32 index[K] (strictly increasing, < V); float64 points[3 K];
// float64 radii[K] when flag 0 is set. Values are taken bit for bit, with the rules of the MHSK reader (finite
// coordinates, radii finite and > 0).
std::string skeleton_delta_binary(const Skeleton& base, const Skeleton& changed);  // precondition: same topology
// `base` with the delta applied. Error(InvalidInput) naming the byte offset or the skeleton vertex on anything
// malformed (length, magic, version, counts that do not match base, indices, values); base is not changed.
Skeleton apply_skeleton_delta(const Skeleton& base, std::string_view bytes);

}  // namespace mesohex::studio
