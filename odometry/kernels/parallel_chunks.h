#pragma once
// Chunked loops over the terms of a problem (or the rows of an image) whose results do not
// depend on the number of threads: work is cut into fixed chunks, each chunk's sums are kept
// apart, and the partial sums are added in chunk order afterwards.
//
// oneTBB runs the chunks (work stealing, one chunk per task): the calling thread takes
// chunks itself and a worker only gets the chunks it steals while it runs, so the caller
// never waits at a barrier for a worker the scheduler has not given a core (on a loaded
// machine it then does all chunks itself, at one-thread speed). Static shares (OpenMP) wait
// for every worker: 2 threads were 20-50x slower than one under load. threads = 1 never
// enters TBB.
#include <cstddef>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

namespace bivo::odometry {

// An arena of `threads` slots (the caller's and threads - 1 workers'), one per count,
// made once per calling thread.
tbb::task_arena& chunk_arena(int threads);

template <class Fn>
void for_each_chunk(int chunks, int threads, const Fn& fn) {
  if (threads > 1 && chunks > 1) {
    chunk_arena(threads).execute([&] {
      tbb::parallel_for(
          tbb::blocked_range<int>(0, chunks, 1),
          [&](const tbb::blocked_range<int>& r) {
            for (int c = r.begin(); c != r.end(); ++c) fn(c);
          },
          tbb::simple_partitioner());
    });
    return;
  }
  for (int c = 0; c < chunks; ++c) fn(c);
}

// total = sum over chunks c of fn(begin_c, end_c), chunks of `chunk` items over [0, items),
// added in chunk order. Sums needs a default constructor and add(const Sums&).
template <class Sums, class Fn>
Sums sum_over_chunks(std::size_t items, std::size_t chunk, int threads, const Fn& fn) {
  const int chunks = static_cast<int>((items + chunk - 1) / chunk);
  std::vector<Sums> partial(static_cast<std::size_t>(chunks));
  for_each_chunk(chunks, threads, [&](int c) {
    const std::size_t begin = static_cast<std::size_t>(c) * chunk;
    const std::size_t end = begin + chunk < items ? begin + chunk : items;
    partial[static_cast<std::size_t>(c)] = fn(begin, end);
  });
  Sums total{};
  for (const Sums& p : partial) total.add(p);
  return total;
}

// Runs `main` on the calling thread and `beside` as one task of the same arena, returning when
// both are done: with threads > 1 a worker takes `beside` (coarse work that would otherwise sit
// between two of main's fine-grained parallel loops) and then steals main's chunks; the caller
// runs `beside` itself if no worker has taken it by the end of main. One thread: main, then
// beside (which then does not run when main throws). An exception from either is rethrown
// after both have stopped, main's when both throw.
template <class Main, class Beside>
void run_beside(int threads, const Main& main, const Beside& beside) {
  if (threads <= 1) {
    main();
    beside();
    return;
  }
  chunk_arena(threads).execute([&] {
    tbb::task_group group;
    group.run([&] { beside(); });
    try {
      main();
    } catch (...) {
      try {
        group.wait();
      } catch (...) {
      }
      throw;
    }
    group.wait();
  });
}

}  // namespace bivo::odometry
