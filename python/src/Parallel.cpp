#include "Parallel.hpp"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

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
    arena.execute([&] {
      // One event per task: events differ a lot in cost.
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1),
                        [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t i = range.begin(); i < range.end();
                               ++i) {
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
