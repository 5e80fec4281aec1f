#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <string>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "pllvo/common/error.h"
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

TEST(KeyframeWorker, TwoStagesKeepJobOrderAndOverlapTheParts) {
  std::mutex m;
  std::vector<std::string> log;
  std::atomic<bool> second_part_running{false}, overlapped{false};
  std::set<std::thread::id> first_threads, second_threads;
  {
    KeyframeWorker worker(true, 2);
    for (int i = 0; i < 6; ++i)
      worker.submit(
          [&, i] {
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
            if (second_part_running) overlapped = true;
            std::lock_guard<std::mutex> lock(m);
            first_threads.insert(std::this_thread::get_id());
            log.push_back("a" + std::to_string(i));
          },
          [&, i] {
            second_part_running = true;
            // Long enough for the next job's first part to start meanwhile.
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            {
              std::lock_guard<std::mutex> lock(m);
              second_threads.insert(std::this_thread::get_id());
              log.push_back("b" + std::to_string(i));
            }
            second_part_running = false;
          });
    EXPECT_GE(worker.pending(), 1u);
    worker.wait_idle();
    EXPECT_EQ(worker.pending(), 0u);
  }
  std::vector<std::string> firsts, seconds;
  for (const auto& e : log) (e[0] == 'a' ? firsts : seconds).push_back(e.substr(1));
  ASSERT_EQ(firsts.size(), 6u);
  ASSERT_EQ(seconds.size(), 6u);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(firsts[i], std::to_string(i));
    EXPECT_EQ(seconds[i], std::to_string(i));
    // A job's second part comes after its own first part.
    const auto a = std::find(log.begin(), log.end(), "a" + std::to_string(i));
    const auto b = std::find(log.begin(), log.end(), "b" + std::to_string(i));
    EXPECT_LT(a, b);
  }
  EXPECT_TRUE(overlapped);
  ASSERT_EQ(first_threads.size(), 1u);
  ASSERT_EQ(second_threads.size(), 1u);
  EXPECT_NE(*first_threads.begin(), *second_threads.begin());
}

TEST(KeyframeWorker, AFailedFirstPartSkipsItsSecondPart) {
  for (int stages : {1, 2})
    for (bool threaded : {true, false}) {
      KeyframeWorker worker(threaded, stages);
      std::atomic<int> seconds{0};
      worker.submit([] { throw std::runtime_error("detection failed"); }, [&] { ++seconds; });
      worker.submit([] {}, [&] { ++seconds; });
      worker.wait_idle();
      EXPECT_EQ(seconds, 1) << "stages " << stages << " threaded " << threaded;
      EXPECT_THROW(worker.rethrow_if_failed(), std::runtime_error);
      EXPECT_TRUE(worker.idle());
    }
}

// Both stages' threads, and threads they start (the networks' helpers), run `nice` levels below
// the caller; the caller keeps its own level.
TEST(KeyframeWorker, ItsThreadsRunBelowTheCallersPriority) {
  const int caller = KeyframeWorker::thread_nice();
  if (caller > 19 - 5) GTEST_FAIL() << "this test needs a caller below nice 15, it runs at " << caller;
  std::vector<int> levels;
  std::mutex m;
  {
    KeyframeWorker worker(true, 2, 5);
    for (int i = 0; i < 3; ++i)
      worker.submit(
          [&] {
            std::lock_guard<std::mutex> lock(m);
            levels.push_back(KeyframeWorker::thread_nice());
          },
          [&] {
            int helper = -100;
            std::thread([&] { helper = KeyframeWorker::thread_nice(); }).join();
            std::lock_guard<std::mutex> lock(m);
            levels.push_back(KeyframeWorker::thread_nice());
            levels.push_back(helper);
          });
    worker.wait_idle();
  }
  EXPECT_EQ(levels, std::vector<int>(9, caller + 5));
  EXPECT_EQ(KeyframeWorker::thread_nice(), caller);
  EXPECT_THROW(KeyframeWorker(true, 2, 20), InternalError);
}

TEST(KeyframeWorker, RejectsAStageCountItDoesNotHave) {
  EXPECT_THROW(KeyframeWorker(true, 3), InternalError);
  EXPECT_THROW(KeyframeWorker(false, 0), InternalError);
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
