// `mesohex analyze SKELETON`: prints the skeleton analysis (paper step 2): counts, vertex classes, predicted hexes.
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "mesohex/stages/skeleton_analysis.h"
#include "mesohex_io/skeleton_io.h"

namespace mesohex::cli {

void register_analyze(CLI::App& app, int* status) {
    auto path = std::make_shared<std::string>();
    CLI::App* cmd = app.add_subcommand("analyze", "Classify a skeleton's vertices, count branches and leaflets, "
                                                  "predict the raw hex count.");
    cmd->add_option("skeleton", *path, "Skeleton file (.skel, .cg, .cgr, .ig, .obj)")->required();
    cmd->footer("Example: mesohex analyze cactus.skel");
    cmd->callback([path, status]() {
        const Skeleton skeleton = read_skeleton(*path);
        const SkeletonAnalysis an = analyze_skeleton(skeleton);
        std::cout << *path << "\n" << analysis_to_text(an);
        *status = 0;
    });
}

}  // namespace mesohex::cli
