// Fuzz target: hex mesh readers (.mesh, .vtk, .vtu, .msh). Any mesohex::Error is a correct refusal; anything else
// (another exception, a crash, a sanitizer report, a hang) is a finding. A mesh that is read is also checked.
#include <cstdlib>

#include "fuzz_common.h"
#include "mesohex/core/error.h"
#include "mesohex_io/hex_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    mesohex::fuzz::Input in;
    if (!mesohex::fuzz::split_input(data, size, {"mesh", "vtk", "vtu", "msh"}, in)) return 0;
    try {
        const mesohex::HexMesh mesh = mesohex::read_hex_mesh_text(in.text, in.format, mesohex::fuzz::kInputName);
        for (const std::array<int, 8>& hex : mesh.hexes)
            for (const int v : hex)
                if (v < 0 || static_cast<std::size_t>(v) >= mesh.points.size()) std::abort();  // reader postcondition
        for (const mesohex::Vec3& p : mesh.points)
            if (!mesohex::is_finite(p)) std::abort();
    } catch (const mesohex::Error&) {
    }
    return 0;
}
