// `mesohex studio` as a process: prints its URL on one line, listens on 127.0.0.1 (or warns for another host),
// answers, and exits 0 on SIGTERM.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <regex>
#include <string>

#include <httplib.h>

namespace {

struct Studio {
    pid_t pid = -1;
    std::string first_line;
    std::string stderr_text;
};

// Starts `mesohex studio ARGS --port 0`, reads its first stdout line; the stderr read until then is in stderr_text.
Studio spawn(const std::vector<std::string>& args) {
    int out[2], err[2];
    if (::pipe(out) != 0 || ::pipe(err) != 0) return {};
    Studio s;
    s.pid = ::fork();
    if (s.pid == 0) {
        ::dup2(out[1], 1);
        ::dup2(err[1], 2);
        ::close(out[0]), ::close(err[0]), ::close(out[1]), ::close(err[1]);
        std::vector<std::string> all = {MESOHEX_CLI_PATH, "studio"};
        all.insert(all.end(), args.begin(), args.end());
        all.push_back("--port");
        all.push_back("0");
        std::vector<char*> argv;
        for (std::string& a : all) argv.push_back(a.data());
        argv.push_back(nullptr);
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    ::close(out[1]), ::close(err[1]);
    char c;
    while (::read(out[0], &c, 1) == 1 && c != '\n') s.first_line += c;
    ::close(out[0]);
    ::fcntl(err[0], F_SETFL, O_NONBLOCK);
    char buf[4096];
    ssize_t n;
    while ((n = ::read(err[0], buf, sizeof buf)) > 0) s.stderr_text.append(buf, static_cast<std::size_t>(n));
    ::close(err[0]);
    return s;
}

int stop(const Studio& s) {
    ::kill(s.pid, SIGTERM);
    int status = 0;
    ::waitpid(s.pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST(StudioCli, PrintsItsUrlAnswersAndStopsOnSigterm) {
    const Studio s = spawn({std::string(MESOHEX_PROJECT_DIR) + "/data/tiny/tripod.obj"});
    ASSERT_GT(s.pid, 0);
    std::smatch m;
    ASSERT_TRUE(std::regex_match(s.first_line, m, std::regex(R"(mesohex studio: http://127\.0\.0\.1:(\d+)/)")))
        << s.first_line;
    const int port = std::stoi(m[1].str());
    httplib::Client c("127.0.0.1", port);
    const auto r = c.Get("/api/session");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
    EXPECT_NE(r->body.find("\"skeleton_name\":\"" + std::string(MESOHEX_PROJECT_DIR) + "/data/tiny/tripod.obj\""),
              std::string::npos);
    EXPECT_EQ(s.stderr_text.find("warning: listening"), std::string::npos) << s.stderr_text;
    EXPECT_EQ(stop(s), 0);
}

// Another host (here another loopback address, so nothing is exposed) is allowed with a warning.
TEST(StudioCli, AnotherHostPrintsAWarning) {
    const Studio s = spawn({"--host", "127.0.0.2"});
    ASSERT_GT(s.pid, 0);
    EXPECT_EQ(s.first_line.rfind("mesohex studio: http://127.0.0.2:", 0), 0u) << s.first_line;
    EXPECT_NE(s.stderr_text.find("warning: listening on 127.0.0.2"), std::string::npos) << s.stderr_text;
    EXPECT_EQ(stop(s), 0);
}

TEST(StudioCli, UnreadableSkeletonIsAFileErrorBeforeListening) {
    const Studio s = spawn({"/nonexistent/skeleton.obj"});
    ASSERT_GT(s.pid, 0);
    EXPECT_EQ(s.first_line, "");
    int status = 0;
    ::waitpid(s.pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_NE(WEXITSTATUS(status), 0);
}
