#pragma once

// Test support: the one-line message of a refused input.

#include "conftrack/core/Error.hpp"

#include <string>
#include <utility>

namespace conftrack::test {

/// The message of the InputError that `read()` throws, or "(accepted)" if
/// it throws none.
template <class Read>
std::string inputErrorOf(Read&& read) {
  try {
    std::forward<Read>(read)();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

}  // namespace conftrack::test
