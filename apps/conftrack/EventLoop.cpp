#include "EventLoop.hpp"

#include "conftrack/core/DataFiles.hpp"
#include "conftrack/core/Error.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/frontend/ReconstructionSetup.hpp"
#include "conftrack/io/EventFiles.hpp"

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <optional>
#include <thread>

#include "OptionChecks.hpp"
#include "Progress.hpp"

namespace conftrack::cli {

void addLuminousRegionOptions(CLI::App& cmd, LuminousRegionOptions& o,
                              const std::string& purpose) {
  cmd.add_option("--luminous-region", o.preset,
                 "Luminous region preset: " + LuminousRegion::presetNames() +
                     " (docs/luminous-region.md); " + purpose)
      ->check(luminousRegionPreset());
  cmd.add_option("--beam-sigma-z", o.sigmaZ,
                 "Length (sigma z) of the luminous region [mm], replacing the "
                 "preset's; alone, a region at the origin with only this "
                 "length")
      ->check(finiteNumber(0.0, LuminousRegion::kMaxLength / units::mm));
}

std::optional<LuminousRegion::Config> chosenLuminousRegion(
    const LuminousRegionOptions& o) {
  if (o.preset.empty() && !o.sigmaZ) {
    return std::nullopt;
  }
  LuminousRegion::Config c;
  if (!o.preset.empty()) {
    // The option's validator has checked the name.
    c = LuminousRegion::findPreset(o.preset)->config;
  }
  if (o.sigmaZ) {
    c.sigmaZ = *o.sigmaZ * units::mm;
  }
  return c;
}

void addSampleOptions(CLI::App& cmd, SampleOptions& o) {
  cmd.add_option("--sample", o.sample,
                 "muons (particle gun), ttbar3tev, bb500, hepmc:<file>")
      ->capture_default_str();
  cmd.add_option("--overlay-bx", o.overlayBx,
                 "Bunch crossings of gamma gamma -> hadrons overlay")
      ->capture_default_str()
      ->check(wholeNumber(0, 100000));
  cmd.add_option("--seed", o.seed, "Run seed")
      ->capture_default_str()
      ->check(wholeNumber(0, UINT64_MAX));
  cmd.add_option("--config", o.configFile,
                 "Generator TOML file ([generator] and [overlay] tables)")
      ->check(CLI::ExistingFile);
  cmd.add_option("--gen", o.settings,
                 "Generator setting key=value, e.g. --gen p_GeV=10 --gen "
                 "theta_deg=89 (overlay keys as overlay.key=value)");
  cmd.add_flag("--no-ms", o.noMultipleScattering,
               "Switch off multiple scattering in the simulation");
  cmd.add_flag("--no-eloss", o.noEnergyLoss,
               "Switch off energy loss in the simulation");
  cmd.add_flag("--no-time-window", o.noTimeWindow,
               "Keep hits outside the 10 ns readout window");
  addLuminousRegionOptions(cmd, o.luminousRegion,
                           "default: clic3tev for ttbar3tev, bb500 and the "
                           "overlay, a point for muons, the file's vertices "
                           "for hepmc");
  cmd.add_flag("--module-level", o.moduleLevel,
               "Simulate the flat sensors of data/layouts/<detector>_layout"
               ".json.gz (CLICdet, CLD): overlapping sensors give two hits");
}

std::shared_ptr<const ModuleLayout> loadModuleLayout(const SampleOptions& o,
                                                     const Detector& detector) {
  return o.moduleLevel ? loadShippedLayout(detector) : nullptr;
}

EventSimulation::Config makeSimulationConfig(const SampleOptions& o) {
  EventSimulation::Config c;
  c.sample = o.sample;
  c.overlayBx = o.overlayBx;
  c.seed = o.seed;
  c.simulator.multipleScattering = !o.noMultipleScattering;
  c.simulator.energyLoss = !o.noEnergyLoss;
  c.applyTimeWindow = !o.noTimeWindow;
  c.luminousRegion = chosenLuminousRegion(o.luminousRegion);
  if (!o.configFile.empty() && !o.settings.empty()) {
    throw InputError("--config and --gen: give the settings in one of them");
  }
  if (!o.configFile.empty()) {
    c.generatorToml = readConfigText(o.configFile, "generator");
    c.generatorTomlSource = o.configFile;
  } else if (!o.settings.empty()) {
    std::string generator;
    std::string overlay;
    std::string region;
    for (const std::string& s : o.settings) {
      auto eq = s.find('=');
      if (eq == std::string::npos || eq == 0) {
        throw InputError("--gen " + s + ": expected key=value");
      }
      std::string key = s.substr(0, eq);
      std::string value = s.substr(eq + 1);
      // Values that are not numbers, booleans, arrays or quoted strings
      // are strings: --gen particle=mu-.
      double number = 0.0;
      auto [end, ec] =
          std::from_chars(value.data(), value.data() + value.size(), number);
      bool literal =
          (ec == std::errc() && end == value.data() + value.size()) ||
          value == "true" || value == "false" ||
          (!value.empty() && (value[0] == '[' || value[0] == '"'));
      if (!literal) {
        value = "\"" + value + "\"";
      }
      if (key.rfind("overlay.", 0) == 0) {
        overlay += key.substr(8) + " = " + value + "\n";
      } else if (key.rfind("luminous_region.", 0) == 0) {
        region += key.substr(16) + " = " + value + "\n";
      } else {
        generator += key + " = " + value + "\n";
      }
    }
    c.generatorToml = (generator.empty() ? "" : "[generator]\n" + generator) +
                      (overlay.empty() ? "" : "[overlay]\n" + overlay) +
                      (region.empty() ? "" : "[luminous_region]\n" + region);
    c.generatorTomlSource = "--gen options";
  }
  return c;
}

namespace {

/// "K/N" as a shard, or nullopt if it is not one.
std::optional<ShardOption> parseShard(const std::string& text) {
  const auto slash = text.find('/');
  if (slash == std::string::npos) {
    return std::nullopt;
  }
  auto whole = [](std::string_view digits, std::size_t& value) {
    const char* end = digits.data() + digits.size();
    auto [ptr, ec] = std::from_chars(digits.data(), end, value);
    return !digits.empty() && ptr == end && ec == std::errc{};
  };
  ShardOption shard;
  const std::string_view view(text);
  if (!whole(view.substr(0, slash), shard.index) ||
      !whole(view.substr(slash + 1), shard.count) || shard.count == 0 ||
      shard.count > kMaxShards || shard.index >= shard.count) {
    return std::nullopt;
  }
  return shard;
}

}  // namespace

void addShardOption(CLI::App& cmd, ShardOption& shard) {
  cmd.add_option_function<std::string>(
         "--shard",
         [&shard](const std::string& text) { shard = *parseShard(text); },
         "Process only the K-th of N slices of the events (K from 0; "
         "contiguous blocks by event number, so an event gives the same "
         "result in any shard); `conftrack merge` joins the reports")
      ->type_name("K/N")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            return parseShard(text)
                       ? ""
                       : "'" + text + "' is not K/N with 0 <= K < N <= " +
                             std::to_string(kMaxShards);
          },
          "K/N"));
}

