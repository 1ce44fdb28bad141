#pragma once

/// @file EventLoop.hpp
/// What several subcommands share: the sample options (generator, overlay,
/// seed, simulation switches), the --threads option, and a parallel loop
/// over events with progress.

#include "conftrack/simulation/EventSimulation.hpp"
#include "conftrack/simulation/LuminousRegion.hpp"

#include <CLI/CLI.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace conftrack::cli {

/// Command-line choice of a luminous region.
struct LuminousRegionOptions {
  /// --luminous-region: a preset name (empty: not given).
  std::string preset;
  /// --beam-sigma-z: sigma z [mm, as typed], replacing the preset's.
  std::optional<double> sigmaZ;
};

/// Adds --luminous-region PRESET and --beam-sigma-z MM; `purpose` ends the
/// help text of --luminous-region (what the region is used for).
void addLuminousRegionOptions(CLI::App& cmd, LuminousRegionOptions& options,
                              const std::string& purpose);
/// The region the options choose: the preset (or a point at the origin)
/// with --beam-sigma-z as its length; nullopt if neither option is given.
std::optional<LuminousRegion::Config> chosenLuminousRegion(
    const LuminousRegionOptions& options);

/// Command-line description of a simulated sample.
struct SampleOptions {
  std::string sample = "ttbar3tev";
  std::size_t overlayBx = 0;
  std::uint64_t seed = 1;
  std::string configFile;
  std::vector<std::string> settings;  ///< --gen key=value
  bool noMultipleScattering = false;
  bool noEnergyLoss = false;
  bool noTimeWindow = false;
  LuminousRegionOptions luminousRegion;
  bool moduleLevel = false;  ///< --module-level
};

/// Adds --sample, --overlay-bx, --seed, --config, --gen, --no-ms,
/// --no-eloss, --no-time-window, --luminous-region, --beam-sigma-z,
/// --module-level.
void addSampleOptions(CLI::App& cmd, SampleOptions& options);
/// With --module-level, the sensors of `detector` from its shipped layout
/// file (geometry/LayoutFile.hpp), for EventSimulation::Config::modules; else
/// null. InputError if the detector has no layout file.
std::shared_ptr<const ModuleLayout> loadModuleLayout(
    const SampleOptions& options, const Detector& detector);
/// Turns the options into an EventSimulation configuration (reads the
/// --config file). Throws InputError for bad values.
EventSimulation::Config makeSimulationConfig(const SampleOptions& options);

/// --shard K/N: the K-th (0-based) of N contiguous slices of a run's
/// events, for running one run as N processes (docs/cluster.md).
struct ShardOption {
  std::size_t index = 0;
  std::size_t count = 1;
};

/// Most shards --shard accepts.
inline constexpr std::size_t kMaxShards = 1000000;

/// Adds --shard K/N ("K/N" with 0 <= K < N <= kMaxShards; refused with a
/// one-line message otherwise).
void addShardOption(CLI::App& cmd, ShardOption& shard);

/// The event indices [first, second) of `shard` among `n` events:
/// [n K / N, n (K + 1) / N), so the shards tile the events in order and
/// differ in size by at most one (a shard may be empty when N > n).
std::pair<std::size_t, std::size_t> shardRange(std::size_t n,
                                               const ShardOption& shard);

/// Adds -j,--threads (0: all cores).
void addThreadsOption(CLI::App& cmd, std::size_t& threads);

/// Runs fn(i) for i in [0, n) on `threads` threads (0: all cores) with a
/// progress report. Exceptions from fn propagate (the first one).
void forEachEvent(std::size_t n, std::size_t threads, const std::string& label,
                  const std::function<void(std::size_t)>& fn);

/// The event numbers in a folder of event files; InputError if none.
std::vector<std::uint64_t> requireEvents(const std::string& dir);

/// `requested` if given (each must be in `dir`, else InputError), else every
/// event of `dir` (requireEvents).
std::vector<std::uint64_t> selectEvents(
    const std::string& dir, const std::vector<std::uint64_t>& requested);

/// Number of threads `threads` stands for (0: hardware concurrency).
std::size_t effectiveThreads(std::size_t threads);

}  // namespace conftrack::cli
