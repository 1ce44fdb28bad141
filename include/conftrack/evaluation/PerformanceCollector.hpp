#pragma once

/// @file PerformanceCollector.hpp
/// Tracking performance over a run: efficiency, fake and duplicate rates
/// with the CLICdp definitions (evaluation.md A1) and the ACTS variant
/// (A2) as extras, their distributions, residuals and pulls for
/// single-particle samples, and CPU time per step.
///
/// Usage: one collector per run; any thread calls addEvent() for its event;
/// summary() at the end. Per-event results are merged in increasing event
/// index, whatever the thread that produced them and whenever it finished,
/// so that the summary is identical for any thread count.

#include "conftrack/core/Event.hpp"
#include "conftrack/core/Track.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/evaluation/GaussianFit.hpp"
#include "conftrack/evaluation/Histograms.hpp"
#include "conftrack/evaluation/TrackResiduals.hpp"
#include "conftrack/evaluation/TruthMatching.hpp"
#include "conftrack/reconstruction/finding/TrackCandidate.hpp"

#include <cstddef>
#include <cstdint>
#include <map>
#include <mutex>
#include <span>
#include <vector>

namespace conftrack {

/// The extra cuts of the CLICdp efficiency plots (evaluation.md A1 table):
/// each distribution applies all of them except the one on its own
/// variable (versus theta: pT, R_vtx, proximity; versus pT: theta, R_vtx,
/// proximity; versus phi: all; versus R_vtx: all but R_vtx; versus
/// proximity: all but proximity).
struct PlotSelection {
  /// pT > minPt.
  double minPt = 1.0 * units::GeV;
  /// minTheta < theta < maxTheta.
  double minTheta = 10.0 * units::degree;
  double maxTheta = 170.0 * units::degree;
  /// Production radius sqrt(x^2 + y^2) < maxVertexRadius.
  double maxVertexRadius = 50.0 * units::mm;
  /// Proximity (Delta R to the closest other particle) > minProximity.
  double minProximity = 0.02;
};

/// Settings of the performance evaluation.
struct PerformanceConfig {
  /// Reconstructable particles (CLICdp ILDLike).
  ParticleSelection particles;
  /// Count overlaid background particles in the headline efficiencies and
  /// their distributions. Off: as in the paper, those are the physics
  /// event's particles; background efficiency is reported separately.
  bool includeBackground = false;
  /// Track-particle matching of the headline numbers (CLICdp: one-way,
  /// purity >= 0.75; set doubleMatching and purity 0.5 for ACTS).
  MatchingConfig matching;
  /// Ratio of the extra ACTS-style numbers (always double matching).
  double actsMatchingRatio = 0.5;
  /// Track-side selection of the CLICdp plots and "selected" rates:
  /// nHits >= minTrackHits (4 for ttbar, 3 for single particles).
  std::uint32_t minTrackHits = 4;
  /// Cuts of the efficiency plots.
  PlotSelection plotSelection;
  /// Single-particle sample: collect residuals and pulls of the best
  /// matched fitted track of every reconstructable particle.
  bool singleParticle = false;
  /// Nominal polar angles of the resolution curves; a particle belongs to
  /// one if |min(theta, 180 deg - theta) - nominal| <= resolutionThetaWindow.
  std::vector<double> resolutionThetas = {
      10.0 * units::degree, 30.0 * units::degree, 50.0 * units::degree,
      70.0 * units::degree, 89.0 * units::degree};
  double resolutionThetaWindow = 3.0 * units::degree;
  /// Bin edges in generated pT; the default is log-uniform, 4 bins per
  /// decade, centred on 1, 10, 100, ... GeV (edges 10^((k + 1/2)/4) GeV
  /// from 0.075 to 1333 GeV). A curve point is at the mean generated pT of
  /// its entries.
  std::vector<double> resolutionPtEdges = defaultResolutionPtEdges();
  /// Resolution points and pulls need at least this many tracks.
  std::size_t minFitEntries = 10;

