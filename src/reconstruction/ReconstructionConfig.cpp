/// @file ReconstructionConfig.cpp
/// Reading a chain file into the whole reconstruction's settings: the
/// finder's tables and the track selection's [selection] table.

#include "conftrack/core/ConfigTable.hpp"
#include "conftrack/core/DataFiles.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"

#include <algorithm>
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

/// Indices of the chain's steps named by the string array `key` of `t`,
/// in the order given; an unknown name fails at the key.
std::vector<std::uint16_t> stepIndices(const ConfigTable& t,
                                       std::string_view key,
                                       const FinderConfig& chain) {
  std::vector<std::uint16_t> indices;
  for (const std::string& name : t.getStringArray(key)) {
    auto it =
        std::find_if(chain.steps.begin(), chain.steps.end(),
                     [&](const FindingStep& s) { return s.name == name; });
    if (it == chain.steps.end()) {
      t.fail(key, "no step named '" + name + "'");
    }
    indices.push_back(static_cast<std::uint16_t>(it - chain.steps.begin()));
  }
  return indices;
}

/// The [selection] table over `defaults`; the values' sense is checked by
/// the TrackSelector constructor, whose message is located at the key.
/// Step names (short_track_steps) are those of `chain`.
TrackSelector::Config readSelection(const ConfigTable& t,
                                    TrackSelector::Config c,
                                    const FinderConfig& chain) {
  c.minHits = count(t, "min_hits", c.minHits);
  c.cloneSharedHits = count(t, "clone_shared_hits", c.cloneSharedHits);
  c.minUniqueHits = count(t, "min_unique_hits", c.minUniqueHits);
  c.dropOutliers = t.getBool("drop_outliers", c.dropOutliers);
  c.shortTrackHits = count(t, "short_track_hits", c.shortTrackHits);
  c.shortTrackMaxChi2Ndf =
      t.getDouble("short_track_max_chi2_ndf", c.shortTrackMaxChi2Ndf,
                  Range::positiveFinite());
  if (t.has("short_track_steps")) {
    c.shortTrackSteps = stepIndices(t, "short_track_steps", chain);
  }
  t.rejectUnknownKeys();
  if (std::optional<TrackSelector::Problem> p = TrackSelector::findProblem(c)) {
    t.fail(p->key, p->what);
  }
  return c;
}

/// The [split_merging] table over `defaults` (SplitTrackMerger::Config),
/// checked by findProblem with the message located at the key.
SplitTrackMerger::Config readSplitMerging(const ConfigTable& t,
                                          SplitTrackMerger::Config c) {
  c.enabled = t.getBool("enabled", c.enabled);
  c.maxParameterChi2 = t.getDouble("max_parameter_chi2", c.maxParameterChi2,
                                   Range::positiveFinite());
  c.maxTanLambdaDifference =
      t.getDouble("max_tan_lambda_difference", c.maxTanLambdaDifference,
                  Range::positiveFinite());
  c.maxPhi0Difference = t.getDouble("max_phi0_difference", c.maxPhi0Difference,
                                    Range::positiveFinite());
  c.maxSameLayerDistance =
      t.getDouble("max_same_layer_distance_mm",
                  c.maxSameLayerDistance / units::mm, Range::positiveFinite()) *
      units::mm;
  c.maxChi2Ratio =
      t.getDouble("max_chi2_ratio", c.maxChi2Ratio, Range::positiveFinite());
  t.rejectUnknownKeys();
  if (std::optional<SplitTrackMerger::Problem> p =
          SplitTrackMerger::findProblem(c)) {
    t.fail(p->key, p->what);
  }
  return c;
}

/// The [hit_reassignment] table over `defaults` (HitReassigner::Config),
/// checked by findProblem with the message located at the key.
HitReassigner::Config readHitReassignment(const ConfigTable& t,
                                          HitReassigner::Config c) {
  c.enabled = t.getBool("enabled", c.enabled);
  c.freeHits = t.getBool("free_hits", c.freeHits);
  c.maxEndDistance =
      t.getDouble("max_end_distance_mm", c.maxEndDistance / units::mm,
                  Range::positiveFinite()) *
      units::mm;
  c.maxTransverse =
      t.getDouble("max_transverse_mm", c.maxTransverse / units::mm,
                  Range::positiveFinite()) *
      units::mm;
  c.maxLongitudinal =
      t.getDouble("max_longitudinal_mm", c.maxLongitudinal / units::mm,
                  Range::positiveFinite()) *
      units::mm;
  c.maxPredictedChi2 = t.getDouble("max_predicted_chi2", c.maxPredictedChi2,
                                   Range::positiveFinite());
  c.scatteringPerMetre =
      t.getDouble("scattering_mm_per_m_gev", c.scatteringPerMetre / units::mm,
                  Range::positiveFinite()) *
      units::mm;
  c.refitsPerHit = static_cast<int>(
      t.getInt("refits_per_hit", c.refitsPerHit, Range::closed(1, 16)));
  c.maxChi2Increase = t.getDouble("max_chi2_increase", c.maxChi2Increase,
                                  Range::positiveFinite());
  t.rejectUnknownKeys();
  if (std::optional<HitReassigner::Problem> p = HitReassigner::findProblem(c)) {
    t.fail(p->key, p->what);
  }
  return c;
}

/// The [second_pass] table: names of the chain's steps (`chain`), checked
/// by Reconstruction::findSecondPassProblem with the message located at the
/// key.
std::vector<std::uint16_t> readSecondPass(const ConfigTable& t,
                                          const FinderConfig& chain) {
  std::vector<std::uint16_t> steps = stepIndices(t, "steps", chain);
  t.rejectUnknownKeys();
  if (auto p = Reconstruction::findSecondPassProblem(steps, chain)) {
    t.fail(p->first, p->second);
  }
  return steps;
}

}  // namespace

Reconstruction::Config readReconstructionTable(const ConfigTable& root,
                                               const Detector& detector) {
  Reconstruction::Config config;
  config.chain = readChainTable(root, detector);
  if (std::optional<ConfigTable> selection = root.findTable("selection")) {
    config.selector = readSelection(*selection, config.selector, config.chain);
  }
  if (std::optional<ConfigTable> merging = root.findTable("split_merging")) {
    config.merger = readSplitMerging(*merging, config.merger);
  }
  if (std::optional<ConfigTable> reassignment =
          root.findTable("hit_reassignment")) {
    config.reassigner = readHitReassignment(*reassignment, config.reassigner);
  }
  if (std::optional<ConfigTable> second = root.findTable("second_pass")) {
    config.secondPassSteps = readSecondPass(*second, config.chain);
  }
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
