#pragma once
// A float array whose memory outlives it: released blocks go to a per-thread pool and the
// next array of about the same size takes them back. The per-level problems of a frame pair
// hold ~12 MB of structure-of-arrays buffers at 640x480 (reference terms, residuals,
// gradients, weights); allocated afresh for every pair, each of their pages was faulted in
// and zeroed by the kernel again (docs/odometry.md "Speed"). With the pool, the problems of
// pair k + 1 reuse the pages of pair k.
//
// A released block goes back to the pool of the thread that allocated it, wherever it is
// released: a frame prepared on a worker (sequence_tracking.h) and dropped by the tracking
// thread two pairs later returns its blocks to the worker, which prepares the next frame
// with them. (Into the releasing thread's pool, the worker allocated every frame anew and
// the tracking thread's pool filled up with blocks it never asked for: 300 MB resident
// instead of 60 for fr1/rpy on two threads.)
//
// The entries of a new array are NOT initialized (a reused block holds whatever floats its
// previous owner wrote); callers write before they read, and zero their padding themselves.
// The pool keeps at most kMaxPooledBlocks blocks per thread (the smallest go first): one
// pair's problems at four levels (12 blocks each) and a few frames' interleaved levels.
#include <cstddef>
#include <memory>

namespace bivo::odometry {

// Blocks start on a 64-byte boundary (a cache line, one sixteen-lane vector): glibc places
// large blocks 16 bytes past a page start, so every 64-byte load of the AVX-512 kernels
// would straddle two cache lines.
struct AlignedFloatsDelete {
  static constexpr std::size_t kAlignment = 64;
  void operator()(float* p) const;
};
using AlignedFloats = std::unique_ptr<float[], AlignedFloatsDelete>;

struct FloatPool;  // one thread's released blocks (pooled_floats.cpp)

class PooledFloats {
 public:
  static constexpr std::size_t kMaxPooledBlocks = 96;

  PooledFloats() = default;
  explicit PooledFloats(std::size_t n);
  ~PooledFloats();
  PooledFloats(PooledFloats&& o) noexcept;
  PooledFloats& operator=(PooledFloats&& o) noexcept;
  PooledFloats(const PooledFloats&) = delete;
  PooledFloats& operator=(const PooledFloats&) = delete;

  // n entries (uninitialized, see above); the previous block goes back to the pool.
  void reset(std::size_t n);
  // Entries [from, size()) set to value.
  void fill_from(std::size_t from, float value);

  float* data() { return data_.get(); }
  const float* data() const { return data_.get(); }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  float& operator[](std::size_t i) { return data_[i]; }
  float operator[](std::size_t i) const { return data_[i]; }

  // Blocks waiting in this thread's pool (for tests).
  static std::size_t pooled_blocks();

 private:
  void release();
  AlignedFloats data_;
  std::size_t size_ = 0, capacity_ = 0;
  std::shared_ptr<FloatPool> origin_;  // the pool data_ goes back to (null: freed)
};

}  // namespace bivo::odometry