  /// Settings for single-particle (muon gun) samples: minTrackHits 3,
  /// residuals on, and no pT or theta cut in the efficiency plots (a gun
  /// at theta = 10 deg or pT < 1 GeV is the point of the plot there).
  static PerformanceConfig singleParticleSample();
  /// The default resolutionPtEdges.
  static std::vector<double> defaultResolutionPtEdges();
};

/// Wall times of one event supplied by the caller [ms].
struct EventTimes {
  double simulation = 0.0;
  double finding = 0.0;
  double fitting = 0.0;
};

/// The three efficiency classes of the summary.
struct EfficiencyRatios {
  Ratio all;          ///< all reconstructable particles
  Ratio ptAbove1GeV;  ///< pT > 1 GeV
  Ratio ptBelow1GeV;  ///< 0.1 GeV <= pT <= 1 GeV (the rest of `all`)

  EfficiencyRatios& operator+=(const EfficiencyRatios& other);
};

/// Performance counts of one event or of several merged events. Counts and
/// histograms are integers (merge order does not matter); the time sums,
/// step list and residual list are appended in merge order.
struct PerformanceData {
  PerformanceData();

  std::uint64_t events = 0;
  /// Events without hit truth (only times and track counts are taken).
  std::uint64_t eventsWithoutTruth = 0;
  /// Field of the last merged event [T].
  double bz = 0.0;

  /// Reconstructable headline particles (see includeBackground).
  std::uint64_t reconstructableParticles = 0;
  std::uint64_t tracks = 0;
  std::uint64_t fittedTracks = 0;
  /// Tracks with nHits >= minTrackHits.
  std::uint64_t selectedTracks = 0;

  /// Efficiency of the headline particles (the physics event's, or all with
  /// includeBackground), of the physics event's and of the background. The
  /// plot-cut ratios and the efficiency histograms are also for the physics
  /// event's particles.
  EfficiencyRatios efficiency;
  EfficiencyRatios signalEfficiency;
  EfficiencyRatios backgroundEfficiency;
  /// Efficiency with the cuts of the plots versus theta, versus pT and
  /// versus phi (all cuts).
  Ratio efficiencyThetaPlotCuts;
  Ratio efficiencyPtPlotCuts;
  Ratio efficiencyAllPlotCuts;

  /// Over all tracks: fake (not matched) and CLICdp duplicate (the majority
  /// particle has more than one track; no purity cut; every member counted).
  Ratio fakes;
  Ratio duplicates;
  /// The same over tracks with nHits >= minTrackHits (duplicate sets
  /// formed among these tracks).
  Ratio selectedFakes;
  Ratio selectedDuplicates;
  /// ACTS convention (double matching at actsMatchingRatio): particle
  /// efficiency, fake rate and duplicate rate (only the extra matched
  /// tracks of a particle count).
  Ratio actsEfficiency;
  Ratio actsFakes;
  Ratio actsDuplicates;

  /// Efficiency distributions with the plot cuts (PlotSelection), in
  /// native units (GeV, rad, mm); efficiencyVsPtAll without extra cuts.
  RatioHistogram efficiencyVsPt;
  RatioHistogram efficiencyVsPtAll;
  RatioHistogram efficiencyVsTheta;
  RatioHistogram efficiencyVsPhi;
  RatioHistogram efficiencyVsVertexRadius;
  RatioHistogram efficiencyVsProximity;
  /// Fake and duplicate rates versus the reconstructed pT (cut
  /// minTheta < theta < maxTheta) and theta (cut pT > minPt), for tracks
  /// with nHits >= minTrackHits.
  RatioHistogram fakeRateVsPt;
  RatioHistogram fakeRateVsTheta;
  RatioHistogram duplicateRateVsPt;
  RatioHistogram duplicateRateVsTheta;

  /// Single-particle samples: one entry per reconstructed particle.
  std::vector<TrackResidual> residuals;

