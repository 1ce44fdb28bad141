#include "conftrack/reconstruction/finding/FindingChain.hpp"

#include "conftrack/core/ConfigTable.hpp"
#include "conftrack/core/DataFiles.hpp"
#include "conftrack/core/Error.hpp"
#include "conftrack/core/Units.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace conftrack {

namespace {

/// A required number in the unit its key names, converted to native units.
double quantity(const ConfigTable& t, std::string_view key, double unit) {
  return t.getDouble(key) * unit;
}

/// An optional number in the unit its key names; `fallback` is native.
double quantity(const ConfigTable& t, std::string_view key, double unit,
                double fallback) {
  return t.has(key) ? t.getDouble(key) * unit : fallback;
}

/// An optional count that must fit std::uint32_t (its sense is checked by
/// findChainProblem).
std::uint32_t count(const ConfigTable& t, std::string_view key,
                    std::uint32_t fallback) {
  return static_cast<std::uint32_t>(
      t.getInt(key, fallback,
               Range::closed(0, std::numeric_limits<std::uint32_t>::max())));
}

std::vector<std::uint16_t> subdetectors(const ConfigTable& t,
                                        std::string_view key,
                                        const Detector& detector) {
  std::vector<std::uint16_t> out;
  for (const std::string& c : t.getStringArray(key)) {
    std::optional<std::uint16_t> sub = detector.findSubdetector(c);
    if (!sub) {
      std::string known;
      for (const Subdetector& d : detector.subdetectors()) {
        known += (known.empty() ? "" : ", ") + d.name;
      }
      t.fail(key, "detector '" + detector.name() + "' has no subdetector '" +
                      c + "' (it has: " + known + ")");
    }
    out.push_back(*sub);
  }
  return out;
}

/// Fills a step from its table; the values' sense is checked afterwards
/// by findChainProblem, as for a chain built in code.
FindingStep readStep(const ConfigTable& t, const Detector& detector) {
  using units::GeV;
  using units::mm;
  using units::rad;
  const double perMm = 1.0 / units::mm;  // conformal distances
  const double one = 1.0;                // dimensionless
  FindingStep s;
  s.name = t.getString("name");
  s.collections = subdetectors(t, "collections", detector);
  if (t.has("seed_collections")) {
    s.seedCollections = subdetectors(t, "seed_collections", detector);
    // In code an empty list means "seed from every hit"; in a file that is
    // said by leaving the key out.
    if (s.seedCollections.empty()) {
      t.fail("seed_collections",
             "must not be empty (leave it out to seed from every hit)");
    }
  }
  if (t.has("inward_collections")) {
    s.inwardCollections = subdetectors(t, "inward_collections", detector);
    if (s.inwardCollections.empty()) {
      t.fail("inward_collections",
             "must not be empty (leave it out for no inward following)");
    }
  }
  std::vector<std::string> actions = t.getStringArray("actions");
  for (const std::string& a : actions) {
    bool* flag = a == "build"    ? &s.build
                 : a == "extend" ? &s.extend
                 : a == "sort"   ? &s.sort
                 : a == "helix"  ? &s.helix
                                 : nullptr;
    if (flag == nullptr) {
      t.fail("actions", "unknown action \"" + a +
                            "\" (expected build, extend, sort, helix)");
    }
    if (*flag) {
      t.fail("actions", "action \"" + a + "\" listed twice");
    }
    *flag = true;
  }
  s.maxCellAngle = quantity(t, "max_cell_angle", rad);
  s.maxCellAngleRZ = quantity(t, "max_cell_angle_rz", rad);
  s.chi2Cut = quantity(t, "chi2_cut", one);
  s.chi2PtScale = quantity(t, "chi2_cut_pt_scale_GeV", GeV, s.chi2PtScale);
  s.minHits = static_cast<std::uint32_t>(t.getInt(
      "min_hits", Range::closed(0, std::numeric_limits<std::uint32_t>::max())));
  s.maxDistance = quantity(t, "max_distance", perMm);
  s.slopeZRange = quantity(t, "slope_z_range", one);
  s.highPtCut = quantity(t, "high_pt_cut_GeV", GeV);
  s.maxSeedDeltaPhi = quantity(t, "max_seed_dphi", rad, s.maxSeedDeltaPhi);
  s.maxSeedZ0 = quantity(t, "max_seed_z0_mm", mm, s.maxSeedZ0);
  s.vertexWindow = quantity(t, "vertex_window_mm", mm, s.vertexWindow);
  s.vertexPrepassFreeHits =
      t.getBool("vertex_prepass_free_hits", s.vertexPrepassFreeHits);
  s.maxSeedLength = quantity(t, "max_seed_length_mm", mm, s.maxSeedLength);
  s.maxSeedGap = quantity(t, "max_seed_gap_mm", mm, s.maxSeedGap);
  s.seedLengthPerGap =
      quantity(t, "seed_length_per_gap", one, s.seedLengthPerGap);
  s.maxSeedLengthPerGap =
      quantity(t, "seed_length_per_gap_max_mm", mm, s.maxSeedLengthPerGap);
  s.maxSeedCells = count(t, "max_seed_cells", s.maxSeedCells);
  s.maxPaths = count(t, "max_paths", s.maxPaths);
  s.maxCellsPerHit = count(t, "max_cells_per_hit", s.maxCellsPerHit);
  s.minPt = quantity(t, "min_pt_GeV", GeV, s.minPt);
  s.maxD0 = quantity(t, "max_d0_mm", mm, s.maxD0);
  s.maxMissedLayers = count(t, "max_missed_layers", s.maxMissedLayers);
  s.continueMissedLayers =
      count(t, "continue_missed_layers", s.continueMissedLayers);
  s.continueChi2Cut = quantity(t, "continue_chi2_cut", one, s.continueChi2Cut);
  s.firstPassMinHits = count(t, "first_pass_min_hits", s.firstPassMinHits);
  s.pastTurnMinHits = count(t, "past_turn_min_hits", s.pastTurnMinHits);
  s.overlapPairBelowHits =
      count(t, "overlap_pair_below_hits", s.overlapPairBelowHits);
  s.straightLineFit = t.getBool("straight_line_fit", false);
  s.onlySzChi2Cut = t.getBool("only_sz_chi2_cut", false);
  s.radialSearch = t.getBool("radial_search", false);
  s.recovery = t.getBool("recovery", false);
  std::string dir = t.getString("direction", "inside-out");
  if (dir == "inside-out") {
    s.direction = SearchDirection::eInsideOut;
  } else if (dir == "outside-in") {
    s.direction = SearchDirection::eOutsideIn;
  } else {
    t.fail("direction", "expected \"inside-out\" or \"outside-in\"");
  }
  std::string fit = t.getString("fit_direction", "forward");
  if (fit != "forward" && fit != "backward") {
    t.fail("fit_direction", "expected \"forward\" or \"backward\"");
  }
  s.fitBackward = fit == "backward";
  t.rejectUnknownKeys();
  return s;
}

/// The [vertex_prepass] table; the values' sense is checked by
/// findChainProblem.
VertexZPrepass::Config readVertexPrepass(const ConfigTable& t,
                                         const Detector& detector) {
  using units::mm;
  using units::rad;
  VertexZPrepass::Config c;
  c.collections = subdetectors(t, "collections", detector);
  c.maxAbsZ = quantity(t, "max_z_mm", mm, c.maxAbsZ);
  c.binWidth = quantity(t, "bin_width_mm", mm, c.binWidth);
  c.smoothBins = count(t, "smooth_bins", c.smoothBins);
  c.maxDeltaPhi = quantity(t, "max_dphi", rad, c.maxDeltaPhi);
  c.confirmPhi = quantity(t, "confirm_dphi", rad, c.confirmPhi);
  c.confirmZ = quantity(t, "confirm_dz_mm", mm, c.confirmZ);
  c.minExcess = quantity(t, "min_excess", 1.0, c.minExcess);
  c.minSignificance = quantity(t, "min_significance", 1.0, c.minSignificance);
  t.rejectUnknownKeys();
  return c;
}

BeamSpotPrepass::Config readBeamSpotPrepass(const ConfigTable& t,
                                            const Detector& detector) {
  using units::mm;
  using units::rad;
  BeamSpotPrepass::Config c;
  c.collections = subdetectors(t, "collections", detector);
  c.minLayerGap = quantity(t, "min_layer_gap_mm", mm, c.minLayerGap);
  c.maxDeltaPhi = quantity(t, "max_dphi", rad, c.maxDeltaPhi);
  c.confirmPhi = quantity(t, "confirm_dphi", rad, c.confirmPhi);
  c.confirmZ = quantity(t, "confirm_dz_mm", mm, c.confirmZ);
  c.maxAbsZ = quantity(t, "max_z_mm", mm, c.maxAbsZ);
  c.minPt = quantity(t, "min_pt_GeV", units::GeV, c.minPt);
  c.maxD0 = quantity(t, "max_d0_mm", mm, c.maxD0);
  c.maxSeedHits = count(t, "max_seed_hits", c.maxSeedHits);
  c.minTriplets = count(t, "min_triplets", c.minTriplets);
  c.minScale = quantity(t, "min_scale_mm", mm, c.minScale);
  t.rejectUnknownKeys();
  return c;
}

}  // namespace

