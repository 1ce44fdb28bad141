/// @file ReconstructionConfig.cpp
/// Reading a chain file into the whole reconstruction's settings: the
/// finder's tables and the track selection's [selection] table.

#include "conftrack/core/ConfigTable.hpp"
#include "conftrack/core/DataFiles.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"

#include <limits>

namespace conftrack {

namespace {

/// An optional count that must fit std::uint32_t.
std::uint32_t count(const ConfigTable& t, std::string_view key,
                    std::uint32_t fallback) {
  return static_cast<std::uint32_t>(
      t.getInt(key, fallback,
               Range::closed(0, std::numeric_limits<std::uint32_t>::max())));
}

/// The [selection] table over `defaults`; the values' sense is checked by
/// the TrackSelector constructor, whose message is located at the key.
TrackSelector::Config readSelection(const ConfigTable& t,
                                    TrackSelector::Config c) {
  c.minHits = count(t, "min_hits", c.minHits);
  c.cloneSharedHits = count(t, "clone_shared_hits", c.cloneSharedHits);
  c.minUniqueHits = count(t, "min_unique_hits", c.minUniqueHits);
  c.dropOutliers = t.getBool("drop_outliers", c.dropOutliers);
  t.rejectUnknownKeys();
  if (std::optional<TrackSelector::Problem> p = TrackSelector::findProblem(c)) {
    t.fail(p->key, p->what);
  }
  return c;
}

}  // namespace

Reconstruction::Config readReconstructionTable(const ConfigTable& root,
                                               const Detector& detector) {
  Reconstruction::Config config;
  if (std::optional<ConfigTable> selection = root.findTable("selection")) {
    config.selector = readSelection(*selection, config.selector);
  }
  config.chain = readChainTable(root, detector);
  return config;
}

Reconstruction::Config parseReconstructionConfig(std::string_view text,
                                                 const std::string& sourceName,
                                                 const Detector& detector) {
  std::shared_ptr<toml::table> table = ConfigTable::parse(text, sourceName);
  return readReconstructionTable(ConfigTable(*table, sourceName, ""), detector);
}

Reconstruction::Config readReconstructionConfig(
    const std::filesystem::path& chainFile, const Detector& detector) {
  return parseReconstructionConfig(readConfigText(chainFile, "chain"),
                                   chainFile.string(), detector);
}

}  // namespace conftrack
