#include "odometry/kernels/parallel_chunks.h"

#include <map>
#include <memory>

namespace bivo::odometry {

tbb::task_arena& chunk_arena(int threads) {
  // Per calling thread: an arena admits a fixed number of external threads, and two callers
  // sharing one would queue behind each other.
  thread_local std::map<int, std::unique_ptr<tbb::task_arena>> arenas;
  std::unique_ptr<tbb::task_arena>& arena = arenas[threads];
  if (!arena) arena = std::make_unique<tbb::task_arena>(threads);
  return *arena;
}

}  // namespace bivo::odometry
