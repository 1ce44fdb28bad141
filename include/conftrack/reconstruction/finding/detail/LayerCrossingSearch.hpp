#pragma once

/// @file LayerCrossingSearch.hpp
/// The machinery that the extension units (TrackExtension,
/// CatchAllExtension, InwardExtension) and the HoleFilling share
/// (internal): a track growing hit by hit (Chain) and its refit, the
/// predicted crossings of a layer by its helix, the bounded hit window
/// around a crossing, and the allowance for multiple scattering.

#include "conftrack/reconstruction/finding/detail/FinderState.hpp"

#include <cstdint>
#include <limits>
#include <string_view>
#include <utility>
#include <vector>

namespace conftrack::detail {

/// A predicted crossing of a layer: arc length and azimuth.
struct Prediction {
  double s;
  double phi;
};

/// A compatible hit on a predicted layer crossing.
struct Candidate {
  ConfIndex hit;
  double s;     ///< predicted arc length of the crossing
  double chi2;  ///< chi2_uv + chi2_sz increase
  double dUv;
};

/// Allowance for multiple scattering at a hit (variances added to the
/// hit's own in the chi2 increments).
struct Scatter {
  double uv = 0.0;  ///< perpendicular to the conformal curve [1/mm^2]
  double z = 0.0;   ///< along z [mm^2]
};

/// A track being grown: hits and fits.
struct Chain {
  std::vector<ConfIndex> hits;
  ConformalFitResult uv;
  ArcFrame arc;
  SzFitResult sz;
  /// The conformal fit model of the track the chain started from, kept
  /// while it grows: a track built with the straight-line (prompt) model
  /// keeps it (see TrackExtension.hpp for why).
  bool quadratic = true;
};

/// Which way along the track a search goes from the chain's end hit.
enum class Direction : std::uint8_t {
  eOutward,  ///< after the last hit, away from the IP
  eInward,   ///< before the first hit, back towards the IP
};

/// Which crossings of a barrel layer are predicted.
enum class Branches : std::uint8_t {
  /// Within half a turn of the end hit: the branch the particle is on.
  eOutgoing,
  /// Within one turn: both crossings (a looper coming back in).
  eWholeTurn,
};

/// Where the searches of one chain state start (LayerCrossingSearch::start):
/// the chain's circle and (s, z) line, the arc length of the hit it is
/// extended from and the direction, and the arc length beyond which no
/// crossing is predicted. That limit depends on the chain, not on the
/// layer, so it is taken once for the loop over a pool's layers (two
/// circle intersections and arc lengths, each an atan2: taken per layer
/// they were half of predict()'s cost on CLICdet).
struct SearchStart {
  ArcFrame arc;
  SzFitResult sz;
  double sLast = 0.0;
  Direction direction = Direction::eOutward;
  /// Outward: where the track's circle first leaves the tracker (the
  /// largest barrel radius or disk outer radius, plus a margin) or
  /// FinderConfig::maxTrackTurns from its first hit, whichever is first;
  /// inward: infinite.
  double sExit = std::numeric_limits<double>::infinity();
};

/// Scratch buffers of the searches, reused from track to track so that the
/// loops over crossings and hits allocate nothing once they have grown.
struct CrossingScratch {
  std::vector<Prediction> predictions;
  std::vector<ConfIndex> window;
  /// Of window(): (squared distance, hit).
  std::vector<std::pair<double, ConfIndex>> distances;
  /// Outer radius of the tracker's layers plus a margin [mm]; negative
  /// until predict() first needs it.
  double outerRadius = -1.0;
};

/// The searches of one unit's run on one track: binds the event's state,
/// the hit pool and the counters to the unit's scratch buffers. Made anew
/// for each run (it holds only references).
class LayerCrossingSearch {
 public:
  /// `maxWindowHits`: FinderConfig::maxWindowHits, the bound on the hits
  /// examined per predicted crossing (counted as Guard::eWindowHits).
  LayerCrossingSearch(const FinderState& state, const HitPool& pool,
                      StepStats& stats, std::uint32_t maxWindowHits,
                      CrossingScratch& scratch)
      : m_state(state),
        m_hits(state.hits),
        m_pool(pool),
        m_stats(stats),
        m_maxWindowHits(maxWindowHits),
        m_scratch(scratch) {}

