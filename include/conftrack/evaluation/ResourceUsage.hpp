#pragma once

/// @file ResourceUsage.hpp
/// Process resource usage for the performance report.

namespace conftrack {

/// Peak resident set size of this process in MiB (2^20 bytes), read from
/// VmHWM in /proc/self/status; NaN where that is not available (not
/// Linux).
double peakRssMb();

}  // namespace conftrack
