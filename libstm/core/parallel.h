#pragma once
/// The little thread scheduling the pipeline does, in one place: a callable run on a second thread
/// beside the caller's work (run_concurrently, BackgroundTask), a loop whose chunks several threads
/// share (SharedLoop), and a progress callback that two threads may call (serialised). Results never
/// depend on the scheduling: the callers give each thread its own outputs, and a shared loop's
/// iterations are independent.
#include "libstm/core/progress.h"
#include "libstm/core/stopwatch.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace sdm {

/// Starts `task` on a thread of its own at construction. wait() blocks until it has returned and
/// rethrows what it threw (once). The destructor waits too, swallowing the exception, so that a
/// caller unwinding from its own failure never leaves the thread running on its locals.
class BackgroundTask {
 public:
  template <class Task>
  explicit BackgroundTask(Task&& task)
      : thread_([this, task = std::forward<Task>(task)]() mutable {
          try {
            task();
          } catch (...) {
            failure_ = std::current_exception();
          }
        }) {}
  BackgroundTask(const BackgroundTask&) = delete;
  BackgroundTask& operator=(const BackgroundTask&) = delete;
  ~BackgroundTask() {
    if (thread_.joinable()) thread_.join();
  }

  void wait() {
    if (thread_.joinable()) thread_.join();
    if (failure_) std::rethrow_exception(std::exchange(failure_, nullptr));
  }

 private:
  std::exception_ptr failure_;  ///< declared before thread_: set by the thread, which starts last
  std::thread thread_;
};

/// Runs `background` on a second thread and `here` on the calling one, and returns when both have
/// returned.
/// \throw what `here` threw, else what `background` threw.
template <class Background, class Here>
void run_concurrently(Background&& background, Here&& here) {
  BackgroundTask task(std::forward<Background>(background));
  std::exception_ptr failure;
  try {
    here();
  } catch (...) {
    failure = std::current_exception();
  }
  try {
    task.wait();
  } catch (...) {
    if (!failure) throw;
  }
  if (failure) std::rethrow_exception(failure);
}

/// body(i) for every i in [0, count), in chunks of `chunk` consecutive indices that any thread
/// calling work() takes in turn, so that a thread with nothing else to do joins in. The iterations
/// must be independent (each writes only its own outputs). work() never throws: a failing chunk is
/// recorded and the rest go on; wait() blocks until every chunk is done and rethrows the first
/// failure recorded.
class SharedLoop {
 public:
  SharedLoop(int count, int chunk, std::function<void(int)> body)
      : count_(count), chunk_(std::max(chunk, 1)), chunks_((count + chunk_ - 1) / chunk_), body_(std::move(body)) {}

  void work() {
    const Stopwatch watch;
    int finished = 0;
    std::exception_ptr failure;
    for (int c; (c = next_chunk_++) < chunks_;) {
      try {
        for (int i = c * chunk_; i < std::min(count_, (c + 1) * chunk_); ++i) body_(i);
      } catch (...) {
        failure = std::current_exception();
      }
      ++finished;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    seconds_ += watch.seconds();
    if (failure && !failure_) failure_ = failure;
    chunks_done_ += finished;
    if (chunks_done_ == chunks_) done_.notify_all();
  }

  void wait() {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return chunks_done_ == chunks_; });
    if (failure_) std::rethrow_exception(failure_);
  }

  /// Time spent in work(), summed over the threads that called it (final once wait() returned).
  double seconds() {
    std::lock_guard<std::mutex> lock(mutex_);
    return seconds_;
  }

 private:
  const int count_, chunk_, chunks_;
  const std::function<void(int)> body_;
  std::atomic<int> next_chunk_{0};
  std::mutex mutex_;
  std::condition_variable done_;
  int chunks_done_ = 0;
  double seconds_ = 0;
  std::exception_ptr failure_;
};

/// body(i) for every i in [0, count), in chunks of `chunk`, on the calling thread and up to
/// `threads` - 1 others (0: one per hardware thread); returns when all are done and rethrows the
/// first failure. The iterations must be independent.
inline void parallel_for(int count, int chunk, const std::function<void(int)>& body, int threads = 0) {
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
  SharedLoop loop(count, chunk, body);
  const int chunks = (count + std::max(chunk, 1) - 1) / std::max(chunk, 1);
  std::vector<std::unique_ptr<BackgroundTask>> helpers;
  for (int t = 1; t < std::min(threads, chunks); ++t) helpers.push_back(std::make_unique<BackgroundTask>([&loop] { loop.work(); }));
  loop.work();
  for (auto& h : helpers) h->wait();
  loop.wait();
}

/// `progress` behind a mutex, for stages that report from two threads (lines never interleave).
/// Empty when `progress` is.
inline Progress serialised(const Progress& progress) {
  if (!progress) return Progress();
  auto mutex = std::make_shared<std::mutex>();
  return [progress, mutex](const std::string& line) {
    std::lock_guard<std::mutex> lock(*mutex);
    progress(line);
  };
}

}  // namespace sdm
