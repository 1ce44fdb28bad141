/// @file AllocatorSetupTests.cpp
/// The CLI's malloc setup (apps/conftrack/AllocatorSetup.hpp): memory the
/// finder frees between steps and events stays in the process, so that
/// the next step's arrays are not faulted in again page by page.

#include <gtest/gtest.h>

#include <cstddef>
#include <memory>
#include <sys/resource.h>

#include "AllocatorSetup.hpp"

namespace conftrack {
namespace {

long minorFaults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

/// Minor page faults of allocating, writing and freeing `bytes`.
long faultsOfAFreshArray(std::size_t bytes) {
  const long before = minorFaults();
  {
    auto array = std::make_unique<char[]>(bytes);  // zeroed: every page
    array[bytes - 1] = 1;
    EXPECT_EQ(array[0] + array[bytes - 1], 1);
  }
  return minorFaults() - before;
}

TEST(AllocatorSetup, FreedArraysAreNotFaultedInAgain) {
#if defined(__SANITIZE_ADDRESS__) || !defined(__GLIBC__)
  GTEST_SKIP() << "the setup is for glibc's malloc";
#else
  // 48 MB: above glibc's largest adaptive mmap threshold (32 MB), so with
  // its defaults every such array is a fresh mapping, 12,288 pages of
  // 4 kB faulted in each time.
  constexpr std::size_t kBytes = std::size_t{48} << 20;
  ASSERT_TRUE(cli::setUpAllocator());
  faultsOfAFreshArray(kBytes);  // the first time the memory is new
  const long again = faultsOfAFreshArray(kBytes);
  EXPECT_LT(again, 200) << "minor faults of the second 48 MB array";
#endif
}

}  // namespace
}  // namespace conftrack
