/// @file main.cpp
/// libFuzzer entry point of one target; the target is chosen at compile time
/// (CONFTRACK_FUZZ_TARGET, see fuzz/CMakeLists.txt) and its body lives in
/// targets/FuzzTargets.cpp, shared with the regression test.

#include "conftrack/core/Log.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "FuzzTargets.hpp"

namespace {

const conftrack::fuzz::Target& target() {
  static const conftrack::fuzz::Target* t =
      conftrack::fuzz::findTarget(CONFTRACK_FUZZ_TARGET);
  if (t == nullptr) {
    std::fprintf(stderr, "no fuzz target '%s'\n", CONFTRACK_FUZZ_TARGET);
    std::abort();
  }
  return *t;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  // Readers may warn; millions of lines on stderr would only slow the run.
  conftrack::log::setLevel(conftrack::log::Level::eError);
  target();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data,
                                      std::size_t size) {
  target().run(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
