#pragma once

/// @file HelixFollower.hpp
/// The following part of the helix step for displaced tracks
/// (FindingStep::helix, docs/algorithm.md 3.8): a candidate, seeded as a
/// triplet of hits (HelixTracks.cpp), is extended outwards layer crossing
/// by layer crossing along the helix of its hits.

#include "conftrack/reconstruction/finding/ConformalHits.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"
#include "conftrack/reconstruction/finding/HitPool.hpp"
#include "conftrack/reconstruction/finding/detail/FinderState.hpp"
#include "conftrack/reconstruction/finding/detail/HelixPath.hpp"
#include "conftrack/reconstruction/finding/detail/HelixPredictionError.hpp"

#include <cstdint>
#include <limits>
#include <vector>

namespace conftrack::detail {

/// Extends helix-step candidates over one step's hit pool. Reads the
/// finder's state (which hits are used, the overlap settings, the field)
/// and writes nothing but the paths it is given; not thread-safe (scratch
/// buffers), one per step run.
///
/// At each predicted crossing of a pool layer (the helix of the circle
/// fitted to all hits, rescaled to the field ahead (nextStretch), z from
/// the (s, z) filter), the compatible unused hit of lowest chi2 is taken
/// with its overlap partners on other sensors of the layer; the chi2 has
/// the layer's resolution (on a disk also its radial one, across the
/// track as far as the track runs across the radius), the prediction's
/// transverse error (HelixPredictionError) and the filter's z error.
/// Residuals are taken at the hit, since a layer's sensors
/// lie up to FinderConfig::overlapMaxGap from its nominal surface. The
/// path ends at the first crossing past follow()'s maxMissedLayers
/// crossings without a hit (crossings of layers it already holds do not
/// count).
class HelixFollower {
 public:
  /// An extension looks at the pool's layers within four times the
  /// step's maxSeedLength of its last hit's layer.
  HelixFollower(const FinderState& state, const FindingStep& step,
                const HitPool& pool);

  /// How far follow() goes: crossings without a hit, and the chi2 cut
  /// per added hit (the step's maxMissedLayers and chi2Cut while
  /// building, its continueMissedLayers and continueChi2Cut when an
  /// accepted candidate is followed on).
  struct Limits {
    std::uint32_t maxMissedLayers = 0;
    double chi2Cut = 0.0;
    /// The path runs against the particle's motion (followInward): it
    /// ends where its helix comes closest to the beam line, where the
    /// particle was produced at the latest.
    bool untilClosestApproach = false;
    /// The path runs against the particle's motion and goes on past its
    /// closest approach to the beam line (followPastTurn): the crossings
    /// before that point are neither searched nor counted as missed until
    /// the first hit beyond it is taken.
    bool fromClosestApproach = false;
  };

  /// Extends the path outwards hit by hit (see the class comment), ending
  /// it past `limits.maxMissedLayers` crossings without a hit.
  void follow(HelixPath& p, const Limits& limits);
  /// Follows the path from its first hit against the motion, towards the
  /// particle's production point, like follow() (the same limits), and
  /// puts the hits found before its first. A step seeded in an outer
  /// subdetector takes the particle's hits in the inner one this way
  /// (FindingStep::inwardCollections).
  void followInward(HelixPath& p, const Limits& limits);
  /// After followInward: follows the path on from its first hit against
  /// the motion, past the helix's closest approach to the beam line and
  /// out along the other leg (the particle's way in, if it was produced
  /// off the beam line moving inwards), with `limits`, skipping the
  /// crossings before the closest approach. The hits found there are put
  /// before the path's first if they are at least `minHits`
  /// (FindingStep::pastTurnMinHits); otherwise the path is unchanged.
  void followPastTurn(HelixPath& p, const Limits& limits,
                      std::uint32_t minHits);

  /// Adds the overlap partners of the path's seed hits (its first three),
  /// which follow() does not see: on other sensors of a seed hit's layer,
  /// unused hits within FinderConfig::overlapMaxArc of it whose residuals
  /// to the path's circle and (s, z) line differ from the seed hit's by
  /// at most FinderConfig::overlapMaxChi2 (the test of
  /// addOverlapPartners), the best per sensor, up to three hits per
  /// layer. Keeps the hits in arc-length order. A forward particle in
  /// TrackML's pixel disks leaves pairs and triples on every disk: without
  /// them its path has a hit per disk and falls short of the step's
  /// minHits.
  void addSeedPartners(HelixPath& p);

  /// True if the triplet's helix crosses another layer of the pool well
  /// inside its extent between its first and last hit: a seed must not
  /// skip a layer (the detector's layers are efficient, and a triplet
  /// spread over distant layers is mostly a random combination).
  bool skipsLayer(const HelixPath& p, const TransverseCircle& c);

  /// helixTheta0 for this step's pT floor.
  double theta0(std::uint32_t layer, double pt, double t) const;
  /// circlePt in the field the finder uses for pT.
  double ptOf(const TransverseCircle& c) const;

