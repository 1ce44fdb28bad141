#pragma once

/// @file FuzzTargets.hpp
/// The bodies of conftrack's libFuzzer targets (docs/fuzzing.md), one per
/// reader of outside input. Shared by the fuzzer executables (fuzz/main.cpp)
/// and the regression test (tests/fuzz/FuzzRegressionTests.cpp), so that a
/// stored crash input replays through exactly the path that crashed.
///
/// A target hands the bytes to the real reader through its in-memory entry
/// point (parseHits, parseDetector, readHepMCEvents, ...). InputError, the
/// refusal of bad input, is the expected outcome for most inputs and is
/// caught; anything else (another exception, a crash, a sanitizer report)
/// escapes and is a finding.

#include <span>
#include <string_view>

namespace conftrack::fuzz {

/// How a reader ended on one input.
enum class Outcome {
  eAccepted,  ///< every reader call returned normally
  eRefused,   ///< at least one reader call threw InputError
};

/// One fuzz target.
struct Target {
  /// Name of the executable (fuzz_<name>), the corpus folder
  /// fuzz/corpus/<name>/ and the regression folder fuzz/regressions/<name>/.
  std::string_view name;
  /// Runs the reader(s) on `data`; lets everything but InputError escape.
  Outcome (*run)(std::string_view data);
};

/// All targets.
std::span<const Target> targets();

/// The target called `name`, or nullptr.
const Target* findTarget(std::string_view name);

}  // namespace conftrack::fuzz
