// The studio's job manager with stand-in work (no meshing): ordering, one job per client, cancellation through the
// progress callback, failures, and the bound on kept jobs.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

#include "jobs.h"

using namespace mesohex::studio;
using namespace std::chrono_literals;

namespace {

std::string error_text(std::exception_ptr ep) {
    try {
        std::rethrow_exception(ep);
    } catch (const std::exception& e) {
        return std::string("{\"message\":\"") + e.what() + "\"}";
    }
}

// Waits (at most 20 s) until the job is finished; its last snapshot.
JobSnapshot wait_finished(const JobManager& m, long id) {
    const auto deadline = std::chrono::steady_clock::now() + 20s;
    for (;;) {
        const std::optional<JobSnapshot> s = m.wait_change(id, -1, 50ms);
        if (!s) throw std::runtime_error("job dropped");
        if (s->state == JobState::Done || s->state == JobState::Failed || s->state == JobState::Cancelled) return *s;
        if (std::chrono::steady_clock::now() > deadline) throw std::runtime_error("job did not finish");
        std::this_thread::sleep_for(5ms);
    }
}

// Work that reports progress every millisecond until cancelled (or 20 s).
JobWork until_cancelled(std::atomic<int>* started = nullptr) {
    return [started](JobContext& ctx) {
        if (started) ++*started;
        for (int i = 0; i < 20000; ++i) {
            ctx.progress({"fit", i, 20000, 0, 0, ""});
            std::this_thread::sleep_for(1ms);
        }
        return std::string("\"not cancelled\"");
    };
}

}  // namespace

TEST(StudioJobs, AJobRunsAndKeepsItsResult) {
    JobManager m(error_text);
    const std::optional<long> id = m.submit("a", [](JobContext& ctx) {
        ctx.progress({"fit", 1, 2, 0, 0, ""});
        return std::string("{\"x\":1}");
    });
    ASSERT_TRUE(id);
    const JobSnapshot s = wait_finished(m, *id);
    EXPECT_EQ(s.state, JobState::Done);
    EXPECT_EQ(s.result, "{\"x\":1}");
    EXPECT_EQ(s.progress.stage, "fit");
    EXPECT_EQ(s.progress.step, 1);
    EXPECT_EQ(s.progress.steps, 2);
}

TEST(StudioJobs, AFailureKeepsTheFormattedError) {
    JobManager m(error_text);
    const long id = *m.submit("a", [](JobContext&) -> std::string { throw std::runtime_error("bad skeleton"); });
    const JobSnapshot s = wait_finished(m, id);
    EXPECT_EQ(s.state, JobState::Failed);
    EXPECT_EQ(s.error, "{\"message\":\"bad skeleton\"}");
    EXPECT_TRUE(s.result.empty());
}

// A second job of the same client cancels the first (through its next progress report); another client's job is
// left alone.
TEST(StudioJobs, ANewJobOfTheSameClientCancelsThePreviousOne) {
    JobManager m(error_text);
    std::atomic<int> started{0};
    const long first = *m.submit("a", until_cancelled(&started));
    while (started.load() == 0) std::this_thread::sleep_for(1ms);
    EXPECT_EQ(m.get(first)->state, JobState::Running);
    const long second = *m.submit("a", [](JobContext&) { return std::string("2"); });
    const long other = *m.submit("b", [](JobContext&) { return std::string("3"); });
    EXPECT_EQ(wait_finished(m, first).state, JobState::Cancelled);
    EXPECT_EQ(wait_finished(m, second).state, JobState::Done);
    EXPECT_EQ(wait_finished(m, other).state, JobState::Done);
    EXPECT_EQ(m.get(second)->result, "2");
}

// Cancelling a queued job finishes it at once; its work never runs.
TEST(StudioJobs, CancellingAQueuedJobNeverRunsIt) {
    JobManager m(error_text);
    std::atomic<int> started{0};
    const long running = *m.submit("a", until_cancelled(&started));
    while (started.load() == 0) std::this_thread::sleep_for(1ms);
    std::atomic<bool> ran{false};
    const long queued = *m.submit("b", [&ran](JobContext&) {
        ran = true;
        return std::string("1");
    });
    EXPECT_EQ(m.get(queued)->state, JobState::Queued);
    EXPECT_TRUE(m.cancel(queued));
    EXPECT_EQ(m.get(queued)->state, JobState::Cancelled);
    EXPECT_TRUE(m.cancel(running));
    EXPECT_EQ(wait_finished(m, running).state, JobState::Cancelled);
    EXPECT_FALSE(ran.load());
    EXPECT_FALSE(m.cancel(12345));
}

// 10 finished jobs of one client: the first 2 are dropped, the last 8 kept; another client's job survives.
TEST(StudioJobs, KeepsTheLastEightFinishedJobsPerClient) {
    JobManager m(error_text);
    const long b = *m.submit("b", [](JobContext&) { return std::string("b"); });
    wait_finished(m, b);
    std::vector<long> ids;
    for (int i = 0; i < 10; ++i) {
        ids.push_back(*m.submit("a", [i](JobContext&) { return std::to_string(i); }));
        wait_finished(m, ids.back());
    }
    for (int i = 0; i < 10; ++i) EXPECT_EQ(m.get(ids[i]).has_value(), i >= 2) << i;
    EXPECT_EQ(m.get(ids[9])->result, "9");
    EXPECT_TRUE(m.get(b).has_value());
}

// The destructor cancels a running job and returns.
TEST(StudioJobs, DestructionCancelsTheRunningJob) {
    std::atomic<int> started{0};
    {
        JobManager m(error_text);
        m.submit("a", until_cancelled(&started));
        while (started.load() == 0) std::this_thread::sleep_for(1ms);
    }
    EXPECT_EQ(started.load(), 1);
}
