// TEMPORARY STUB: `mesohex quality` and `mesohex convert` are being written.
#include "commands.h"

namespace mesohex::cli {
void register_quality(CLI::App& app, int* status) { (void)app; (void)status; }
void register_convert(CLI::App& app, int* status) { (void)app; (void)status; }
}  // namespace mesohex::cli