std::pair<std::size_t, std::size_t> shardRange(std::size_t n,
                                               const ShardOption& shard) {
  // floor(n k / N) without forming n k: with n = q N + r it is
  // q k + floor(r k / N), and r k < N^2 <= 10^12.
  const std::size_t q = n / shard.count;
  const std::size_t r = n % shard.count;
  const auto bound = [&](std::size_t k) { return q * k + r * k / shard.count; };
  return {bound(shard.index), bound(shard.index + 1)};
}

void addThreadsOption(CLI::App& cmd, std::size_t& threads) {
  cmd.add_option("-j,--threads", threads, "Threads (0: all cores)")
      ->capture_default_str()
      ->check(wholeNumber(0, kMaxThreads));
}

std::vector<std::uint64_t> requireEvents(const std::string& dir) {
  std::vector<std::uint64_t> events = listEvents(dir);
  if (events.empty()) {
    throw InputError(dir, "no event files (eventNNNNNNNNN-hits.csv)");
  }
  return events;
}

std::vector<std::uint64_t> selectEvents(
    const std::string& dir, const std::vector<std::uint64_t>& requested) {
  std::vector<std::uint64_t> available = requireEvents(dir);
  if (requested.empty()) {
    return available;
  }
  for (std::uint64_t n : requested) {
    if (!std::binary_search(available.begin(), available.end(), n)) {
      throw InputError(dir, "no hits file of event " + std::to_string(n));
    }
  }
  return requested;
}

std::size_t effectiveThreads(std::size_t threads) {
  if (threads > 0) {
    return threads;
  }
  return std::max<std::size_t>(1, std::thread::hardware_concurrency());
}

void forEachEvent(std::size_t n, std::size_t threads, const std::string& label,
                  const std::function<void(std::size_t)>& fn) {
  Progress progress(label, n);
  const std::size_t nThreads = effectiveThreads(threads);
  // More threads than cores were asked for: TBB caps its workers at the
  // core count unless told otherwise (with a warning on stderr).
  std::optional<tbb::global_control> allow;
  if (nThreads > std::max(1u, std::thread::hardware_concurrency())) {
    allow.emplace(tbb::global_control::max_allowed_parallelism, nThreads);
  }
  tbb::task_arena arena(static_cast<int>(nThreads));
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i != r.end(); ++i) {
                          fn(i);
                          progress.advance();
                        }
                      });
  });
  progress.finish();
}

}  // namespace conftrack::cli
