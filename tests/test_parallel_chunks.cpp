// run_beside (odometry/kernels/parallel_chunks.h): both functions run once, main on the calling
// thread; with one thread in the order main, beside; an exception from either side reaches
// the caller only after both have stopped, main's first.
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "odometry/kernels/parallel_chunks.h"

namespace {

using bivo::odometry::run_beside;

TEST(RunBeside, OneThreadRunsMainThenBesideOnTheCaller) {
  std::vector<std::string> order;
  const auto caller = std::this_thread::get_id();
  std::thread::id beside_thread;
  run_beside(
      1, [&] { order.push_back("main"); },
      [&] {
        order.push_back("beside");
        beside_thread = std::this_thread::get_id();
      });
  EXPECT_EQ(order, (std::vector<std::string>{"main", "beside"}));
  EXPECT_EQ(beside_thread, caller);
}

TEST(RunBeside, TwoThreadsRunEachOnceMainOnTheCaller) {
  for (int round = 0; round < 50; ++round) {
    std::atomic<int> mains{0}, besides{0};
    std::thread::id main_thread;
    run_beside(
        2,
        [&] {
          main_thread = std::this_thread::get_id();
          ++mains;
        },
        [&] { ++besides; });
    EXPECT_EQ(mains.load(), 1);
    EXPECT_EQ(besides.load(), 1);
    EXPECT_EQ(main_thread, std::this_thread::get_id());
  }
}

// Main's own parallel loops still cover every chunk while beside runs.
TEST(RunBeside, MainsChunksAllRunBesideALongTask) {
  std::vector<int> seen(64, 0);
  std::atomic<bool> beside_done{false};
  run_beside(
      2, [&] { bivo::odometry::for_each_chunk(64, 2, [&](int c) { seen[static_cast<std::size_t>(c)] += 1; }); },
      [&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));  // longer than main
        beside_done = true;
      });
  EXPECT_TRUE(beside_done.load());  // run_beside returned only after it
  for (int c = 0; c < 64; ++c) EXPECT_EQ(seen[static_cast<std::size_t>(c)], 1) << c;
}

TEST(RunBeside, BesidesExceptionReachesTheCallerAfterMain) {
  for (int threads : {1, 2}) {
    bool main_ran = false;
    try {
      run_beside(
          threads, [&] { main_ran = true; }, [] { throw std::runtime_error("beside failed"); });
      ADD_FAILURE() << "no exception, threads " << threads;
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), "beside failed");
    }
    EXPECT_TRUE(main_ran) << threads;
  }
}

TEST(RunBeside, MainsExceptionWaitsForBesideAndWinsOverIts) {
  for (int threads : {1, 2}) {
    for (bool beside_throws : {false, true}) {
      std::atomic<bool> beside_done{false};
      try {
        run_beside(
            threads, [] { throw std::runtime_error("main failed"); },
            [&] {
              std::this_thread::sleep_for(std::chrono::milliseconds(5));
              beside_done = true;
              if (beside_throws) throw std::runtime_error("beside failed");
            });
        ADD_FAILURE() << "no exception, threads " << threads;
      } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()), "main failed") << threads;
      }
      // With one thread main's exception leaves before beside starts: nothing to wait for.
      if (threads > 1) {
        EXPECT_TRUE(beside_done.load()) << beside_throws;
      }
    }
  }
}

}  // namespace
