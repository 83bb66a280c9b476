#pragma once
// The studio's background jobs: one worker thread runs them in submission order; one job at a time per client (a new
// job for the same client cancels the previous one); cancellation through the job's progress callback, which throws
// JobCancelled once the job is cancelled; finished jobs kept for polling, bounded per client and overall.
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

namespace mesohex::studio {

enum class JobState { Queued, Running, Done, Failed, Cancelled };
const char* to_string(JobState s);

struct JobProgress {
    std::string stage;  // "raw", "attempt", "fit", "untangle", "improve", "smooth" ("" before the first report)
    int step = 0;
    int steps = 0;      // the stage's cap on step (0 when unknown)
    double sj_min = 0;  // fit: current min scaled Jacobian
    long inverted = 0;  // fit, untangle, improve: hexes with scaled Jacobian <= 0
    std::string what;   // attempt only: what the attempt changes (MeshProgress::what: "first", "fully padded", ...)
};

// Thrown from JobContext::progress once the job is cancelled; the worker catches it.
struct JobCancelled : std::runtime_error {
    JobCancelled() : std::runtime_error("job cancelled") {}
};

// What a running job sees: report progress (and be cancelled there).
class JobContext {
public:
    virtual ~JobContext() = default;
    // Records the progress; throws JobCancelled when the job was cancelled.
    virtual void progress(const JobProgress& p) = 0;
    virtual bool cancelled() const = 0;
};

// A job's work: returns its result (JSON text); throws on failure.
using JobWork = std::function<std::string(JobContext&)>;
// Turns a failure into the job's error (JSON text).
using JobErrorFormatter = std::function<std::string(std::exception_ptr)>;

struct JobSnapshot {
    long id = 0;
    std::string client;
    JobState state = JobState::Queued;
    JobProgress progress;
    std::string result;  // JSON text when Done
    std::string error;   // JSON text when Failed
    long version = 0;    // increases at every change of state or progress
};

struct JobLimits {
    int kept_per_client = 8;  // finished jobs kept per client (oldest dropped)
    int kept_total = 64;      // finished jobs kept over all clients
    int max_queued = 32;      // queued jobs over all clients; submit beyond it fails (Busy)
};

class JobManager {
public:
    JobManager(JobErrorFormatter format_error, JobLimits limits = {});
    ~JobManager();  // cancels every job, joins the worker
    JobManager(const JobManager&) = delete;
    JobManager& operator=(const JobManager&) = delete;

    // Queues `work` for `client`, cancelling the client's queued or running job. Returns the job id (> 0), or
    // nullopt when max_queued jobs are already waiting.
    std::optional<long> submit(const std::string& client, JobWork work);
    std::optional<JobSnapshot> get(long id) const;
    // Cancels a queued or running job. false: no such job (or it was dropped). A finished job stays as it is.
    bool cancel(long id);
    // Waits until the job's version exceeds `seen_version` or it is finished, at most `timeout`; the snapshot then
    // (nullopt: no such job).
    std::optional<JobSnapshot> wait_change(long id, long seen_version, std::chrono::milliseconds timeout) const;

private:
    struct Job;
    class Context;
    void worker_loop();
    void finish_locked(Job& job, JobState state);  // marks finished, enforces the bounds
    void cancel_locked(Job& job);

    JobErrorFormatter format_error_;
    JobLimits limits_;
    mutable std::mutex mutex_;
    mutable std::condition_variable changed_;  // any job changed (waiters) or a job was queued / stop (worker)
    std::map<long, std::shared_ptr<Job>> jobs_;
    std::deque<long> queue_;
    std::deque<long> finished_;  // in finishing order
    long next_id_ = 1;
    bool stopping_ = false;
    std::thread worker_;
};

}  // namespace mesohex::studio
