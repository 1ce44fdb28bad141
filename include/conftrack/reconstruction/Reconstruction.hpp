#pragma once

/// @file Reconstruction.hpp
/// The whole reconstruction of one event: conformal finding, Kalman
/// fitting and track selection (paper section 4). Truth is never used.

#include "conftrack/core/ConfigTable.hpp"
#include "conftrack/core/Hit.hpp"
#include "conftrack/core/Track.hpp"
#include "conftrack/geometry/Detector.hpp"
#include "conftrack/geometry/ModuleLayout.hpp"
#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"
#include "conftrack/reconstruction/fitting/KalmanFitter.hpp"
#include "conftrack/reconstruction/selection/HitReassigner.hpp"
#include "conftrack/reconstruction/selection/SplitTrackMerger.hpp"
#include "conftrack/reconstruction/selection/TrackSelector.hpp"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace conftrack {

/// The fitter's view of a found track: its hits (a view into `found`,
/// which must outlive it), its first fit direction and the beam line
/// [mm] its perigee is taken about (FitInput::beamLine).
FitInput fitInput(const FoundTrack& found,
                  const Vector2& beamLine = Vector2::Zero());

/// The finder's track (toTrack) with the results of `fitted`, the fit of
/// fitInput(found): outlier flags, states, chi2 and ndf.
Track withFit(const FoundTrack& found, const Track& fitted);

class Reconstruction {
 public:
  struct Config {
    /// Finding chain (chains/<detector>.toml).
    FinderConfig chain;
    KalmanFitter::Config fitter;
    TrackSelector::Config selector;
    /// Merging split tracks after the fit, before the selection (chain
    /// file [split_merging]; off by default).
    SplitTrackMerger::Config merger;
    /// Outlier hits and hits of no track given to the fitted track whose
    /// end they continue, after both passes (chain file
    /// [hit_reassignment]; off by default).
    HitReassigner::Config reassigner;
    /// Fit the candidates; without it the tracks carry only the finder's
    /// estimates and the selection keeps unfitted tracks.
    bool fit = true;
    /// Steps of the chain (indices, ascending, each once) that run again
    /// after the selection over the hits no selected track holds (chain
    /// file [second_pass] steps; none by default): candidates that the
    /// fit or the selection drop held hits while the later steps ran,
    /// and particles whose hits they held are found only once those hits
    /// are free (algorithm.md 3.21). The new tracks are fitted and
    /// selected like the first ones and follow them.
    std::vector<std::uint16_t> secondPassSteps;
  };

  /// Output of one event.
  struct Result {
    std::vector<Track> tracks;
    /// Per finding step: counters and time.
    std::vector<StepStats> steps;
    /// Tracks of the second pass (Config::secondPassSteps), the last ones
    /// of `tracks`.
    std::size_t secondPassTracks = 0;
    /// The finder's vertex regions (FindingResult::vertexRegions).
    std::vector<std::pair<double, double>> vertexRegions;
    /// The beam line about which the finder mapped the hits
    /// (FindingResult::beamSpot) [mm].
    Vector2 beamSpot = Vector2::Zero();
    std::size_t candidates = 0;
    std::size_t fitFailures = 0;
    /// Pairs of pieces merged after the fit (SplitTrackMerger).
    std::size_t splitMerges = 0;
    /// Hits moved or added by the hit reassignment (HitReassigner).
    std::size_t reassignedHits = 0;
    double findingMs = 0.0;
    /// The fit, with the refits of the split-track merging and of the hit
    /// reassignment.
    double fittingMs = 0.0;
    double selectionMs = 0.0;
  };

  /// `sensors`, if given, a module layout of `detector` whose module
  /// numbers are those of the hits (TrackML files, a module-level
  /// simulation): the fit measures each hit on its sensor's plane
  /// (KalmanFitter). Without it hits are measured on the plane of their
  /// own axes, a layer's tangent plane for hits read from files.
  Reconstruction(const Detector& detector, Config config,
                 const std::shared_ptr<const ModuleLayout>& sensors = nullptr);

  /// Reconstructs the tracks of one event. Thread-safe (const).
  Result run(std::span<const Hit> hits) const;

  /// The first problem of `secondPassSteps` for `chain` as (chain-file key
  /// of [second_pass], what); nothing if valid. The steps must exist, be
  /// ascending without repeats, and find tracks (build or helix) in
  /// collections of their own.
  static std::optional<std::pair<std::string, std::string>>
  findSecondPassProblem(const std::vector<std::uint16_t>& secondPassSteps,
                        const FinderConfig& chain);

  const Config& config() const { return m_config; }

 private:
  /// Fits, merges and selects the finder's tracks of one pass into `r`
  /// (tracks appended; counters and times added), their perigees about
  /// the pass's beam line r.beamSpot.
  void fitAndSelect(std::span<const Hit> hits, std::vector<FoundTrack> found,
                    Result& r) const;
  /// The second pass (Config::secondPassSteps) over the hits that no
  /// track of `r` holds; its tracks are appended to r.tracks.
  void secondPass(std::span<const Hit> hits, Result& r) const;

  Config m_config;
  ConformalTrackFinder m_finder;
  KalmanFitter m_fitter;
  SplitTrackMerger m_merger;
  HitReassigner m_reassigner;
  TrackSelector m_selector;
};

/// The reconstruction settings of a chain file (chains/<detector>.toml):
/// the finder's tables ([finder], [vertex_prepass], [[step]]: readChain)
/// and the track selection's [selection] table (keys min_hits,
/// clone_shared_hits, min_unique_hits: TrackSelector::Config; absent keys
/// keep the defaults). Bad values throw InputError naming file, line and
/// key. `fit` is true.
Reconstruction::Config readReconstructionConfig(
    const std::filesystem::path& chainFile, const Detector& detector);

/// readReconstructionConfig on TOML text; `sourceName` names it in errors.
Reconstruction::Config parseReconstructionConfig(std::string_view text,
                                                 const std::string& sourceName,
                                                 const Detector& detector);

/// readReconstructionConfig on a parsed chain file (its root table): one
/// parse, read against several detectors.
Reconstruction::Config readReconstructionTable(const ConfigTable& root,
                                               const Detector& detector);

}  // namespace conftrack
