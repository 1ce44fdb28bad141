#pragma once

/// @file HelixSeeds.hpp
/// The seeds of the helix step for displaced tracks (FindingStep::helix,
/// docs/algorithm.md 3.8): triplets of unused hits on consecutive layers
/// with a free circle (HelixTracks.cpp follows and accepts them).

#include "conftrack/reconstruction/finding/ConformalHits.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"
#include "conftrack/reconstruction/finding/HitPool.hpp"
#include "conftrack/reconstruction/finding/StepStats.hpp"
#include "conftrack/reconstruction/finding/detail/FinderState.hpp"
#include "conftrack/reconstruction/finding/detail/HelixFollower.hpp"
#include "conftrack/reconstruction/finding/detail/HelixPath.hpp"

#include <cstdint>
#include <utility>
#include <vector>

namespace conftrack::detail {

/// A seed of the helix step: three hits, their circle, and the (s, z) kink
/// in units of its expected spread.
struct HelixTriplet {
  HelixPath path;
  TransverseCircle circle;
  double kink = 0.0;
};

/// The seed triplets of one helix step over its hit pool. Seeds are
/// triplets of unused hits on consecutive layers (the straight line
/// between two seed hits must not pass well inside another layer), each
/// within maxSeedLength of the previous one (further between adjacent
/// layers up to maxSeedGap apart, and with seedLengthPerGap between
/// layers whose scaled distance exceeds it) and further out (larger radius on a
/// barrel layer, larger |z| on a disk). The third hit is searched only
/// around the doublet's chord extended to the next layer, as wide as a
/// track of pT >= minPt can bend. The circle through the three, with no
/// beam-line constraint, must have pT >= minPt (within the error of a
/// three-hit curvature) and |d0| <= maxD0, and the slopes of its two
/// segments in the (s, z) plane, where a helix is straight, must agree
/// within maxCellAngleRZ plus three standard deviations of multiple
/// scattering and resolution. Not thread-safe (scratch buffers).
class HelixSeeds {
 public:
  /// `follower` gives the scattering angles and pT of a circle.
  HelixSeeds(const FinderState& state, const FindingStep& step,
             const HitPool& pool, const HelixFollower& follower);

  /// The triplets of seed hit h1, straightest (lowest kink) first; each
  /// counts as a cell of `stats`.
  void triplets(ConfIndex h1, std::vector<HelixTriplet>& out, StepStats& stats);

 private:
  /// True if no other layer of the pool lies between layers a and b, gap
  /// apart (its distances to both add up to theirs within 1 mm).
  bool adjacent(std::uint32_t a, std::uint32_t b, double gap) const;

  /// The longest seed segment from a hit on layer a to one on layer b.
  double seedLength(std::uint32_t a, std::uint32_t b) const;

  /// True if the straight line from hit a to hit b passes well inside
  /// another layer of the pool (a doublet must not skip a layer; over a
  /// seed's length the helix is close to the chord).
  bool chordSkipsLayer(ConfIndex a, ConfIndex b) const;

  /// Seeds move outwards: to a larger radius on a barrel layer, to a
  /// larger |z| on a disk.
  bool outwards(ConfIndex from, ConfIndex to) const;

  /// Unused pool hits within maxSeedLength of hit `from`, on other layers
  /// than its own, further out (outwards()); sorted by index.
  void neighbours(ConfIndex from, std::vector<ConfIndex>& out);

  /// Unused pool hits that can follow the doublet (h1, h2) on a track of
  /// pT >= minPt, sorted by index: on each nearby layer (not theirs), the
  /// window around the doublet's chord extended from h2, as wide as the
  /// bending (the chord's direction differs from the track's at h2 by at
  /// most d12 / (2 rho_min), and a track leaves its tangent by
  /// l^2 / (2 rho_min)) and, along z or R, as the longitudinal deflection
  /// at pT = minPt allows.
  void thirdCandidates(ConfIndex h1, ConfIndex h2, std::vector<ConfIndex>& out);

  /// Variance of the (s, z) slope between two hits a distance ds apart.
  double slopeVariance(ConfIndex a, ConfIndex b, double ds, double t) const;

  /// False if the triplet's curvature exceeds that of pT = minPt by more
  /// than three standard deviations of its measurement (hit resolution and
  /// scattering in the middle layer): the circle through three hits a few
  /// cm apart in the transverse plane (forward tracks) measures the
  /// curvature poorly.
  bool bendAllowed(ConfIndex h1, ConfIndex h2, ConfIndex h3,
                   const TransverseCircle& c) const;

  const FinderState& m_state;
  const ConformalHits& m_hits;
  const std::vector<SensitiveLayer>& m_layers;
  const FindingStep& m_step;
  const HitPool& m_pool;
  const HelixFollower& m_follower;
  /// Radius of curvature at pT = minPt [mm].
  double m_minRho;
  std::vector<ConfIndex> m_window;
  std::vector<ConfIndex> m_seconds;
  std::vector<ConfIndex> m_thirds;
  std::vector<std::pair<double, std::uint32_t>> m_layerSteps;
  /// Per detector layer: the scattering angle at pT = minPt, normal
  /// incidence.
  std::vector<double> m_maxTheta0;
  /// Per detector layer: the pool's layers within maxSeedLength.
  std::vector<std::vector<std::uint32_t>> m_near;
  /// Per pair of detector layers (a * layers + b): the longest seed
  /// segment between them (maxSeedLength, more between adjacent layers
  /// further apart and with seedLengthPerGap).
  std::vector<double> m_seedLength;
};

}  // namespace conftrack::detail
