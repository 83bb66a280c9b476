#include "jobs.h"

#include <algorithm>
#include <atomic>

namespace mesohex::studio {

const char* to_string(JobState s) {
    switch (s) {
        case JobState::Queued: return "queued";
        case JobState::Running: return "running";
        case JobState::Done: return "done";
        case JobState::Failed: return "failed";
        case JobState::Cancelled: return "cancelled";
    }
    return "?";
}

struct JobManager::Job {
    JobSnapshot snap;
    JobWork work;
    std::atomic<bool> cancel{false};
    bool finished() const {
        return snap.state == JobState::Done || snap.state == JobState::Failed || snap.state == JobState::Cancelled;
    }
};

class JobManager::Context : public JobContext {
public:
    Context(JobManager& m, Job& job) : m_(m), job_(job) {}
    void progress(const JobProgress& p) override {
        if (job_.cancel.load()) throw JobCancelled();
        {
            const std::lock_guard<std::mutex> lock(m_.mutex_);
            job_.snap.progress = p;
            ++job_.snap.version;
        }
        m_.changed_.notify_all();
    }
    bool cancelled() const override { return job_.cancel.load(); }

private:
    JobManager& m_;
    Job& job_;
};

JobManager::JobManager(JobErrorFormatter format_error, JobLimits limits)
    : format_error_(std::move(format_error)), limits_(limits), worker_([this] { worker_loop(); }) {}

JobManager::~JobManager() {
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
        for (auto& [id, job] : jobs_) job->cancel = true;
    }
    changed_.notify_all();
    worker_.join();
}

std::optional<long> JobManager::submit(const std::string& client, JobWork work) {
    long id = 0;
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        for (auto& [other_id, job] : jobs_)
            if (job->snap.client == client && !job->finished()) cancel_locked(*job);
        if (static_cast<int>(queue_.size()) >= limits_.max_queued) {
            changed_.notify_all();
            return std::nullopt;
        }
        id = next_id_++;
        auto job = std::make_shared<Job>();
        job->snap.id = id;
        job->snap.client = client;
        job->work = std::move(work);
        jobs_[id] = job;
        queue_.push_back(id);
    }
    changed_.notify_all();
    return id;
}

std::optional<JobSnapshot> JobManager::get(long id) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto it = jobs_.find(id);
    if (it == jobs_.end()) return std::nullopt;
    return it->second->snap;
}

bool JobManager::cancel(long id) {
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        const auto it = jobs_.find(id);
        if (it == jobs_.end()) return false;
        cancel_locked(*it->second);
    }
    changed_.notify_all();
    return true;
}

std::optional<JobSnapshot> JobManager::wait_change(long id, long seen_version,
                                                   std::chrono::milliseconds timeout) const {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait_for(lock, timeout, [&] {
        const auto it = jobs_.find(id);
        return stopping_ || it == jobs_.end() || it->second->snap.version > seen_version || it->second->finished();
    });
    const auto it = jobs_.find(id);
    if (it == jobs_.end()) return std::nullopt;
    return it->second->snap;
}

void JobManager::cancel_locked(Job& job) {
    if (job.finished()) return;
    job.cancel = true;
    if (job.snap.state == JobState::Queued) {
        queue_.erase(std::remove(queue_.begin(), queue_.end(), job.snap.id), queue_.end());
        finish_locked(job, JobState::Cancelled);
    }
    // A running job finishes as Cancelled when its work next reports progress (or returns).
}

void JobManager::finish_locked(Job& job, JobState state) {
    job.snap.state = state;
    ++job.snap.version;
    job.work = nullptr;
    finished_.push_back(job.snap.id);
    // Bounds: per client, then overall; the oldest finished jobs go first.
    const std::string client = job.snap.client;
    int of_client = 0;
    for (const long id : finished_) of_client += jobs_.at(id)->snap.client == client;
    for (auto it = finished_.begin(); it != finished_.end() && of_client > limits_.kept_per_client;) {
        if (jobs_.at(*it)->snap.client == client) {
            jobs_.erase(*it);
            it = finished_.erase(it);
            --of_client;
        } else {
            ++it;
        }
    }
    while (static_cast<int>(finished_.size()) > limits_.kept_total) {
        jobs_.erase(finished_.front());
        finished_.pop_front();
    }
}

void JobManager::worker_loop() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        changed_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
        if (stopping_) return;
        const long id = queue_.front();
        queue_.pop_front();
        const std::shared_ptr<Job> job = jobs_.at(id);  // keeps the job alive even if it is dropped meanwhile
        job->snap.state = JobState::Running;
        ++job->snap.version;
        JobWork work = std::move(job->work);
        lock.unlock();
        changed_.notify_all();

        std::string result, error;
        JobState state = JobState::Done;
        try {
            Context ctx(*this, *job);
            result = work(ctx);
            if (job->cancel.load()) state = JobState::Cancelled;
        } catch (const JobCancelled&) {
            state = JobState::Cancelled;
        } catch (...) {
            if (job->cancel.load()) {
                state = JobState::Cancelled;
            } else {
                state = JobState::Failed;
                try {
                    error = format_error_(std::current_exception());
                } catch (...) {
                    error = R"({"code":"NumericalFailure","message":"job failed"})";
                }
            }
        }
        work = nullptr;
        lock.lock();
        if (state == JobState::Done) job->snap.result = std::move(result);
        if (state == JobState::Failed) job->snap.error = std::move(error);
        if (jobs_.count(id)) finish_locked(*job, state);
        changed_.notify_all();
    }
}

}  // namespace mesohex::studio
