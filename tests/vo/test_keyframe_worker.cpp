#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "pllvo/vo/keyframe_worker.h"

namespace pllvo::vo {
namespace {

TEST(KeyframeWorker, RunsJobsInOrderOffTheCallersThread) {
  std::vector<int> order;
  std::mutex m;
  std::atomic<bool> other_thread{true};
  const auto caller = std::this_thread::get_id();
  {
    KeyframeWorker worker(true);
    for (int i = 0; i < 20; ++i)
      worker.submit([&, i] {
        if (std::this_thread::get_id() == caller) other_thread = false;
        std::lock_guard<std::mutex> lock(m);
        order.push_back(i);
      });
    worker.wait_idle();
    EXPECT_TRUE(worker.idle());
    EXPECT_EQ(worker.pending(), 0u);
  }
  ASSERT_EQ(order.size(), 20u);
  for (int i = 0; i < 20; ++i) EXPECT_EQ(order[i], i);
  EXPECT_TRUE(other_thread);
}

TEST(KeyframeWorker, SubmitDoesNotWaitForTheJob) {
  KeyframeWorker worker(true);
  std::atomic<bool> release{false};
  worker.submit([&] {
    while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  // The caller continues while the job runs; the worker reports itself busy.
  EXPECT_FALSE(worker.idle());
  EXPECT_EQ(worker.pending(), 1u);
  release = true;
  worker.wait_idle();
  EXPECT_TRUE(worker.idle());
}

TEST(KeyframeWorker, SingleThreadModeRunsInline) {
  KeyframeWorker worker(false);
  int value = 0;
  worker.submit([&] { value = 42; });
  EXPECT_EQ(value, 42);
  EXPECT_TRUE(worker.idle());
}

TEST(KeyframeWorker, ExceptionsReachTheCaller) {
  for (bool threaded : {true, false}) {
    KeyframeWorker worker(threaded);
    worker.submit([] { throw std::runtime_error("bad keyframe"); });
    worker.wait_idle();
    EXPECT_THROW(worker.rethrow_if_failed(), std::runtime_error);
    EXPECT_NO_THROW(worker.rethrow_if_failed());  // reported once
  }
}

}  // namespace
}  // namespace pllvo::vo
