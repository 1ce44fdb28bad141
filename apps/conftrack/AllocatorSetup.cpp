#include "AllocatorSetup.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>

#if defined(__GLIBC__)
#include <malloc.h>
#include <sys/mman.h>
#endif

namespace conftrack::cli {

bool setUpAllocator() {
#if defined(__GLIBC__)
  // Allocations up to this size come from the heap, not from their own
  // mappings, and the heap is not trimmed below this much free memory
  // (glibc's defaults adapt between 128 kB and 32 MB and trim at twice
  // that, so the finder's arrays of a few MB to tens of MB went back to
  // the system after every step).
  constexpr std::size_t kMiB = std::size_t{1} << 20;
  constexpr std::size_t kMmapThreshold = 512 * kMiB;
  constexpr std::size_t kTrimThreshold = 1024 * kMiB;
  constexpr std::size_t kHugeRegion = 256 * kMiB;
  if (mallopt(M_MMAP_THRESHOLD, static_cast<int>(kMmapThreshold)) == 0 ||
      mallopt(M_TRIM_THRESHOLD, static_cast<int>(kTrimThreshold)) == 0) {
    return false;  // this glibc refuses them: keep its defaults
  }
  // Grow the heap by one large region, mark it for huge pages and give it
  // back to malloc, which keeps it (the trim threshold above) and serves
  // the following allocations from it. Nothing is touched here: memory is
  // only committed where it is used, 2 MB at a time.
  void* block = std::malloc(kHugeRegion);
  if (block == nullptr) {
    return true;  // the settings above still act
  }
  constexpr std::uintptr_t kHugePage = 2 * kMiB;
  const auto begin = reinterpret_cast<std::uintptr_t>(block);
  const std::uintptr_t first = (begin + kHugePage - 1) & ~(kHugePage - 1);
  const std::uintptr_t last = (begin + kHugeRegion) & ~(kHugePage - 1);
  if (last > first) {
    // Refused where the kernel has no THP: then the heap stays as it is.
    madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
  }
  std::free(block);
  return true;
#else
  return false;
#endif
}

}  // namespace conftrack::cli
