#include "odometry/kernels/pooled_floats.h"

#include <algorithm>
#include <memory>
#include <mutex>
#include <new>
#include <vector>

namespace bivo::odometry {
namespace {

// Set when this thread's pool is closed (thread exit): arrays allocated on this thread after
// that (while statics of the main thread are destroyed) are freed on release.
thread_local bool pool_closed = false;

}  // namespace

// Its own thread takes blocks out; any thread puts them back (under the mutex). Closed at
// its thread's exit: blocks released after that are freed.
struct FloatPool {
  struct Block {
    AlignedFloats data;
    std::size_t capacity = 0;
  };
  std::mutex mutex;
  std::vector<Block> blocks;
  bool open = true;
};

namespace {

// This thread's pool, kept alive by the arrays holding its blocks.
std::shared_ptr<FloatPool> this_thread_pool() {
  struct Holder {
    std::shared_ptr<FloatPool> pool = std::make_shared<FloatPool>();
    ~Holder() {
      pool_closed = true;
      const std::lock_guard<std::mutex> lock(pool->mutex);
      pool->open = false;
      pool->blocks.clear();
    }
  };
  if (pool_closed) return nullptr;
  thread_local Holder holder;
  return holder.pool;
}

}  // namespace

void AlignedFloatsDelete::operator()(float* p) const { ::operator delete[](p, std::align_val_t{kAlignment}); }

PooledFloats::PooledFloats(std::size_t n) { reset(n); }

PooledFloats::~PooledFloats() { release(); }

PooledFloats::PooledFloats(PooledFloats&& o) noexcept
    : data_(std::move(o.data_)), size_(o.size_), capacity_(o.capacity_), origin_(std::move(o.origin_)) {
  o.size_ = o.capacity_ = 0;
}

PooledFloats& PooledFloats::operator=(PooledFloats&& o) noexcept {
  if (this != &o) {
    release();
    data_ = std::move(o.data_);
    size_ = o.size_;
    capacity_ = o.capacity_;
    origin_ = std::move(o.origin_);
    o.size_ = o.capacity_ = 0;
  }
  return *this;
}

void PooledFloats::reset(std::size_t n) {
  if (n <= capacity_) {
    size_ = n;
    return;
  }
  release();
  if (n == 0) return;
  // The smallest pooled block that holds n; else a new one with room for the next frame's
  // slightly larger count of the same level.
  origin_ = this_thread_pool();
  if (origin_) {
    const std::lock_guard<std::mutex> lock(origin_->mutex);
    std::vector<FloatPool::Block>& blocks = origin_->blocks;
    auto best = blocks.end();
    for (auto it = blocks.begin(); it != blocks.end(); ++it) {
      if (it->capacity >= n && (best == blocks.end() || it->capacity < best->capacity)) best = it;
    }
    if (best != blocks.end()) {
      data_ = std::move(best->data);
      capacity_ = best->capacity;
      blocks.erase(best);
    }
  }
  if (!data_) {
    capacity_ = n + n / 8;
    data_.reset(static_cast<float*>(
        ::operator new[](capacity_ * sizeof(float), std::align_val_t{AlignedFloatsDelete::kAlignment})));
  }
  size_ = n;
}

void PooledFloats::fill_from(std::size_t from, float value) {
  if (from < size_) std::fill(data_.get() + from, data_.get() + size_, value);
}

void PooledFloats::release() {
  if (!data_) return;
  const std::size_t capacity = capacity_;
  size_ = capacity_ = 0;
  const std::shared_ptr<FloatPool> origin = std::move(origin_);
  if (!origin) {
    data_.reset();
    return;
  }
  const std::lock_guard<std::mutex> lock(origin->mutex);
  if (!origin->open) {
    data_.reset();
    return;
  }
  std::vector<FloatPool::Block>& blocks = origin->blocks;
  blocks.push_back({std::move(data_), capacity});
  if (blocks.size() > kMaxPooledBlocks) {
    const auto smallest =
        std::min_element(blocks.begin(), blocks.end(),
                         [](const FloatPool::Block& a, const FloatPool::Block& b) { return a.capacity < b.capacity; });
    blocks.erase(smallest);
  }
}

std::size_t PooledFloats::pooled_blocks() {
  const std::shared_ptr<FloatPool> pool = this_thread_pool();
  if (!pool) return 0;
  const std::lock_guard<std::mutex> lock(pool->mutex);
  return pool->blocks.size();
}

}  // namespace bivo::odometry
