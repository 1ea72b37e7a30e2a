#pragma once
// Chunked loops over the terms of a problem (or the rows of an image) whose results do not
// depend on the number of threads: work is cut into fixed chunks, each chunk's sums are kept
// apart, and the partial sums are added in chunk order afterwards. OpenMP (GCC's libgomp)
// runs the chunks; threads = 1 never enters a parallel region.
#include <cstddef>
#include <vector>

namespace bivo::odometry {

template <class Fn>
void for_each_chunk(int chunks, int threads, const Fn& fn) {
#ifdef _OPENMP
  if (threads > 1 && chunks > 1) {
#pragma omp parallel for num_threads(threads) schedule(static)
    for (int c = 0; c < chunks; ++c) fn(c);
    return;
  }
#endif
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

}  // namespace bivo::odometry