FinderConfig parseChain(std::string_view text, const std::string& sourceName,
                        const Detector& detector) {
  std::shared_ptr<toml::table> table = ConfigTable::parse(text, sourceName);
  return readChainTable(ConfigTable(*table, sourceName, ""), detector);
}

FinderConfig readChainTable(const ConfigTable& root, const Detector& detector) {
  FinderConfig cfg;
  std::optional<ConfigTable> finder = root.findTable("finder");
  if (finder) {
    const ConfigTable& f = *finder;
    cfg.thetaRange = quantity(f, "theta_range", units::rad, cfg.thetaRange);
    cfg.cloneSharedHits = count(f, "clone_shared_hits", cfg.cloneSharedHits);
    cfg.maxPathsPerSeed = count(f, "max_paths_per_seed", cfg.maxPathsPerSeed);
    cfg.maxCellsPerSeed = count(f, "max_cells_per_seed", cfg.maxCellsPerSeed);
    cfg.maxSeedNeighbours =
        count(f, "max_seed_neighbours", cfg.maxSeedNeighbours);
    cfg.maxCellNeighbours =
        count(f, "max_cell_neighbours", cfg.maxCellNeighbours);
    cfg.maxLeavesPerSeed =
        count(f, "max_leaves_per_seed", cfg.maxLeavesPerSeed);
    cfg.maxCellsPerHit = count(f, "max_cells_per_hit", cfg.maxCellsPerHit);
    cfg.maxTripletsPerSeed =
        count(f, "max_triplets_per_seed", cfg.maxTripletsPerSeed);
    cfg.maxWindowHits = count(f, "max_window_hits", cfg.maxWindowHits);
    cfg.maxCachedCells = count(f, "max_cached_cells", cfg.maxCachedCells);
    cfg.extensionPhiWindow =
        quantity(f, "extension_phi_window", units::rad, cfg.extensionPhiWindow);
    cfg.extensionLookahead = static_cast<int>(
        f.getInt("extension_lookahead", cfg.extensionLookahead,
                 Range::closed(std::numeric_limits<int>::min(),
                               std::numeric_limits<int>::max())));
    cfg.extensionHitChi2Ratio =
        quantity(f, "extension_hit_chi2_ratio", 1.0, cfg.extensionHitChi2Ratio);
    cfg.extensionHitChi2Floor =
        quantity(f, "extension_hit_chi2_floor", 1.0, cfg.extensionHitChi2Floor);
    cfg.extensionSkipChi2 =
        quantity(f, "extension_skip_chi2", 1.0, cfg.extensionSkipChi2);
    cfg.extensionSzFilter =
        f.getBool("extension_sz_filter", cfg.extensionSzFilter);
    cfg.extensionUvScattering =
        f.getBool("extension_uv_scattering", cfg.extensionUvScattering);
    cfg.legacyFourTesla = f.getBool("legacy_four_tesla", false);
    cfg.finalHoleFilling =
        f.getBool("final_hole_filling", cfg.finalHoleFilling);
    cfg.finalMinUniqueHits = static_cast<std::uint32_t>(
        f.getInt("final_min_unique_hits", cfg.finalMinUniqueHits,
                 Range::closed(0, 100)));
    cfg.finalTrimSharedHits =
        f.getBool("final_trim_shared_hits", cfg.finalTrimSharedHits);
    cfg.sharedHitsEachStep =
        f.getBool("shared_hits_each_step", cfg.sharedHitsEachStep);
    cfg.scatteringAllowance =
        f.getBool("scattering_allowance", cfg.scatteringAllowance);
    cfg.inwardScatteringAllowance =
        f.getBool("inward_scattering_allowance", cfg.inwardScatteringAllowance);
    cfg.finalExtension = f.getBool("final_extension", cfg.finalExtension);
    cfg.finalExtensionAngleFactor = quantity(
        f, "final_extension_angle_factor", 1.0, cfg.finalExtensionAngleFactor);
    cfg.finalExtensionPhiWindow =
        quantity(f, "final_extension_phi_window", units::rad,
                 cfg.finalExtensionPhiWindow);
    cfg.overlapHits = f.getBool("overlap_hits", cfg.overlapHits);
    cfg.fieldCorrection = f.getBool("field_correction", cfg.fieldCorrection);
    cfg.beamSpotX = quantity(f, "beam_spot_x_mm", units::mm, cfg.beamSpotX);
    cfg.beamSpotY = quantity(f, "beam_spot_y_mm", units::mm, cfg.beamSpotY);
    cfg.overlapMaxChi2 =
        quantity(f, "overlap_max_chi2", 1.0, cfg.overlapMaxChi2);
    cfg.overlapMaxArc =
        quantity(f, "overlap_max_arc_mm", units::mm, cfg.overlapMaxArc);
    cfg.overlapMaxGap =
        quantity(f, "overlap_max_gap_mm", units::mm, cfg.overlapMaxGap);
    cfg.maxTrackTurns = quantity(f, "max_track_turns", 1.0, cfg.maxTrackTurns);
    cfg.trackMerging = f.getBool("track_merging", cfg.trackMerging);
    cfg.mergeDropTurns = f.getBool("merge_drop_turns", cfg.mergeDropTurns);
    cfg.mergeMaxDeltaPhi =
        quantity(f, "merge_max_dphi", units::rad, cfg.mergeMaxDeltaPhi);
    cfg.mergeMaxDistance =
        quantity(f, "merge_max_distance_mm", units::mm, cfg.mergeMaxDistance);
    cfg.mergeMaxDz = quantity(f, "merge_max_dz_mm", units::mm, cfg.mergeMaxDz);
    cfg.mergeMaxChi2Ratio =
        quantity(f, "merge_max_chi2_ratio", 1.0, cfg.mergeMaxChi2Ratio);
    f.rejectUnknownKeys();
  }
  std::optional<ConfigTable> prepass = root.findTable("vertex_prepass");
  if (prepass) {
    cfg.vertexPrepass = readVertexPrepass(*prepass, detector);
  }
  std::optional<ConfigTable> beamPrepass = root.findTable("beam_spot_prepass");
  if (beamPrepass) {
    cfg.beamSpotPrepass = readBeamSpotPrepass(*beamPrepass, detector);
  }
  // [selection], [split_merging], [second_pass] and [hit_reassignment]
  // belong to the track selection, the merging after the fit, the pass
  // after the selection and the stage after both passes of the same file
  // (readReconstructionConfig); the finder has no use for them.
  (void)root.findTable("selection");
  (void)root.findTable("split_merging");
  (void)root.findTable("hit_reassignment");
  (void)root.findTable("second_pass");
  std::vector<ConfigTable> steps = root.getTableArray("step");
  for (const ConfigTable& step : steps) {
    cfg.steps.push_back(readStep(step, detector));
  }
  root.rejectUnknownKeys();
  // The same validation as for a chain built in code, located at the key.
  if (std::optional<ChainProblem> p = findChainProblem(cfg, detector)) {
    if (p->step) {
      steps[*p->step].fail(p->key, p->what);
    }
    constexpr std::string_view kFinder = "finder.";
    if (p->key.starts_with(kFinder) && finder) {
      finder->fail(p->key.substr(kFinder.size()), p->what);
    }
    constexpr std::string_view kPrepass = "vertex_prepass.";
    if (p->key.starts_with(kPrepass) && prepass) {
      prepass->fail(p->key.substr(kPrepass.size()), p->what);
    }
    constexpr std::string_view kBeamPrepass = "beam_spot_prepass.";
    if (p->key.starts_with(kBeamPrepass) && beamPrepass) {
      beamPrepass->fail(p->key.substr(kBeamPrepass.size()), p->what);
    }
    root.fail(p->key, p->what);
  }
  return cfg;
}

FinderConfig readChain(const std::filesystem::path& file,
                       const Detector& detector) {
  return parseChain(readConfigText(file, "chain"), file.string(), detector);
}

std::filesystem::path resolveChainPath(const std::string& nameOrPath) {
  return resolveShippedFile("chains", nameOrPath, "chain");
}

}  // namespace conftrack
