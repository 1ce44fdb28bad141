#pragma once

/// @file FinderState.hpp
/// Per-event state of the conformal finder (internal). The finder object is
/// const; everything that changes during an event lives here.

#include "conftrack/geometry/Detector.hpp"
#include "conftrack/reconstruction/finding/ConformalHits.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"
#include "conftrack/reconstruction/finding/HitPool.hpp"
#include "conftrack/reconstruction/finding/TrackCandidate.hpp"

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace conftrack::detail {

/// Total order of candidate quality: longer first, then lower
/// chi2_uv/ndf + chi2_sz/ndf, then the hit lists (deterministic ties).
bool betterCandidate(const TrackCandidate& a, const TrackCandidate& b);

/// betterCandidate of candidate `a` against track `b` as its build made it
/// (TrackCandidate::builtHits and builtQuality): more hits, then lower
/// quality, then the hit lists.
bool betterThanBuilt(const TrackCandidate& a, const TrackCandidate& b);

/// Clone treatment (upstream.md 8, step 5, made order-independent): a new
/// candidate sharing at least `minShared` hits with accepted tracks replaces
/// them if it is better than each of them, and is dropped otherwise. A
/// track accepted earlier in the same build step (builtHits set: buildTracks
/// clears it when the step ends) is judged as built (betterThanBuilt): its
/// completion's hits would otherwise decide for the seed visited first.
class CloneIndex {
 public:
  explicit CloneIndex(std::size_t nHits) : m_hitTracks(nHits) {}
  /// Returns true if `candidate` was added to `tracks`; the tracks it
  /// replaced as clones are then listed by killed().
  bool offer(std::vector<TrackCandidate>& tracks, TrackCandidate candidate,
             std::uint32_t minShared);
  /// The tracks the last successful offer() killed as clones.
  const std::vector<std::uint32_t>& killed() const { return m_killed; }
  /// True if a live track of `tracks` holds hit `h`.
  bool held(ConfIndex h, const std::vector<TrackCandidate>& tracks) const;
  /// Re-indexes after `tracks` was compacted or reordered.
  void rebuild(const std::vector<TrackCandidate>& tracks);
  /// Registers hit `h` as part of track `t` (extensions).
  void addHit(ConfIndex h, std::uint32_t t) { m_hitTracks[h].push_back(t); }
  /// Tracks killed as clones since the last rebuild (still in `tracks`).
  std::size_t dead() const { return m_dead; }

 private:
  std::vector<std::vector<std::uint32_t>> m_hitTracks;
  std::vector<std::uint32_t> m_killed;
  /// offer(): (track, hits shared with the candidate), reused.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> m_shared;
  std::size_t m_dead = 0;
};

/// Everything that changes while one event is processed.
struct FinderState {
  const ConformalHits& hits;
  const Detector& detector;
  const FinderConfig& config;
  /// Field used in the pT estimate [T] (4 T with legacyFourTesla).
  double bzForPt;
  /// The bending factors the hits were mapped with (makeConformalHits);
  /// null in a uniform field or without FinderConfig::fieldCorrection.
  const PromptBending* bending = nullptr;
  /// Per hit: 0 free, 1 on a track or claimed, kReserved held by a track
  /// of an earlier pass (ConformalTrackFinder::Pass), never released.
  std::vector<std::uint8_t> used;
  static constexpr std::uint8_t kReserved = 2;
  std::vector<TrackCandidate> tracks;
  CloneIndex clones;
  /// Vertex regions of the event from the vertex-z pre-pass ([lo, hi] in
  /// z, ascending; empty without a pre-pass or where it found none).
  std::vector<std::pair<double, double>> vertexRegions;
  /// The regions the current build step seeds about (SeedAutomaton): the
  /// event's, or with FindingStep::vertexPrepassFreeHits those of a
  /// pre-pass over the hits no track holds when the step starts.
  std::vector<std::pair<double, double>> stepVertexRegions;

  FinderState(const ConformalHits& h, const Detector& d, const FinderConfig& c,
              double bz)
      : hits(h),
        detector(d),
        config(c),
        bzForPt(bz),
        used(h.size(), 0),
        clones(h.size()) {}
  /// Removes dead tracks and re-indexes.
  void compact();
};

/// sqrt(x^2 + y^2) without std::hypot's overflow protection, which costs
/// several times a square root and is not needed for lengths in mm or
/// slopes (a tenth of the helix step's time went into hypot).
inline double norm2(double x, double y) { return std::sqrt(x * x + y * y); }

/// x^2.
inline double square(double x) { return x * x; }

/// Angle between two 2-D directions, in [0, pi]: atan2(|a x b|, a . b)
/// (no NaN for parallel vectors, unlike acos of the dot product).
inline double angleBetween(double ax, double ay, double bx, double by) {
  return std::atan2(std::abs(ax * by - ay * bx), ax * bx + ay * by);
}

/// Highland width of the deflection in a layer of a track of momentum p
/// [GeV] and slope tanLambda, the path through the layer being
/// 1/sin(theta) on a cylinder and 1/|cos(theta)| on a disk, capped at
/// grazing incidence; 0 without material or momentum. The finders' chi2s
/// know only the hit resolutions and add this where scattering dominates.
double layerTheta0(const SensitiveLayer& layer, double p, double tanLambda);

/// Fits a hit list as a candidate of `step`; returns false if a fit fails
/// or the chi2 cuts reject it.
bool fitCandidate(const FinderState& state, const FindingStep& step,
                  std::vector<ConfIndex> hits, TrackCandidate& out);

/// BuildNewTracks: cellular automaton per seed, path extraction, fits,
/// clone treatment (upstream.md 5, 6, 8).
void buildTracks(FinderState& state, const FindingStep& step,
                 std::uint16_t stepIndex, const HitPool& pool,
                 StepStats& stats);

/// Helix-triplet building of displaced tracks (FindingStep::helix): seeds
/// are triplets of unused hits with a free circle, followed outwards along
/// their helix; accepted tracks claim their hits at once.
void buildHelixTracks(FinderState& state, const FindingStep& step,
                      std::uint16_t stepIndex, const HitPool& pool,
                      StepStats& stats);

/// Completion of a newly built track (a conftrack addition; upstream has
/// neither part): for inside-out steps, follows its fitted helix from the
/// first hit back towards the IP through the step's layers and adds
/// compatible hits (the per-layer extension run backwards); then fills
/// holes, layers crossed between its hits without a hit on the track. Both
/// recover hits lost when a short cell (e.g. between the two sensors of a
/// double layer, 2 mm apart) failed an angle cut and the automaton skipped
/// the layer.
void completeTrack(FinderState& state, const FindingStep& step,
                   const HitPool& pool, StepStats& stats, std::uint32_t t);

/// Final hole filling (FinderConfig::finalHoleFilling): the hole filling
/// of completeTrack for every live track, over `pool`, with the cuts of the
/// step that built each track.
void fillHoles(FinderState& state, const HitPool& pool, StepStats& stats);

/// The chain's vertex-z pre-pass (FinderConfig::vertexPrepass, required):
/// fills state.vertexRegions; returns its statistics (step "VertexZ": its
/// time).
StepStats findVertexRegions(FinderState& state);

/// The vertex regions of the chain's pre-pass over the hits that no track
/// holds (state.used), for a step with FindingStep::vertexPrepassFreeHits.
std::vector<std::pair<double, double>> findFreeHitVertexRegions(
    const FinderState& state);

/// ExtendTracks: per-layer extension of tracks above the step's pT cut,
/// then the catch-all extension of all tracks (upstream.md 10).
void extendTracks(FinderState& state, const FindingStep& step,
                  const HitPool& pool, StepStats& stats);

}  // namespace conftrack::detail