  /// Time sums [ms] and per-step finder statistics (merged by name, in
  /// order of first appearance).
  double simulationMs = 0.0;
  double findingMs = 0.0;
  double fittingMs = 0.0;
  std::vector<StepStats> steps;
  /// Distribution of the reconstruction (finding + fitting) time per
  /// event [ms].
  CountHistogram reconstructionMsPerEvent;

  /// Adds `other` (a later event or block of events) to this.
  void merge(const PerformanceData& other);
};

/// One point of a resolution curve.
struct ResolutionPoint {
  ResidualQuantity quantity = eResidualD0;
  /// Nominal polar angle of the curve [rad].
  double theta = 0.0;
  /// Generated-pT bin and the mean generated pT of its entries [GeV].
  double ptLow = 0.0;
  double ptHigh = 0.0;
  double ptMean = 0.0;
  /// Core fit of the residuals (native units).
  GaussianFit fit;
};

/// Fitted pull distribution of one quantity over all residual entries.
struct PullResult {
  PullQuantity quantity = ePullD0;
  GaussianFit fit;
  /// 50 bins over [-5, 5].
  CountHistogram histogram;
};

/// Final numbers of a run.
struct PerformanceSummary {
  PerformanceConfig config;
  PerformanceData data;
  /// Peak resident memory when the summary was made [MiB].
  double peakRssMb = 0.0;
  /// Single-particle samples: resolution curves (entries per quantity,
  /// theta, pT bin) and pulls (one per PullQuantity); empty otherwise.
  std::vector<ResolutionPoint> resolutions;
  std::vector<PullResult> pulls;

  /// Mean times per event [ms] (0 without events).
  double simulationMsPerEvent() const;
  double findingMsPerEvent() const;
  double fittingMsPerEvent() const;
  double reconstructionMsPerEvent() const;
};

/// Computes the resolution curves and pulls of `data` and reads the peak
/// memory: the end of a run.
PerformanceSummary summarizePerformance(const PerformanceConfig& config,
                                        const PerformanceData& data);

/// Collects per-event performance data of a run from any number of threads.
class PerformanceCollector {
 public:
  using Config = PerformanceConfig;

  /// @param config evaluation settings
  /// @param firstIndex index of the first event to come (a shard's first
  ///        event): results merge as soon as the indices from here on are
  ///        in, instead of waiting for the summary
  explicit PerformanceCollector(Config config = {}, std::size_t firstIndex = 0);

  /// Evaluates one event; no shared state, callable from any thread.
  /// @param event the event with truth (without truth only times and
  ///        track counts are taken)
  /// @param tracks its reconstructed (and possibly fitted) tracks
  /// @param bz the detector field [T]
  /// @param steps the finder's per-step statistics of this event
  /// @param times the wall times of this event
  PerformanceData analyseEvent(const Event& event,
                               std::span<const Track> tracks, double bz,
                               std::span<const StepStats> steps,
                               const EventTimes& times) const;

  /// Hands over the result of event `index` (thread-safe). Results are
  /// merged in increasing index order as soon as all lower indices are
  /// in; with indices 0, 1, 2, ... only the out-of-order ones are held.
  /// Throws std::invalid_argument for an index given twice.
  void add(std::size_t index, PerformanceData data);

  /// analyseEvent() followed by add() (thread-safe).
  void addEvent(std::size_t index, const Event& event,
                std::span<const Track> tracks, double bz,
                std::span<const StepStats> steps, const EventTimes& times);

  /// Merges all results handed over so far, in index order (gaps allowed)
  /// and summarises them (thread-safe; may be called more than once).
  PerformanceSummary summary() const;

  const Config& config() const { return m_config; }

 private:
  Config m_config;
  mutable std::mutex m_mutex;
  /// Results waiting for a lower index.
  std::map<std::size_t, PerformanceData> m_pending;
  /// Next index to merge into m_merged.
  std::size_t m_nextIndex = 0;
  PerformanceData m_merged;
};

}  // namespace conftrack
