#include "conftrack/reconstruction/finding/FindingChain.hpp"

#include "conftrack/core/ConfigTable.hpp"
#include "conftrack/core/DataFiles.hpp"
#include "conftrack/core/Error.hpp"

#include <algorithm>
#include <cmath>

namespace conftrack {

namespace {

FindingStep readStep(const ConfigTable& t, const Detector& detector,
                     bool first) {
  FindingStep s;
  s.name = t.getString("name");
  if (s.name.empty()) {
    t.fail("name", "must not be empty");
  }
  for (const std::string& c : t.getStringArray("collections")) {
    std::optional<std::uint16_t> sub = detector.findSubdetector(c);
    if (!sub) {
      std::string known;
      for (const Subdetector& d : detector.subdetectors()) {
        known += (known.empty() ? "" : ", ") + d.name;
      }
      t.fail("collections", "detector '" + detector.name() +
                                "' has no subdetector '" + c +
                                "' (it has: " + known + ")");
    }
    for (std::uint16_t existing : s.collections) {
      if (existing == *sub) {
        t.fail("collections", "subdetector '" + c + "' listed twice");
      }
    }
    s.collections.push_back(*sub);
  }
  if (t.has("seed_collections")) {
    for (const std::string& c : t.getStringArray("seed_collections")) {
      std::optional<std::uint16_t> sub = detector.findSubdetector(c);
      if (!sub) {
        t.fail("seed_collections", "detector '" + detector.name() +
                                       "' has no subdetector '" + c + "'");
      }
      if (std::find(s.seedCollections.begin(), s.seedCollections.end(), *sub) !=
          s.seedCollections.end()) {
        t.fail("seed_collections", "subdetector '" + c + "' listed twice");
      }
      if (!s.collections.empty() &&
          std::find(s.collections.begin(), s.collections.end(), *sub) ==
              s.collections.end()) {
        t.fail("seed_collections",
               "subdetector '" + c + "' is not among the step's collections");
      }
      s.seedCollections.push_back(*sub);
    }
    if (s.seedCollections.empty()) {
      t.fail("seed_collections",
             "must not be empty (leave it out to seed from every hit)");
    }
  }
  if (first && s.collections.empty()) {
    t.fail("collections",
           "the first step must name its collections (an empty list reuses "
           "the previous step's hits)");
  }
  std::vector<std::string> actions = t.getStringArray("actions");
  if (actions.empty()) {
    t.fail("actions",
           "at least one of \"build\", \"extend\", \"sort\", \"helix\"");
  }
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
  s.maxCellAngle =
      t.getDouble("max_cell_angle", Range{0.0, 3.14159, false, true});
  s.maxCellAngleRZ =
      t.getDouble("max_cell_angle_rz", Range{0.0, 3.14159, false, true});
  s.chi2Cut = t.getDouble("chi2_cut", Range::positive());
  s.chi2PtScale =
      t.getDouble("chi2_cut_pt_scale_GeV", s.chi2PtScale, Range::nonNegative());
  s.minHits =
      static_cast<std::uint32_t>(t.getInt("min_hits", Range::closed(3, 100)));
  s.maxDistance = t.getDouble("max_distance", Range{0.0, 1.0, false, true});
  s.slopeZRange = t.getDouble("slope_z_range", Range::positive());
  s.highPtCut = t.getDouble("high_pt_cut_GeV", Range::nonNegative());
  s.maxSeedDeltaPhi = t.getDouble("max_seed_dphi", s.maxSeedDeltaPhi,
                                  Range{0.0, 3.15, false, true});
  s.maxSeedZ0 = t.getDouble("max_seed_z0_mm", s.maxSeedZ0, Range::positive());
  s.maxSeedLength =
      t.getDouble("max_seed_length_mm", s.maxSeedLength, Range::positive());
  s.maxSeedCells = static_cast<std::uint32_t>(
      t.getInt("max_seed_cells", s.maxSeedCells, Range::closed(0, 1e6)));
  s.maxPaths = static_cast<std::uint32_t>(
      t.getInt("max_paths", s.maxPaths, Range::closed(0, 1e9)));
  s.minPt = t.getDouble("min_pt_GeV", s.minPt, Range::nonNegative());
  s.maxD0 = t.getDouble("max_d0_mm", s.maxD0, Range::positive());
  s.maxMissedLayers = static_cast<std::uint32_t>(
      t.getInt("max_missed_layers", s.maxMissedLayers, Range::closed(0, 10)));
  if (s.helix && !std::isfinite(s.maxSeedLength)) {
    t.fail("max_seed_length_mm",
           "required by the \"helix\" action (it bounds the seed search)");
  }
  if (s.helix && s.minPt <= 0.0) {
    t.fail("min_pt_GeV", "required by the \"helix\" action (> 0)");
  }
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

}  // namespace

void FinderConfig::validate() const {
  auto atLeast = [](const char* key, double value, double low) {
    if (!(value >= low)) {
      throw InputError("finder settings", "key '" + std::string(key) +
                                              "': must be at least " +
                                              std::to_string(int(low)));
    }
  };
  atLeast("clone_shared_hits", cloneSharedHits, 1);
  atLeast("max_paths_per_seed", maxPathsPerSeed, 1);
  atLeast("max_cells_per_seed", maxCellsPerSeed, 1);
  atLeast("max_seed_neighbours", maxSeedNeighbours, 1);
  atLeast("max_cell_neighbours", maxCellNeighbours, 1);
  atLeast("max_leaves_per_seed", maxLeavesPerSeed, 1);
  atLeast("max_window_hits", maxWindowHits, 1);
  atLeast("max_cells_per_hit", maxCellsPerHit, 1);
  atLeast("max_cached_cells", maxCachedCells, 1000);
  atLeast("extension_lookahead", extensionLookahead, 0);
  if (!(extensionPhiWindow > 0.0)) {
    throw InputError("finder settings",
                     "key 'extension_phi_window': must be positive");
  }
}

FinderConfig parseChain(std::string_view text, const std::string& sourceName,
                        const Detector& detector) {
  std::shared_ptr<toml::table> table = ConfigTable::parse(text, sourceName);
  ConfigTable root(*table, sourceName, "");
  FinderConfig cfg;
  if (auto f = root.findTable("finder")) {
    cfg.thetaRange = f->getDouble("theta_range", cfg.thetaRange,
                                  Range{0.0, 3.14159, false, true});
    cfg.cloneSharedHits = static_cast<std::uint32_t>(f->getInt(
        "clone_shared_hits", cfg.cloneSharedHits, Range::closed(1, 100)));
    cfg.maxPathsPerSeed = static_cast<std::uint32_t>(f->getInt(
        "max_paths_per_seed", cfg.maxPathsPerSeed, Range::closed(1, 1e9)));
    cfg.maxCellsPerSeed = static_cast<std::uint32_t>(f->getInt(
        "max_cells_per_seed", cfg.maxCellsPerSeed, Range::closed(1, 1e9)));
    cfg.maxSeedNeighbours = static_cast<std::uint32_t>(f->getInt(
        "max_seed_neighbours", cfg.maxSeedNeighbours, Range::closed(1, 1e9)));
    cfg.maxCellNeighbours = static_cast<std::uint32_t>(f->getInt(
        "max_cell_neighbours", cfg.maxCellNeighbours, Range::closed(1, 1e9)));
    cfg.maxLeavesPerSeed = static_cast<std::uint32_t>(f->getInt(
        "max_leaves_per_seed", cfg.maxLeavesPerSeed, Range::closed(1, 1e9)));
    cfg.maxCellsPerHit = static_cast<std::uint32_t>(f->getInt(
        "max_cells_per_hit", cfg.maxCellsPerHit, Range::closed(1, 1e9)));
    cfg.maxWindowHits = static_cast<std::uint32_t>(
        f->getInt("max_window_hits", cfg.maxWindowHits, Range::closed(1, 1e9)));
    cfg.maxCachedCells = static_cast<std::uint32_t>(f->getInt(
        "max_cached_cells", cfg.maxCachedCells, Range::closed(1000, 1e9)));
    cfg.extensionPhiWindow =
        f->getDouble("extension_phi_window", cfg.extensionPhiWindow,
                     Range{0.0, 3.14159, false, true});
    cfg.extensionLookahead = static_cast<int>(f->getInt(
        "extension_lookahead", cfg.extensionLookahead, Range::closed(0, 5)));
    cfg.legacyFourTesla = f->getBool("legacy_four_tesla", false);
    cfg.finalHoleFilling =
        f->getBool("final_hole_filling", cfg.finalHoleFilling);
    cfg.scatteringAllowance =
        f->getBool("scattering_allowance", cfg.scatteringAllowance);
    f->rejectUnknownKeys();
  }
  std::vector<ConfigTable> steps = root.getTableArray("step");
  if (steps.empty()) {
    root.fail("step", "missing: a chain needs at least one [[step]]");
  }
  for (std::size_t i = 0; i < steps.size(); ++i) {
    cfg.steps.push_back(readStep(steps[i], detector, i == 0));
    for (std::size_t j = 0; j + 1 < cfg.steps.size(); ++j) {
      if (cfg.steps[j].name == cfg.steps.back().name) {
        steps[i].fail("name",
                      "duplicate step name '" + cfg.steps.back().name + "'");
      }
    }
  }
  root.rejectUnknownKeys();
  cfg.validate();
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
