// Fuzz target: triangle surface readers (.off, .obj, .stl, .ply). A mesohex::Error is a correct refusal; anything
// else is a finding. A surface that is read has triangles whose indices are in range, and finite points.
#include <cstdlib>

#include "fuzz_common.h"
#include "mesohex/core/error.h"
#include "mesohex_io/surface_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    mesohex::fuzz::Input in;
    if (!mesohex::fuzz::split_input(data, size, {"off", "obj", "stl", "ply"}, in)) return 0;
    try {
        const mesohex::TriangleMesh m = mesohex::read_surface_text(in.text, in.format, mesohex::fuzz::kInputName);
        if (m.triangles.empty()) std::abort();
        for (const std::array<int, 3>& t : m.triangles)
            for (const int v : t)
                if (v < 0 || static_cast<std::size_t>(v) >= m.points.size()) std::abort();
        for (const mesohex::Vec3& p : m.points)
            if (!mesohex::is_finite(p)) std::abort();
    } catch (const mesohex::Error&) {
    }
    return 0;
}
