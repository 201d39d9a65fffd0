// SPDX-License-Identifier: MIT
// Loops whose iterations are independent, on several threads natively (one in a wasm build without
// pthreads). Each iteration writes only its own outputs; whatever is summed over them is summed
// afterwards in index order, so the result is the same on any number of threads.
#pragma once
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace omnislice {

// Threads for a `threads` setting: 0 = every core; always 1 in wasm without pthreads.
inline size_t threadCount(int setting) {
#if defined(__EMSCRIPTEN__) && !defined(__EMSCRIPTEN_PTHREADS__)
  (void)setting;
  return 1;
#else
  if (setting > 0) return size_t(setting);
  return std::max(1u, std::thread::hardware_concurrency());
#endif
}

// fn(i, worker) for i in [0, n) on up to `threads` threads (the caller's among them: worker 0; the
// others 1 ..; a worker's own scratch space can be indexed by it), iterations taken in order by
// whichever thread is free. tick(done) runs on the caller's thread only, after each
// iteration it ran, with the iterations finished so far; returning false stops the loop (no new
// iteration starts) and parallelFor returns false. An exception thrown by fn is rethrown here,
// after every thread has stopped.
template <class Fn, class Tick>
bool parallelFor(size_t n, size_t threads, Fn&& fn, Tick&& tick) {
  threads = std::max<size_t>(1, std::min(threads, n));
  std::atomic<size_t> next{0}, done{0};
  std::atomic<bool> stop{false};
  std::exception_ptr error;
  std::mutex errorLock;
  auto work = [&](size_t worker) {
    const bool caller = worker == 0;
    for (size_t i; !stop && (i = next++) < n;) {
      try {
        fn(i, worker);
      } catch (...) {
        std::lock_guard<std::mutex> lock(errorLock);
        if (!error) error = std::current_exception();
        stop = true;
        return;
      }
      const size_t d = ++done;
      if (caller && !tick(d)) stop = true;
    }
  };
  std::vector<std::thread> pool;
  for (size_t t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
  return !stop;
}

template <class Fn>
void parallelFor(size_t n, size_t threads, Fn&& fn) {
  parallelFor(n, threads, std::forward<Fn>(fn), [](size_t) { return true; });
}

}  // namespace omnislice
