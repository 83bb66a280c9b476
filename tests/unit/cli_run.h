#pragma once
// Runs the built `mesohex` binary (MESOHEX_CLI_PATH) for end-to-end tests.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace mesohex::test {

struct CliRun {
    int status = -1;     // exit status, -1 when the process did not exit normally
    std::string output;  // stdout, plus stderr unless it was discarded
};

inline CliRun run_cli(const std::string& args, bool with_stderr = true) {
    const std::string cmd = std::string(MESOHEX_CLI_PATH) + " " + args + (with_stderr ? " 2>&1" : " 2>/dev/null");
    CliRun r;
    FILE* pipe = ::popen(cmd.c_str(), "r");
    if (!pipe) return r;
    std::array<char, 4096> buf;
    std::size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
    const int raw = ::pclose(pipe);
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    return r;
}

}  // namespace mesohex::test
