#include "pllvo/vo/keyframe_worker.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

#include "pllvo/common/error.h"

namespace pllvo::vo {

KeyframeWorker::KeyframeWorker(bool threaded, int stages, int nice)
    : threaded_(threaded), stages_(stages), nice_(nice) {
  if (stages_ != 1 && stages_ != 2) throw InternalError("keyframe worker: stages must be 1 or 2");
  if (nice_ < 0 || nice_ > 19) throw InternalError("keyframe worker: nice must be in [0, 19]");
  if (!threaded_) return;
  for (int s = 0; s < stages_; ++s) threads_.emplace_back([this, s] { loop(static_cast<size_t>(s)); });
}

int KeyframeWorker::thread_nice() {
  errno = 0;  // -1 is a valid level: only errno tells a failure
  const int level = getpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)));
  return level == -1 && errno != 0 ? 0 : level;
}

void KeyframeWorker::lower_this_thread() const {
  if (nice_ == 0) return;
  // Linux schedules each thread on its own nice value, and threads started from here (the
  // networks' helpers) inherit it. Raising it needs no privilege; failing leaves it as it was.
  const auto tid = static_cast<id_t>(syscall(SYS_gettid));
  setpriority(PRIO_PROCESS, tid, std::min(19, thread_nice() + nice_));
}

KeyframeWorker::~KeyframeWorker() {
  if (!threaded_) return;
  wait_idle();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  for (auto& w : wake_) w.notify_all();
  for (auto& t : threads_) t.join();
}

bool KeyframeWorker::run_part(const Job& part) {
  if (!part) return true;
  try {
    part();
    return true;
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!failure_) failure_ = std::current_exception();
    return false;
  }
}

void KeyframeWorker::submit(Job first, Job second) {
  if (!threaded_) {
    if (run_part(first)) run_part(second);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    queues_[0].push_back({std::move(first), std::move(second)});
    ++in_flight_;
  }
  wake_[0].notify_one();
}

bool KeyframeWorker::idle() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return in_flight_ == 0;
}

size_t KeyframeWorker::pending() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return in_flight_;
}

void KeyframeWorker::wait_idle() {
  if (!threaded_) return;
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [this] { return in_flight_ == 0; });
}

void KeyframeWorker::rethrow_if_failed() {
  std::exception_ptr failure;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    failure = failure_;
    failure_ = nullptr;
  }
  if (failure) std::rethrow_exception(failure);
}

void KeyframeWorker::finish_job() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    --in_flight_;
  }
  done_.notify_all();
}

void KeyframeWorker::loop(size_t stage) {
  lower_this_thread();
  const bool last = static_cast<int>(stage) + 1 == stages_;
  for (;;) {
    Parts parts;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_[stage].wait(lock, [&] { return stop_ || !queues_[stage].empty(); });
      if (queues_[stage].empty()) return;  // stop requested and nothing left
      parts = std::move(queues_[stage].front());
      queues_[stage].pop_front();
    }
    if (stage == 0 && !run_part(parts.first)) {
      finish_job();
      continue;
    }
    if (!last) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        queues_[stage + 1].push_back({Job{}, std::move(parts.second)});
      }
      wake_[stage + 1].notify_one();
      continue;
    }
    run_part(parts.second);
    finish_job();
  }
}

}  // namespace pllvo::vo
