#include "shaderfit/core/parallel.hpp"

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace shaderfit {

namespace {

// Workers beyond this are never started, whatever a caller asks for.
constexpr int kMaxWorkers = 256;

// One parallel_for call. It lives on the caller's stack; every field is guarded by the pool
// mutex, and no worker touches it after its last range is counted in `done`, which the caller
// waits for, so it is safe for the caller to return then.
struct Job {
  RangeFunctionRef body;
  std::size_t n = 0;
  std::size_t grain = 1;
  std::size_t ranges = 0;
  std::size_t next = 0;  // first range not handed out yet
  std::size_t done = 0;  // ranges finished or skipped
  int helpers = 0;       // workers running one of its ranges now
  int max_helpers = 0;
  std::exception_ptr error;
};

}  // namespace

struct ThreadPool::State {
  int threads = 1;
  std::mutex mutex;
  std::condition_variable work_ready;  // a job was queued, or stop
  std::condition_variable job_done;    // some job's last range finished
  std::deque<Job*> queue;              // jobs with ranges not handed out yet
  std::vector<std::thread> workers;
  bool stop = false;

  // A queued job that may take one more helper, or null. Needs the mutex.
  Job* find_job() {
    for (Job* j : queue)
      if (j->helpers < j->max_helpers) return j;
    return nullptr;
  }

  // Hands out the next range of `job`, dequeuing the job when none is left. Needs the mutex.
  std::size_t claim(Job& job) {
    const std::size_t r = job.next++;
    if (job.next == job.ranges) std::erase(queue, &job);
    return r;
  }

  // Runs range r of `job` with the mutex released, then counts it. Needs the mutex held (lock).
  void run_range(Job& job, std::size_t r, std::unique_lock<std::mutex>& lock) {
    lock.unlock();
    std::exception_ptr error;
    try {
      const std::size_t begin = r * job.grain;
      job.body(begin, std::min(job.n, begin + job.grain));
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    if (error) {
      if (!job.error) job.error = error;
      if (job.next < job.ranges) {  // skip what nobody has started
        job.done += job.ranges - job.next;
        job.next = job.ranges;
        std::erase(queue, &job);
      }
    }
    if (++job.done == job.ranges) job_done.notify_all();
  }

  void worker_loop() {
    std::unique_lock lock(mutex);
    for (;;) {
      Job* job = nullptr;
      work_ready.wait(lock, [&] { return stop || (job = find_job()) != nullptr; });
      if (stop) return;
      ++job->helpers;
      run_range(*job, claim(*job), lock);
      --job->helpers;
    }
  }

  // Starts workers until there are `count` (capped). Needs the mutex.
  void ensure_workers(int count) {
    count = std::min(count, kMaxWorkers);
    while (static_cast<int>(workers.size()) < count)
      workers.emplace_back([this] { worker_loop(); });
  }
};

ThreadPool::ThreadPool(int threads) : state_(std::make_unique<State>()) {
  if (threads <= 0) threads = static_cast<int>(std::thread::hardware_concurrency());
  state_->threads = std::max(threads, 1);
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard lock(state_->mutex);
    state_->stop = true;
  }
  state_->work_ready.notify_all();
  for (std::thread& t : state_->workers) t.join();
}

int ThreadPool::threads() const noexcept { return state_->threads; }

void ThreadPool::parallel_for(std::size_t n, std::size_t grain, RangeFunctionRef body,
                              int max_threads) {
  if (n == 0) return;
  grain = std::max<std::size_t>(grain, 1);
  const std::size_t ranges = (n - 1) / grain + 1;
  const int threads = max_threads > 0 ? max_threads : state_->threads;
  if (ranges == 1 || threads == 1) {
    body(0, n);
    return;
  }

  Job job{body};
  job.n = n;
  job.grain = grain;
  job.ranges = ranges;
  job.max_helpers = static_cast<int>(std::min<std::size_t>(threads - 1, ranges - 1));

  State& s = *state_;
  std::unique_lock lock(s.mutex);
  s.ensure_workers(job.max_helpers);
  s.queue.push_back(&job);
  s.work_ready.notify_all();
  // The caller works on its own job until every range is handed out, then waits for helpers.
  while (job.next < job.ranges) s.run_range(job, s.claim(job), lock);
  s.job_done.wait(lock, [&] { return job.done == job.ranges; });
  lock.unlock();
  if (job.error) std::rethrow_exception(job.error);
}

ThreadPool& default_thread_pool() {
  static ThreadPool pool;
  return pool;
}

}  // namespace shaderfit