  const FinderState& state() const { return m_state; }
  const ConformalHits& hits() const { return m_hits; }
  const HitPool& pool() const { return m_pool; }

  /// Copies `track` into `chain` with fresh fits; false if the track is
  /// too short (< 3 hits), a helix-step track (its hits need not lie on a
  /// conformal line or parabola) or does not fit.
  bool begin(const TrackCandidate& track, Chain& chain) const;

  /// Refits the chain's hits (the conformal fit in the frame of `frame`);
  /// false, leaving the fits as they were, if a fit fails.
  bool refit(Chain& c, const ConformalFitResult* frame) const;

  /// The start of the searches along `arc` and `sz` from arc length
  /// `sLast` in `direction` (its SearchStart::sExit computed here).
  SearchStart start(const ArcFrame& arc, const SzFitResult& sz, double sLast,
                    Direction direction);

  /// Crossings of `layer` beyond `from.sLast` in `from.direction`, those of
  /// `branches`, near the layer's extent (kept until the next call).
  /// Outward, none beyond `from.sExit`: a crossing after the track has
  /// left the tracker, a turn later, is another particle's.
  const std::vector<Prediction>& predict(std::uint32_t layer,
                                         const SearchStart& from,
                                         Branches branches);

  /// The pool's hits on `layer` within `halfWidth` of azimuth `phi` and,
  /// if `cone` is set, in that (z, R) cone; at most maxWindowHits of them,
  /// those nearest to the predicted crossing `at` (kept until the next
  /// call).
  const std::vector<ConfIndex>& coneWindow(std::uint32_t layer, double phi,
                                           double halfWidth,
                                           const HitPool::RzCone* cone,
                                           const Vector3& at);

  /// As coneWindow, in a box along the layer (z in [zLo, zHi] on barrels,
  /// R in [rLo, rHi] on disks) instead of a cone.
  const std::vector<ConfIndex>& boxWindow(std::uint32_t layer, double phi,
                                          double halfWidth, double zLo,
                                          double zHi, double rLo, double rHi,
                                          const Vector3& at);

  /// The deflection in the material of the layer of hit `from`, seen at
  /// hit `to` a transverse arc length `ds` further on: the conformal fits
  /// know only the hit resolutions, and below a few GeV the outer tracker's
  /// 7 um are far smaller than this (0.4 mm at 1 GeV between two outer
  /// layers), so good hits would fail the chi2 cuts.
  Scatter scatter(const ConformalFitResult& uv, const SzFitResult& sz,
                  ConfIndex from, ConfIndex to, double ds) const;

  /// True if one of `hits` is on the sensor of h (one hit per sensor).
  bool onSensorOf(const std::vector<ConfIndex>& hits, ConfIndex h) const;

  /// Increase of chi2/ndf when a hit adds `delta` to chi2 and one to ndf.
  static double increase(double chi2, int ndf, double delta);

 private:
  /// Keeps at most m_maxWindowHits hits of the window, those nearest to
  /// the predicted crossing `at` (then by index); counts the cut. The
  /// callers choose among the hits by a total order, so the kept set, not
  /// its order, must be deterministic.
  void limitWindow(const Vector3& at);

  const FinderState& m_state;
  const ConformalHits& m_hits;
  const HitPool& m_pool;
  StepStats& m_stats;
  std::uint32_t m_maxWindowHits;
  CrossingScratch& m_scratch;
};

/// Adds hit h to track t's bookkeeping: the hit is used at once (the next
/// tracks must not take it), indexed for the clone treatment, and counted.
void claimHit(FinderState& state, StepStats& stats, ConfIndex h,
              std::uint32_t t);

/// Writes a grown chain back into the track (hits, fits, pT estimate).
void storeChain(const FinderState& state, const Chain& chain,
                TrackCandidate& track);

/// Largest angle cut or azimuth window of the units' configurations [rad]
/// (that of the chain validation).
inline constexpr double kMaxSearchAngle = 3.14159;

/// Throws std::invalid_argument for a bad configuration value of a unit:
/// "<unit>: key '<key>' <what> (got <value>)", the key being the chain
/// file's.
[[noreturn]] void throwBadKey(std::string_view unit, std::string_view key,
                              std::string_view what, double value);

}  // namespace conftrack::detail
