// The one validation of a finding chain (FindingChain.hpp): the chain-file
// reader fills a FinderConfig and runs it, and so does the finder's
// constructor for chains built in code. Problems name the chain-file key
// they come from; values are compared in the units the key names.

#include "conftrack/core/ConfigTable.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace conftrack {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Angles up to pi (the files' bound, rounded down so that a typed "pi"
/// passes).
constexpr double kMaxAngle = 3.14159;
/// Guards may be switched off in code with the largest count.
constexpr double kMaxCount = std::numeric_limits<std::uint32_t>::max();

/// A native value checked against a range given in the key's unit.
struct Quantity {
  const char* key = nullptr;
  double value = 0.0;  ///< native units
  double unit = 1.0;   ///< the key's unit in native units
  Range range;         ///< in the key's unit
};

std::optional<std::string> firstViolation(std::initializer_list<Quantity> qs,
                                          std::string& key) {
  for (const Quantity& q : qs) {
    std::string problem = rangeViolation(q.value / q.unit, q.range);
    if (!problem.empty()) {
      key = q.key;
      return problem;
    }
  }
  return std::nullopt;
}

std::string subdetectorName(const Detector& detector, std::uint16_t index) {
  return index < detector.subdetectors().size()
             ? "'" + detector.subdetectors()[index].name + "'"
             : std::to_string(index);
}

