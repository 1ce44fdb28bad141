#include "Parallel.hpp"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <exception>
#include <vector>

namespace conftrack::python {

void forEachIndex(std::size_t n, std::size_t threads,
                  const std::function<void(std::size_t)>& fn) {
  std::vector<std::exception_ptr> errors(n);
  auto body = [&](std::size_t i) {
    try {
      fn(i);
    } catch (...) {
      errors[i] = std::current_exception();
    }
  };
  if (threads == 1 || n <= 1) {
    for (std::size_t i = 0; i < n; ++i) {
      body(i);
    }
  } else {
    tbb::task_arena arena(threads == 0 ? tbb::task_arena::automatic
                                       : static_cast<int>(threads));
    // Events in the caller's order, each to the next free thread (an
    // atomic counter, not range splitting): events differ a lot in cost,
    // and a caller that puts the large ones first gets threads that finish
    // together.
    std::atomic<std::size_t> next{0};
    arena.execute([&] {
      tbb::parallel_for(0, arena.max_concurrency(), [&](int) {
        for (std::size_t i = next++; i < n; i = next++) {
          body(i);
        }
      });
    });
  }
  for (const std::exception_ptr& e : errors) {
    if (e) {
      std::rethrow_exception(e);
    }
  }
}

}  // namespace conftrack::python