 private:
  /// A hit compatible with a predicted layer crossing: its chi2, arc
  /// length from the track's last hit, distance from the circle and z
  /// residual.
  struct LayerHit {
    ConfIndex hit;
    double chi2;
    double arc;
    double rPhi;
    double dz;
  };

  /// A predicted crossing of a layer.
  struct Crossing {
    std::uint32_t layer;
    double ds;  ///< arc length from the last hit
    double x, y, z;
    bool inside;  ///< well inside the layer's extent
  };

  /// Fits the path's circle (c) and (s, z) filter (sz; the arc lengths of
  /// p are recomputed on c) and fills m_layerHits with the compatible
  /// unused hits of the first predicted crossing that has any; false if
  /// the path ends first (no circle, the half-turn, or more than
  /// m_limits.maxMissedLayers crossings without a hit).
  bool nextCrossing(HelixPath& p, TransverseCircle& c, SzState& sz);

  /// The hit of m_layerHits to take (m_layerHits is left sorted by chi2):
  /// the best by its chi2 plus that of the best hit one crossing further.
  ConfIndex choose(const HelixPath& p);

  /// In a field that changes along the track (TrackML's solenoid): the
  /// circle of the path's next stretch. The circle c fitted to the hits
  /// has the mean bending of the field along them; it is rescaled about
  /// the last hit by that mean over the bending half-way to the next layer
  /// crossing inside its layer (predicted with the bending at the last
  /// hit first). Returns c in a uniform field. Leaves the crossings
  /// predicted on the returned circle in m_crossings.
  TransverseCircle nextStretch(const HelixPath& p, const TransverseCircle& c,
                               const SzState& sz);

  /// Predicted crossings of the pool's layers after hit `from` (arc length
  /// sFrom on the line z = z0 + t s), within the outgoing half-turn and
  /// within `maxArc` of the hit, nearest first. `inside` is set for
  /// crossings at least kHelixEdgeMargin inside the layer's extent (where
  /// a missing hit is a real miss). A crossing's arc length does not
  /// depend on maxArc, which only leaves out the later ones (and the
  /// barrels further across the radius, which the arc cannot reach).
  void predict(ConfIndex from, double sFrom, double z0, double t,
               const TransverseCircle& c, std::vector<Crossing>& out,
               double maxArc = std::numeric_limits<double>::infinity());

  /// Sets m_taken to the chosen hit of a layer crossing and, on other
  /// sensors of the same layer, the compatible hits of the crossing's
  /// window (m_layerHits, sorted by chi2 as choose() leaves it), the best
  /// per sensor: a particle crossing the
  /// overlap of two sensors leaves a hit on each. A partner is judged by
  /// the difference of its residuals and the chosen hit's (the track's own
  /// prediction error, far larger below a few GeV, cancels over the few
  /// mm between them; OverlapHits does the same for conformal tracks).
  void addOverlapPartners(ConfIndex chosen, double t, double pt);

  /// chi2 of two hits of one layer crossing on different sensors: the
  /// differences dPerp of their distances from the circle and dz of their
  /// z residuals (slope t), against both hits' errors, the scattering by
  /// `deflection` in a's sensor (overlapScatteringVariance; theta0() of its
  /// layer, once per layer crossing) and a 0.05 mm alignment floor.
  double pairChi2(ConfIndex a, ConfIndex h, double dPerp, double dz, double t,
                  double deflection) const;

  /// A hit's transverse resolution [mm] (its conformal tangential error
  /// scaled back).
  double transverseSigma(ConfIndex h) const;

  /// True if the path has a hit on `layer`.
  bool onLayerOf(std::uint32_t layer, const HelixPath& p) const;

  /// True if hit h is already on the path.
  static bool onPath(ConfIndex h, const HelixPath& p);

  const FinderState& m_state;
  const ConformalHits& m_hits;
  const std::vector<SensitiveLayer>& m_layers;
  const FindingStep& m_step;
  /// The limits of the current follow().
  Limits m_limits;
  const HitPool& m_pool;
  std::vector<ConfIndex> m_window;
  std::vector<Crossing> m_crossings;
  /// The compatible hits of the current layer crossing, and those taken.
  std::vector<LayerHit> m_layerHits;
  std::vector<LayerHit> m_taken;
  /// Scratch of the look-ahead (choose).
  std::vector<LayerHit> m_candidates;
  HelixPath m_trial;
  /// The transverse error of the current prediction, and its inputs per
  /// path hit besides its arc length (transverse error, scattering angle).
  HelixPredictionError m_error;
  std::vector<double> m_errorSigma;
  std::vector<double> m_errorKink;
  /// Per detector layer: the pool's layers an extension looks at.
  std::vector<std::vector<std::uint32_t>> m_reach;
};

}  // namespace conftrack::detail
