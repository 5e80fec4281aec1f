#pragma once
// Runs keyframe jobs (networks, matching, triangulation, BA) in order on one worker thread,
// so per-frame tracking never waits for them; or inline, for deterministic tests.
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace pllvo::vo {

class KeyframeWorker {
 public:
  using Job = std::function<void()>;

  /// `threaded` false: submit() runs the job before returning (single-thread mode).
  explicit KeyframeWorker(bool threaded);
  ~KeyframeWorker();  ///< finishes queued jobs, then joins
  KeyframeWorker(const KeyframeWorker&) = delete;
  KeyframeWorker& operator=(const KeyframeWorker&) = delete;

  void submit(Job job);
  /// Nothing queued and nothing running.
  bool idle() const;
  /// Jobs queued or running.
  size_t pending() const;
  /// Blocks until every submitted job has finished.
  void wait_idle();
  /// Rethrows, on the caller's thread, the first exception a job raised.
  void rethrow_if_failed();
  bool threaded() const { return threaded_; }

 private:
  void loop();

  bool threaded_;
  mutable std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::deque<Job> queue_;
  bool running_job_ = false;
  bool stop_ = false;
  std::exception_ptr failure_;
  std::thread thread_;
};

}  // namespace pllvo::vo