std::optional<ChainProblem> findStepProblem(const FindingStep& s,
                                            std::size_t index,
                                            const Detector& detector) {
  auto problem = [&](std::string key, std::string what) {
    return ChainProblem{index, std::move(key), std::move(what)};
  };
  if (s.name.empty()) {
    return problem("name", "must not be empty");
  }
  for (const auto& [key, list] :
       {std::pair<const char*, const std::vector<std::uint16_t>*>{
            "collections", &s.collections},
        {"seed_collections", &s.seedCollections},
        {"inward_collections", &s.inwardCollections}}) {
    if (auto what = subdetectorListProblem(*list, detector)) {
      return problem(key, std::move(*what));
    }
  }
  for (const std::uint16_t sub : s.seedCollections) {
    if (!s.collections.empty() &&
        std::find(s.collections.begin(), s.collections.end(), sub) ==
            s.collections.end()) {
      return problem("seed_collections",
                     "subdetector " + subdetectorName(detector, sub) +
                         " is not among the step's collections");
    }
  }
  if (!s.inwardCollections.empty() && !s.helix) {
    return problem("inward_collections",
                   "only a helix step follows its tracks inwards");
  }
  if (s.pastTurnMinHits > 0 && s.inwardCollections.empty()) {
    return problem("past_turn_min_hits",
                   "only a helix step with inward_collections follows its "
                   "tracks past the turn (0: off)");
  }
  if (index == 0 && s.collections.empty()) {
    return problem("collections",
                   "the first step must name its collections (an empty list "
                   "reuses the previous step's hits)");
  }
  if (!s.build && !s.extend && !s.sort && !s.helix) {
    return problem(
        "actions",
        "at least one of \"build\", \"extend\", \"sort\", \"helix\"");
  }
  using units::GeV;
  using units::mm;
  using units::rad;
  const double perMm = 1.0 / units::mm;  // conformal distances
  const double one = 1.0;                // dimensionless
  std::string key;
  if (auto what = firstViolation(
          {
              {"max_cell_angle", s.maxCellAngle, rad,
               Range{0.0, kMaxAngle, false, true}},
              {"max_cell_angle_rz", s.maxCellAngleRZ, rad,
               Range{0.0, kMaxAngle, false, true}},
              {"chi2_cut", s.chi2Cut, one, Range::positiveFinite()},
              {"chi2_cut_pt_scale_GeV", s.chi2PtScale, GeV,
               Range{0.0, kInf, true, false}},
              {"min_hits", static_cast<double>(s.minHits), one,
               Range::closed(3, 100)},
              {"max_distance", s.maxDistance, perMm,
               Range{0.0, 1.0, false, true}},
              {"slope_z_range", s.slopeZRange, one, Range::positiveFinite()},
              {"high_pt_cut_GeV", s.highPtCut, GeV,
               Range{0.0, kInf, true, false}},
              {"max_seed_dphi", s.maxSeedDeltaPhi, rad,
               Range{0.0, 3.15, false, true}},
              // Infinity: no cut.
              {"max_seed_z0_mm", s.maxSeedZ0, mm, Range::positive()},
              {"vertex_window_mm", s.vertexWindow, mm, Range::positive()},
              {"max_seed_length_mm", s.maxSeedLength, mm, Range::positive()},
              // 0: no pairs beyond max_seed_length_mm.
              {"max_seed_gap_mm", s.maxSeedGap, mm,
               Range::closed(0.0, 100000.0)},
              // 0: max_seed_length_mm on every pair.
              {"seed_length_per_gap", s.seedLengthPerGap, one,
               Range::closed(0.0, 100.0)},
              {"seed_length_per_gap_max_mm", s.maxSeedLengthPerGap, mm,
               Range::closed(0.0, 100000.0)},
              {"max_seed_cells", static_cast<double>(s.maxSeedCells), one,
               Range::closed(0, 1e6)},
              // 0: only the finder's max_paths_per_seed.
              {"max_paths", static_cast<double>(s.maxPaths), one,
               Range::closed(0, kMaxCount)},
              // 0: the finder's max_cells_per_hit.
              {"max_cells_per_hit", static_cast<double>(s.maxCellsPerHit), one,
               Range::closed(0, kMaxCount)},
              {"min_pt_GeV", s.minPt, GeV, Range{0.0, kInf, true, false}},
              {"max_d0_mm", s.maxD0, mm, Range::positive()},
              {"max_missed_layers", static_cast<double>(s.maxMissedLayers), one,
               Range::closed(0, 10)},
              {"continue_missed_layers",
               static_cast<double>(s.continueMissedLayers), one,
               Range::closed(0, 10)},
              // 0: the step's chi2_cut.
              {"continue_chi2_cut", s.continueChi2Cut, one,
               Range{0.0, kInf, true, false}},
              // 0: one pass.
              {"first_pass_min_hits", static_cast<double>(s.firstPassMinHits),
               one, Range::closed(0, 100)},
              // 0: off.
              {"past_turn_min_hits", static_cast<double>(s.pastTurnMinHits),
               one, Range::closed(0, 100)},
              // 0: off.
              {"overlap_pair_below_hits",
               static_cast<double>(s.overlapPairBelowHits), one,
               Range::closed(0, 100)},
          },
          key)) {
    return problem(key, *what);
  }
  if (s.helix && !std::isfinite(s.maxSeedLength)) {
    return problem("max_seed_length_mm",
                   "required by the \"helix\" action (it bounds the seed "
                   "search)");
  }
  if (s.seedLengthPerGap > 0.0 && s.seedLengthPerGap <= 1.0) {
    // Two layers within the seed length pair anyway; a factor of 1 or
    // less would lengthen no pair and silently do nothing.
    return problem("seed_length_per_gap", "must be 0 (off) or above 1");
  }
  if (s.seedLengthPerGap > 0.0 && !s.helix) {
    return problem("seed_length_per_gap",
                   "only a helix step reads it (0: off)");
  }
  if (s.seedLengthPerGap > 0.0 && !(s.maxSeedLengthPerGap > s.maxSeedLength)) {
    return problem("seed_length_per_gap_max_mm",
                   "required with seed_length_per_gap, above "
                   "max_seed_length_mm");
  }
  if (s.seedLengthPerGap == 0.0 && s.maxSeedLengthPerGap != 0.0) {
    return problem("seed_length_per_gap_max_mm",
                   "needs seed_length_per_gap (> 0)");
  }
  if (s.continueChi2Cut > 0.0 && s.continueChi2Cut < s.chi2Cut) {
    return problem("continue_chi2_cut",
                   "must be 0 (the step's chi2_cut) or at least chi2_cut");
  }
  if (s.overlapPairBelowHits != 0 && s.overlapPairBelowHits <= s.minHits) {
    return problem("overlap_pair_below_hits",
                   "must be 0 (off) or above min_hits (shorter tracks are "
                   "not built)");
  }
  if (s.helix && !(s.minPt > 0.0)) {
    return problem("min_pt_GeV", "required by the \"helix\" action (> 0)");
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> subdetectorListProblem(
    const std::vector<std::uint16_t>& list, const Detector& detector) {
  const std::size_t nSub = detector.subdetectors().size();
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (list[i] >= nSub) {
      return "subdetector index " + std::to_string(list[i]) +
             " is not one of the " + std::to_string(nSub) +
             " subdetectors of detector '" + detector.name() + "'";
    }
    if (std::find(list.begin(), list.begin() + static_cast<std::ptrdiff_t>(i),
                  list[i]) != list.begin() + static_cast<std::ptrdiff_t>(i)) {
      return "subdetector " + subdetectorName(detector, list[i]) +
             " listed twice";
    }
  }
  return std::nullopt;
}

std::string ChainProblem::describe() const {
  std::string name = step ? "step[" + std::to_string(*step) + "]." + key : key;
  return "key '" + name + "': " + what;
}

std::optional<ChainProblem> findChainProblem(const FinderConfig& c,
                                             const Detector& detector) {
  using units::rad;
  const double one = 1.0;
  std::string key;
  if (auto what = firstViolation(
          {
              {"theta_range", c.thetaRange, rad,
               Range{0.0, kMaxAngle, false, true}},
              {"clone_shared_hits", static_cast<double>(c.cloneSharedHits), one,
               Range::closed(1, 100)},
              {"max_paths_per_seed", static_cast<double>(c.maxPathsPerSeed),
               one, Range::closed(1, kMaxCount)},
              {"max_cells_per_seed", static_cast<double>(c.maxCellsPerSeed),
               one, Range::closed(1, kMaxCount)},
              {"max_seed_neighbours", static_cast<double>(c.maxSeedNeighbours),
               one, Range::closed(1, kMaxCount)},
              {"max_cell_neighbours", static_cast<double>(c.maxCellNeighbours),
               one, Range::closed(1, kMaxCount)},
              {"max_leaves_per_seed", static_cast<double>(c.maxLeavesPerSeed),
               one, Range::closed(1, kMaxCount)},
              {"max_cells_per_hit", static_cast<double>(c.maxCellsPerHit), one,
               Range::closed(1, kMaxCount)},
              {"max_triplets_per_seed",
               static_cast<double>(c.maxTripletsPerSeed), one,
               Range::closed(1, kMaxCount)},
              {"max_window_hits", static_cast<double>(c.maxWindowHits), one,
               Range::closed(1, kMaxCount)},
              {"max_cached_cells", static_cast<double>(c.maxCachedCells), one,
               Range::closed(1000, kMaxCount)},
              {"extension_phi_window", c.extensionPhiWindow, rad,
               Range{0.0, kMaxAngle, false, true}},
              {"extension_lookahead", static_cast<double>(c.extensionLookahead),
               one, Range::closed(0, 5)},
              {"extension_hit_chi2_ratio", c.extensionHitChi2Ratio, one,
               Range::closed(0.0, 1e6)},
              {"extension_hit_chi2_floor", c.extensionHitChi2Floor, one,
               Range{0.0, 1e6, false, true}},
              {"extension_skip_chi2", c.extensionSkipChi2, one,
               Range::closed(0.0, 1e6)},
              {"overlap_max_chi2", c.overlapMaxChi2, one,
               Range{0.0, 1e6, false, true}},
              {"overlap_max_arc_mm", c.overlapMaxArc, units::mm,
               Range{0.0, 1000.0, false, true}},
              {"overlap_max_gap_mm", c.overlapMaxGap, units::mm,
               Range{0.0, 1000.0, false, true}},
              {"max_track_turns", c.maxTrackTurns, one,
               Range::closed(0.0, 100.0)},
              {"merge_max_dphi", c.mergeMaxDeltaPhi, rad,
               Range{0.0, 1.0, false, true}},
              {"merge_max_distance_mm", c.mergeMaxDistance, units::mm,
               Range{0.0, 1000.0, false, true}},
              {"merge_max_dz_mm", c.mergeMaxDz, units::mm,
               Range{0.0, 10000.0, false, true}},
              {"merge_max_chi2_ratio", c.mergeMaxChi2Ratio, one,
               Range::closed(1.0, 1e6)},
              {"final_extension_angle_factor", c.finalExtensionAngleFactor, one,
               Range::closed(1.0, 100.0)},
              {"final_extension_phi_window", c.finalExtensionPhiWindow, rad,
               Range{0.0, kMaxAngle, false, true}},
              {"beam_spot_x_mm", c.beamSpotX, units::mm,
               Range::closed(-kMaxBeamLineOffset / units::mm,
                             kMaxBeamLineOffset / units::mm)},
              {"beam_spot_y_mm", c.beamSpotY, units::mm,
               Range::closed(-kMaxBeamLineOffset / units::mm,
                             kMaxBeamLineOffset / units::mm)},
              // 0: off.
              {"final_min_unique_hits",
               static_cast<double>(c.finalMinUniqueHits), one,
               Range::closed(0, 100)},
          },
          key)) {
    return ChainProblem{std::nullopt, "finder." + key, *what};
  }
  if (c.finalTrimSharedHits && c.finalMinUniqueHits == 0) {
    return ChainProblem{std::nullopt, "finder.final_trim_shared_hits",
                        "needs final_min_unique_hits (the hits a trimmed "
                        "track must keep)"};
  }
  if (c.sharedHitsEachStep && c.finalMinUniqueHits == 0) {
    return ChainProblem{std::nullopt, "finder.shared_hits_each_step",
                        "needs final_min_unique_hits (the resolution's "
                        "rule)"};
  }
  if (c.beamSpotPrepass) {
    if (auto p = BeamSpotPrepass::findProblem(*c.beamSpotPrepass, detector)) {
      return ChainProblem{std::nullopt, "beam_spot_prepass." + p->first,
                          p->second};
    }
  }
  if (c.vertexPrepass) {
    if (auto p = VertexZPrepass::findProblem(*c.vertexPrepass, detector)) {
      return ChainProblem{std::nullopt, "vertex_prepass." + p->first,
                          p->second};
    }
  }
  if (c.steps.empty()) {
    return ChainProblem{std::nullopt, "step",
                        "missing: a chain needs at least one [[step]]"};
  }
  for (std::size_t i = 0; i < c.steps.size(); ++i) {
    if (auto p = findStepProblem(c.steps[i], i, detector)) {
      return p;
    }
    if (std::isfinite(c.steps[i].vertexWindow) && !c.vertexPrepass) {
      return ChainProblem{i, "vertex_window_mm",
                          "needs the chain's [vertex_prepass] table (the "
                          "vertices it finds)"};
    }
    if (c.steps[i].overlapPairBelowHits != 0 && !c.overlapHits) {
      return ChainProblem{i, "overlap_pair_below_hits",
                          "needs the overlap search (finder.overlap_hits = "
                          "true): it adds the pairs"};
    }
    if (c.steps[i].vertexPrepassFreeHits &&
        !(c.steps[i].build && std::isfinite(c.steps[i].vertexWindow))) {
      return ChainProblem{i, "vertex_prepass_free_hits",
                          "needs the build action and vertex_window_mm (the "
                          "seeds it places)"};
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (c.steps[j].name == c.steps[i].name) {
        return ChainProblem{i, "name",
                            "duplicate step name '" + c.steps[i].name + "'"};
      }
    }
  }
  return std::nullopt;
}

}  // namespace conftrack
