// Fuzz target: skeleton readers (.ig, .cg, .cgr, .skel, .obj). A mesohex::Error is a correct refusal; anything else
// is a finding. A skeleton that is read must satisfy the reader's postconditions (indices in range, radii positive, points finite).
#include <cstdlib>

#include "fuzz_common.h"
#include "mesohex/core/error.h"
#include "mesohex_io/skeleton_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    mesohex::fuzz::Input in;
    if (!mesohex::fuzz::split_input(data, size, {"ig", "cg", "cgr", "skel", "obj"}, in)) return 0;
    try {
        const mesohex::Skeleton s = mesohex::read_skeleton_text(in.text, in.format, mesohex::fuzz::kInputName);
        const std::size_t n = s.points.size();
        for (const std::array<int, 2>& e : s.edges)
            if (e[0] < 0 || e[1] < 0 || static_cast<std::size_t>(e[0]) >= n || static_cast<std::size_t>(e[1]) >= n)
                std::abort();
        for (const std::vector<int>& f : s.faces)
            for (const int v : f)
                if (v < 0 || static_cast<std::size_t>(v) >= n) std::abort();
        for (const double r : s.radii)
            if (!(r > 0)) std::abort();
        for (const mesohex::Vec3& p : s.points)
            if (!mesohex::is_finite(p)) std::abort();
    } catch (const mesohex::Error&) {
    }
    return 0;
}
