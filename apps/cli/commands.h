#pragma once
// Each subcommand lives in its own cmd_<name>.cpp and exposes one registration function. The callback it installs
// returns the process exit status through *status; errors are mesohex::Error (mapped to exit codes in main.cpp).
#include <CLI/CLI.hpp>
#include <cmath>
#include <exception>
#include <sstream>
#include <string>

#include "mesohex/core/error.h"

namespace mesohex {
struct MedialImportOptions;
struct MedialAxisOptions;
}  // namespace mesohex

namespace mesohex::cli {

// Runs f() as the stage `stage` on input `file`: a mesohex::Error gets "<file>: " in front when `name_file` (unless
// it already names the file) and is otherwise passed on; any other exception (CGAL::Failure_exception, std::bad_alloc,
// Eigen, TBB) becomes Error(NumericalFailure) "<file>: <stage>: internal failure: ..." (exit status 6). Nothing is
// written by a failed stage, since outputs are written after it.
template <typename F>
auto at_stage(const std::string& stage, const std::string& file, F&& f, bool name_file = true) -> decltype(f()) {
    try {
        return f();
    } catch (const Error& e) {
        const std::string what = e.what();
        if (!name_file || what.compare(0, file.size(), file) == 0) throw;
        throw Error(e.code(), file + ": " + what, e.where());
    } catch (const std::exception& e) {
        throw foreign_error(e, file + ": " + stage);
    }
}

// A real option in [lo, hi]: CLI::Range lets NaN through (both comparisons are false); this refuses it, and infinities,
// with the option's name in the message (exit status of a CLI11 validation error).
inline CLI::Validator finite_range(double lo, double hi) {
    std::ostringstream bounds;
    bounds << "[" << lo << ", " << hi << "]";
    return CLI::Validator(
        [lo, hi, range = bounds.str()](std::string& text) -> std::string {
            double x = 0;
            try {
                std::size_t used = 0;
                x = std::stod(text, &used);
                if (used != text.size()) return "'" + text + "' is not a number";
            } catch (const std::exception&) {
                return "'" + text + "' is not a number";
            }
            if (!std::isfinite(x) || x < lo || x > hi) return "'" + text + "' is not a finite number in " + range;
            return {};
        },
        "FLOAT in " + bounds.str());
}

// The import's flags for notch and several-curve leaflet corners (--no-bl-notch-corners, --no-bl-branch-corners,
// --bl-corner-max-push, --bl-corner-reach) and the pinch fill (--fill-pinch), writing into *o (which must outlive the
// parse); each help text starts with help_prefix. Shared by `import` and `auto` (cmd_import.cpp).
void add_bl_corner_options(CLI::App* cmd, MedialImportOptions* o, const std::string& help_prefix);

void register_quality(CLI::App& app, int* status);
void register_mesh(CLI::App& app, int* status);
void register_analyze(CLI::App& app, int* status);
void register_convert(CLI::App& app, int* status);
void register_generate(CLI::App& app, int* status);
void register_import(CLI::App& app, int* status);
void register_skeletonize(CLI::App& app, int* status);
void register_thicken(CLI::App& app, int* status);
void register_auto(CLI::App& app, int* status);
void register_studio(CLI::App& app, int* status);
void register_medial(CLI::App& app, int* status);
// The medial axis options `medial` and `auto` share (cmd_medial.cpp); `prefix` starts every help text.
void add_medial_axis_options(CLI::App* cmd, MedialAxisOptions& o, const std::string& prefix);

}  // namespace mesohex::cli
