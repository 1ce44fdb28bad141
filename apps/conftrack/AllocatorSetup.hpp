#pragma once

/// @file AllocatorSetup.hpp
/// The CLI's malloc settings (glibc only; elsewhere a no-op).

namespace conftrack::cli {

/// Keeps freed memory in the process and backs the main heap with
/// transparent huge pages where the kernel offers them (THP `madvise` or
/// `always`). The finder's cell caches, hit pools and per-event arrays are
/// large and short-lived: with glibc's defaults they are returned to the
/// system when freed and faulted in again, page by page, for the next step
/// and event (34,000 minor faults on a real TrackML event). Results do not
/// depend on it (allocation only). Call once, first thing in main().
/// Returns false where it could not act (not glibc, or glibc refused the
/// settings).
bool setUpAllocator();

}  // namespace conftrack::cli
