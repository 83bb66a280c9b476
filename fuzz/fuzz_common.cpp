#include "fuzz_common.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include <unistd.h>

namespace mesohex::fuzz {

std::string write_input(const std::uint8_t* data, std::size_t size, const std::vector<std::string>& extensions) {
    if (size == 0 || extensions.empty()) return {};
    const char* env = std::getenv("TMPDIR");
    const std::string dir = env != nullptr && *env != '\0' ? env : "/tmp";
    const std::string path = dir + "/mesohex_fuzz_" + std::to_string(::getpid()) + "." +
                             extensions[static_cast<std::size_t>(data[0]) % extensions.size()];
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
    out.close();
    if (!out) std::abort();  // the harness cannot write its own file: not a finding in mesohex
    return path;
}

}  // namespace mesohex::fuzz
