// PooledFloats (odometry/kernels/pooled_floats.h): a released block is taken back by the next array
// that fits, on the thread that allocated it, wherever it was released.
#include <cstdint>
#include <future>
#include <thread>

#include <gtest/gtest.h>

#include "odometry/kernels/pooled_floats.h"

namespace {

using bivo::odometry::PooledFloats;

TEST(PooledFloats, APooledBlockIsTakenBackByTheNextArrayThatFits) {
  // Larger than any other block of this process (the pool drops its smallest blocks when
  // full); never written, so its pages are never touched.
  constexpr std::size_t kLarge = std::size_t(1) << 24;
  const float* block = nullptr;
  {
    PooledFloats first(kLarge);
    block = first.data();
    // A cache line per sixteen-lane vector (glibc alone would give 16 past a page start).
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(block) % 64, 0u);
  }
  PooledFloats second(kLarge - 100);  // the smallest pooled block that holds it
  EXPECT_EQ(second.data(), block);
  EXPECT_EQ(second.size(), kLarge - 100);
  PooledFloats moved = std::move(second);
  EXPECT_EQ(moved.data(), block);
  EXPECT_EQ(second.size(), 0u);
}

// A frame prepared on a worker and dropped by the tracking thread (sequence_tracking.h): its
// blocks go back to the worker, whose next frame takes them; the tracking thread's pool
// does not grow.
TEST(PooledFloats, ABlockGoesBackToThePoolOfTheThreadThatAllocatedIt) {
  constexpr std::size_t kLarge = (std::size_t(1) << 24) + 4096;  // larger than any other block here
  std::promise<PooledFloats> handed_over;
  std::promise<void> released;
  std::future<void> released_done = released.get_future();
  const float* block = nullptr;
  const float* again = nullptr;
  std::size_t worker_pool_after_release = 0;
  std::thread worker([&] {
    PooledFloats mine(kLarge);
    block = mine.data();
    handed_over.set_value(std::move(mine));
    released_done.wait();
    worker_pool_after_release = PooledFloats::pooled_blocks();
    PooledFloats next(kLarge - 64);
    again = next.data();
  });
  const std::size_t pooled_here = PooledFloats::pooled_blocks();
  {
    PooledFloats taken = handed_over.get_future().get();
    EXPECT_EQ(taken.data(), block);
  }  // released on this thread
  EXPECT_EQ(PooledFloats::pooled_blocks(), pooled_here);
  released.set_value();
  worker.join();
  EXPECT_EQ(worker_pool_after_release, 1u);
  EXPECT_EQ(again, block);
  // The worker has exited: a block of its pool released now is freed, not pooled.
  PooledFloats orphan;
  {
    std::promise<PooledFloats> out;
    std::thread t([&] { out.set_value(PooledFloats(1000)); });
    orphan = out.get_future().get();
    t.join();
  }
  orphan = PooledFloats();  // releases into the closed pool: no crash, nothing pooled here
  EXPECT_EQ(PooledFloats::pooled_blocks(), pooled_here);
}

}  // namespace
