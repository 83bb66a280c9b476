#pragma once
// Each subcommand lives in its own cmd_<name>.cpp and exposes one registration function. The callback it installs
// returns the process exit status through *status; errors are mesohex::Error (mapped to exit codes in main.cpp).
#include <CLI/CLI.hpp>

namespace mesohex::cli {

void register_quality(CLI::App& app, int* status);
void register_mesh(CLI::App& app, int* status);
void register_analyze(CLI::App& app, int* status);
void register_convert(CLI::App& app, int* status);
void register_generate(CLI::App& app, int* status);
void register_import(CLI::App& app, int* status);
void register_skeletonize(CLI::App& app, int* status);
void register_thicken(CLI::App& app, int* status);
void register_auto(CLI::App& app, int* status);
void register_medial(CLI::App& app, int* status);

}  // namespace mesohex::cli
