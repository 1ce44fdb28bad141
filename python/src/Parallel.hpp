#pragma once

/// @file Parallel.hpp
/// A parallel loop over events for the Python module: call it with the GIL
/// released; results must not depend on the thread count.

#include <cstddef>
#include <functional>

namespace conftrack::python {

/// Runs fn(i) for i in [0, n) on `threads` threads (0: all cores), each
/// thread taking the next index in increasing order when it is free. If some
/// calls throw, the exception of the lowest index is rethrown once all
/// have run, whatever the thread count.
void forEachIndex(std::size_t n, std::size_t threads,
                  const std::function<void(std::size_t)>& fn);

}  // namespace conftrack::python
