#pragma once
// Runs keyframe jobs (networks, matching, triangulation, BA) in order off the tracking thread,
// so per-frame tracking never waits for them; or inline, for deterministic tests.
//
// A job has two parts. With two stages, each part has a thread of its own: the first part of
// the next keyframe (point detection, the network that costs most) runs while the second part
// of this one (matching, BA) still does, so a second core is used without the OpenMP threads
// that spin-wait on a busy machine (docs/vo.md). Parts run in submission order
// within each stage, so second parts run in job order.
#include <array>
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace pllvo::vo {

class KeyframeWorker {
 public:
  using Job = std::function<void()>;

  /// `threaded` false: submit() runs the job before returning (single-thread mode).
  /// `stages` 1: one thread runs both parts of each job; 2: a thread per part.
  /// `nice` > 0: the worker's threads run that much below the caller's priority (Linux nice
  /// levels), so that the tracking thread gets a core whenever it has a frame.
  explicit KeyframeWorker(bool threaded, int stages = 1, int nice = 0);
  ~KeyframeWorker();  ///< finishes queued jobs, then joins
  KeyframeWorker(const KeyframeWorker&) = delete;
  KeyframeWorker& operator=(const KeyframeWorker&) = delete;

  void submit(Job job) { submit(Job{}, std::move(job)); }
  /// A job in two parts; `second` runs after `first` (not at all when `first` threw).
  /// Either may be empty.
  void submit(Job first, Job second);
  /// Nothing queued and nothing running.
  bool idle() const;
  /// Jobs submitted and not finished (a job counts once, whichever part it is in).
  size_t pending() const;
  /// Blocks until every submitted job has finished.
  void wait_idle();
  /// Rethrows, on the caller's thread, the first exception a job raised.
  void rethrow_if_failed();
  bool threaded() const { return threaded_; }
  /// The calling thread's nice level.
  static int thread_nice();

 private:
  struct Parts {
    Job first, second;
  };
  void loop(size_t stage);
  /// Runs `part`; false when it threw (the failure is kept for rethrow_if_failed).
  bool run_part(const Job& part);
  void finish_job();
  void lower_this_thread() const;

  bool threaded_;
  int stages_;
  int nice_;
  mutable std::mutex mutex_;
  std::array<std::condition_variable, 2> wake_;
  std::condition_variable done_;
  std::array<std::deque<Parts>, 2> queues_;
  size_t in_flight_ = 0;
  bool stop_ = false;
  std::exception_ptr failure_;
  std::vector<std::thread> threads_;
};

}  // namespace pllvo::vo
