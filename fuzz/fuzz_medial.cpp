// Fuzz target: the medial mesh reader (.ma; the first byte is ignored so that every target has the same input
// layout). A mesohex::Error is a correct refusal; anything else is a finding, and so is an accepted mesh with an
// index out of range, a non-finite point or a radius that is not finite and positive.
#include <cmath>
#include <cstdlib>

#include "fuzz_common.h"
#include "mesohex/core/error.h"
#include "mesohex_io/medial_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    mesohex::fuzz::Input in;
    if (!mesohex::fuzz::split_input(data, size, {"ma"}, in)) return 0;
    try {
        const mesohex::Skeleton s = mesohex::read_medial_mesh_text(in.text, mesohex::fuzz::kInputName);
        if (s.radii.size() != s.points.size()) std::abort();
        for (const std::array<int, 2>& e : s.edges)
            if (e[0] < 0 || e[1] < 0 || static_cast<std::size_t>(e[0]) >= s.points.size() ||
                static_cast<std::size_t>(e[1]) >= s.points.size())
                std::abort();
        for (const std::vector<int>& f : s.faces)
            for (const int v : f)
                if (v < 0 || static_cast<std::size_t>(v) >= s.points.size()) std::abort();
        for (std::size_t v = 0; v < s.points.size(); ++v)
            if (!mesohex::is_finite(s.points[v]) || !(s.radii[v] > 0) || !std::isfinite(s.radii[v])) std::abort();
    } catch (const mesohex::Error&) {
    }
    return 0;
}
