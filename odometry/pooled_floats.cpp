#include "odometry/pooled_floats.h"

#include <algorithm>
#include <new>
#include <vector>

namespace bivo::odometry {
namespace {

struct Block {
  AlignedFloats data;
  std::size_t capacity = 0;
};

// Set when this thread's pool is gone (thread exit): arrays destroyed after it (statics
// of the main thread) free their block instead.
thread_local bool pool_destroyed = false;

struct Pool {
  std::vector<Block> blocks;
  ~Pool() { pool_destroyed = true; }
};

std::vector<Block>& pool() {
  thread_local Pool p;
  return p.blocks;
}

}  // namespace

void AlignedFloatsDelete::operator()(float* p) const { ::operator delete[](p, std::align_val_t{kAlignment}); }

PooledFloats::PooledFloats(std::size_t n) { reset(n); }

PooledFloats::~PooledFloats() { release(); }

PooledFloats::PooledFloats(PooledFloats&& o) noexcept
    : data_(std::move(o.data_)), size_(o.size_), capacity_(o.capacity_) {
  o.size_ = o.capacity_ = 0;
}

PooledFloats& PooledFloats::operator=(PooledFloats&& o) noexcept {
  if (this != &o) {
    release();
    data_ = std::move(o.data_);
    size_ = o.size_;
    capacity_ = o.capacity_;
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
  std::vector<Block>& blocks = pool();
  auto best = blocks.end();
  for (auto it = blocks.begin(); it != blocks.end(); ++it) {
    if (it->capacity >= n && (best == blocks.end() || it->capacity < best->capacity)) best = it;
  }
  if (best != blocks.end()) {
    data_ = std::move(best->data);
    capacity_ = best->capacity;
    blocks.erase(best);
  } else {
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
  if (pool_destroyed) {
    data_.reset();
    return;
  }
  std::vector<Block>& blocks = pool();
  blocks.push_back({std::move(data_), capacity});
  if (blocks.size() > kMaxPooledBlocks) {
    const auto smallest = std::min_element(blocks.begin(), blocks.end(),
                                           [](const Block& a, const Block& b) { return a.capacity < b.capacity; });
    blocks.erase(smallest);
  }
}

std::size_t PooledFloats::pooled_blocks() { return pool().size(); }

}  // namespace bivo::odometry
