#pragma once

/// @file Extender.hpp
/// Extension of tracks hit by hit along their predicted helix, and the
/// filling of their holes (internal; the algorithm is described in
/// ExtendTracks.cpp, the hole filling in HoleFilling.cpp).

#include "conftrack/reconstruction/finding/detail/FinderState.hpp"

#include <cstdint>
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

/// A track being extended: hits and fits.
struct Chain {
  std::vector<ConfIndex> hits;
  ConformalFitResult uv;
  ArcFrame arc;
  SzFitResult sz;
};

/// Extends or completes tracks of FinderState::tracks over a hit pool with
/// the cuts of one step.
class Extender {
 public:
  Extender(FinderState& state, const FindingStep& step, const HitPool& pool,
           StepStats& stats)
      : m_state(state),
        m_hits(state.hits),
        m_step(step),
        m_pool(pool),
        m_stats(stats) {}

  /// Extends track t. `catchAll` selects the loose low-pT pass;
  /// `inward` follows the track back towards the IP from its first hit
  /// (per-layer mode only).
  void extend(std::uint32_t t, bool catchAll, bool inward = false);

  /// Hole filling: adds unused hits on layers that the track crosses
  /// between its first and last hit but has no hit on (a cell that skipped
  /// a layer), best chi2 increase first.
  void fill(std::uint32_t t, bool local);

 private:
  /// Sets the pass and copies track into chain with fresh fits; false if
  /// the track is too short or does not fit.
  bool begin(const TrackCandidate& track, bool catchAll, bool inward,
             Chain& chain);

  /// Writes the grown chain back into the track.
  void store(const Chain& chain, TrackCandidate& track) const;

  static double increase(double chi2, int ndf, double delta);

  /// The best unused hit in a hole of the chain (see fill), with or
  /// without the scattering allowance; `best` stays kInvalidIndex if none.
  /// With `local` a hit is judged by its residuals relative to those of
  /// the track's hits on either side of the hole (localHoleChi2) instead
  /// of its residuals to the fits.
  void findHole(const Chain& chain, const std::vector<double>& hitS,
                bool allowance, bool local, ConfIndex& best, double& bestS);

  /// chi2 of hit h (arc length s) in the hole after the chain's hit
  /// `before`, from its residuals to the fits minus those interpolated
  /// between the hits on either side. Below a few GeV multiple scattering
  /// bends a track away from its fitted circle and s-z line by far more
  /// than the hit resolution (chi2/ndf ~ 100 at 1 GeV), but smoothly: the
  /// neighbours' residuals carry the local deviation, which the
  /// difference removes.
  double localHoleChi2(const Chain& chain, const std::vector<double>& hitS,
                       std::size_t before, ConfIndex h, double s,
                       const Scatter& ms) const;

  bool refit(Chain& c, const ConformalFitResult* frame) const;

  /// Best total chi2 increase of the next `depth` layers after adding h.
  double lookahead(const Chain& chain, ConfIndex h, int depth);

  /// The deflection in the material of the layer of hit `from`, seen at
  /// hit `to` a transverse arc length `ds` further on: the conformal fits
  /// know only the hit resolutions, and below a few GeV the outer tracker's
  /// 7 um are far smaller than this (0.4 mm at 1 GeV between two outer
  /// layers), so good hits would fail the chi2 cuts.
  Scatter scatter(const ConformalFitResult& uv, const SzFitResult& sz,
                  ConfIndex from, ConfIndex to, double ds) const;

  bool onSensorOf(const std::vector<ConfIndex>& hits, ConfIndex h) const;

  /// Compatible hits on the first layer crossed after the chain's last hit,
  /// best (lowest chi2 increase) first. `excluded` is a tentative hit of
  /// the look-ahead. Returns whether any crossing was predicted at all.
  /// Hits compatible within the hit resolutions are preferred; only when
  /// there are none are the chi2 increments recomputed with the allowance
  /// for multiple scattering (FinderConfig::scatteringAllowance). In dense
  /// jets the allowance alone let low-pT tracks take hits of neighbours
  /// a fraction of a mm away.
  bool collect(const Chain& chain, std::vector<Candidate>& out,
               ConfIndex excluded = kInvalidIndex);

  /// collect, without (`allowanceReach` null) or with the scattering
  /// allowance in the chi2 increments; with it, only crossings up to that
  /// distance from the end are searched. `nearest` receives the distance
  /// of the nearest predicted crossing.
  bool collectWith(const Chain& chain, std::vector<Candidate>& out,
                   ConfIndex excluded, const double* allowanceReach,
                   double* nearest);

  /// Keeps at most FinderConfig::maxWindowHits hits of m_window, those
  /// nearest to the predicted crossing `at` (then by index); counts the
  /// cut. The callers choose among the hits by a total order, so the kept
  /// set, not its order, must be deterministic.
  void limitWindow(const Vector3& at);

  /// Crossings of `layer` after arc length sLast (within one turn).
  void predict(std::uint32_t layer, const ArcFrame& arc, const SzFitResult& sz,
               double sLast);

  FinderState& m_state;
  const ConformalHits& m_hits;
  const FindingStep& m_step;
  const HitPool& m_pool;
  StepStats& m_stats;
  bool m_catchAll = false;
  bool m_inward = false;
  bool m_quadratic = true;
  /// Outer radius of the tracker's layers plus a margin [mm] (set on first
  /// use).
  double m_outerRadius = -1.0;
  std::vector<Prediction> m_predictions;
  std::vector<ConfIndex> m_window;
  /// Scratch of limitWindow: (squared distance, hit).
  std::vector<std::pair<double, ConfIndex>> m_distances;
};

}  // namespace conftrack::detail
