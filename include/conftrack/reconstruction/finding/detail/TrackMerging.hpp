#pragma once

/// @file TrackMerging.hpp
/// Track merging (internal): pieces of one particle that the finder built
/// as separate tracks (an extension that stopped at a gap, a piece seeded
/// later from the leftover hits) are joined into one track (issue 15; the
/// algorithm is described in TrackMerging.cpp).

#include "conftrack/core/Units.hpp"
#include "conftrack/reconstruction/finding/detail/FinderState.hpp"
#include "conftrack/reconstruction/finding/detail/HelixPath.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace conftrack::detail {

class UnusedHits;

/// Merges compatible live tracks of a FinderState.
class TrackMerger {
 public:
  /// Cuts of the merging (FinderConfig::merge*, read from the chain's
  /// [finder] table).
  struct Config {
    /// Largest difference of the azimuths of the two pieces' circle
    /// centres seen from the origin [rad] (a prompt piece's centre lies at
    /// its initial direction -+ pi/2, well measured even for short pieces).
    double maxDeltaPhi = 0.1;
    /// Largest transverse distance of a hit of one piece from the circle
    /// fitted to the other (the one reaching further out) [mm].
    double maxDistance = 10.0;
    /// Largest |z| distance of a hit of one piece from the s-z line of the
    /// other [mm].
    double maxDz = 20.0;
    /// Largest transverse distance between two hits of the merged track on
    /// one layer (on different sensors: an overlap) [mm]; hits on one
    /// layer further apart are a looper's further turn and forbid the
    /// merge.
    double maxSameLayerDistance = 25.0;
    /// The merged fit's chi2 per degree of freedom (each of uv and sz)
    /// must not exceed this multiple of the larger of the pieces' own,
    /// with the pieces' value counted as at least 1 (the steps' own chi2
    /// cuts are not applied: see TrackMerging.cpp).
    double maxChi2Ratio = 10.0;
    /// Below this momentum the s-z bound (maxChi2Ratio times the pieces'
    /// chi2/ndf) is multiplied by (scatteringMomentum / p)^2, p from the
    /// merged fits [GeV]: the s-z fit's errors hold no multiple
    /// scattering, and the scattering between two pieces, which each
    /// piece's own line absorbs, adds to the merged chi2 in proportion to
    /// 1 / p^2 (CLD tt-bar + 30 BX: pieces of one particle of 0.1-1 GeV
    /// reached merged/own ratios of 15-260).
    double scatteringMomentum = 1.0 * units::GeV;
    /// Hits of the piece tested against the other's circle and s-z line
    /// that may fail those tests (maxDistance, maxDz); they are left out
    /// of the merged track, which keeps at least three of the piece's
    /// hits.
    std::uint32_t maxOutliers = 1;
    /// Rounds of merging (a particle in three pieces needs two).
    std::uint32_t maxRounds = 3;
    /// Drop a track that is a further half-turn of a better track's helix
    /// (a looper that the finder found once per half-turn): it lies on the
    /// same circle, crossed in either sense, at a z of the helix one or
    /// more turns on. Only tracks whose circle fits inside
    /// maxLoopDiameter can loop.
    bool dropTurns = true;
    /// Largest variation along a further turn of its hits' distance from
    /// the first half-turn's circle, and largest mean of that distance
    /// divided by 1 + path / scale as the z distance (turnDzPathScale)
    /// [mm] (mergeTracks: FinderConfig::mergeMaxDistance). A turn on a
    /// circle that energy loss has shrunk lies at a nearly constant
    /// distance; another particle's track crossing the circle does not.
    /// Twice that on CLICdet tt-bar + 30 BX (100 events) took the
    /// duplicate rate from 5.7 % to 4.7 % but lost 0.16 % of the particles
    /// of 0.1-1 GeV: turns far off their first half-turn's circle are not
    /// told from neighbouring low-pT particles. An end hit of a track
    /// further than this from the free circle of its other hits is left
    /// out of its circle (TurnCircle).
    double maxTurnDistance = 10.0;
    /// Largest distance of a further turn's circle centre, and of its
    /// radius, from the first half-turn's [mm]. The turn's circle is a
    /// free least-squares fit to its hits (its conformal fit assumes a
    /// circle through the origin, which a turn moved by energy loss and
    /// scattering is not). A turn piece of four to six hits measures its
    /// circle poorly, so this gate is wide and the decision is taken by
    /// the turn score below.
    double maxTurnCentreDistance = 30.0;
    /// The turn score: the sum of the squares of four differences, each
    /// divided by its scale, at most maxTurnScore. The differences are
    /// those of tanLambda (the second turn crossed in the opposite sense
    /// has the opposite sign), of the circle centres [mm], the largest z
    /// distance of a turn hit from the first half-turn's helix at the best
    /// whole number of turns [mm], and the transverse distance of
    /// maxTurnDistance [mm] (both divided as turnDzPathScale says). The scales
    /// are the typical values of true further turns on CLICdet tt-bar + 30 BX
    /// (medians 0.019, 4, 2.3 and 1.2); another particle on a nearby circle
    /// differs most in tanLambda (median 0.16), which the position gates alone
    /// miss for central loopers, whose z advances by millimetres per turn.
    double turnScaleTanLambda = 0.03;
    /// Scale of the circle-centre difference in the turn score [mm].
    double turnScaleCentre = 8.0;
    /// Scale of the z distance in the turn score [mm].
    double turnScaleDz = 5.0;
    /// Scale of the transverse hit distance in the turn score [mm].
    double turnScaleDistance = 3.0;
    /// Largest turn score of a dropped turn (CLICdet tt-bar + 30 BX, 100
    /// events: 12 gives 2.74 % duplicates and 97.54 % at 0.1-1 GeV, 16
    /// 2.49 % and 97.54 %, 25 2.26 % and 97.41 %; before the distance's
    /// path allowance, 12 4.05 %, 16 3.68 %, 25 3.30 %).
    double maxTurnScore = 16.0;
    /// Largest turn score of a further turn whose hits join the first
    /// half-turn's track (TrackCandidate::turnHits: on the track, in none
    /// of its fits); a turn scoring above it, up to maxTurnScore, is
    /// dropped and its hits are left alone. On CLICdet tt-bar + 30 BX (40
    /// events, turns matched to the truth) the turn is the first
    /// half-turn's particle in 99 % of the turns scoring at most 1, 97 %
    /// at 2-4, 83 % at 4-8, 61 % at 8-12 and 39 % at 12-16. 0 joins none.
    double maxJoinScore = 4.0;
    /// Largest turn score of a single unused hit on a further turn of a
    /// track that can loop (TrackMergingTurnHits.cpp): its squared
    /// transverse distance from the track's free circle over
    /// turnScaleDistance squared plus its squared z distance from the
    /// track's helix, at the best whole number of turns on (0-3), over
    /// turnScaleDz squared, with no allowance for the path (0.1: within
    /// 0.95 mm and 1.6 mm). Such hits join the track as a joined turn's
    /// do, each to the track it scores best with; they are the hits of
    /// further turns that no track was built from. CLICdet tt-bar + 30 BX
    /// (100 events, ideal layers / sensors): ACTS fake rate 3.23 / 3.47 %
    /// without, 2.65 / 2.92 % with 0.1, 2.55 / 2.83 % with 0.16; the
    /// CLICdp fake rate 0.203 / 0.255 %, 0.230 / 0.284 %, 0.249 / 0.305 %.
    /// 0 collects none. No hit further along the helix than the chain's
    /// max_track_turns from the track's first hit is collected.
    double maxTurnHitScore = 0.1;
    /// Largest score of a hit taken by the turn follower
    /// (TrackMergingTurnFollower.cpp), which follows each looping track hit
    /// by hit beyond its last hit: as maxTurnHitScore's, but against the
    /// circle and s-z line of the track's latest hits, continued to the
    /// hit (0.25: within 1.5 mm and 2.5 mm), so that it follows a circle
    /// that energy loss shrinks turn by turn. CLICdet tt-bar + 30 BX (100
    /// events, ideal layers / sensors): ACTS fake rate 2.65 / 2.92 %
    /// without, 2.46 / 2.71 % with 0.25, 2.40 / 2.63 % with 0.5; the
    /// CLICdp fake rate 0.230 / 0.284 %, 0.230 / 0.283 %, 0.234 / 0.295 %.
    /// 0 follows none.
    double maxFollowScore = 0.25;
    /// Largest arc from one hit of the turn follower to the next, in turns
    /// of the track's circle (0.5 takes more hits of other particles: the
    /// CLICdp fake rate 0.230 -> 0.237 %).
    double followMaxGapTurns = 0.25;
    /// Where the turn follower finds no hit within reach (the apex of a
    /// looper beyond the last layer it crosses), look for the next turn as
    /// a segment of four unused hits of its own (TrackMergingTurnFollower.cpp).
    /// CLICdet tt-bar + 30 BX (100 events, ideal layers / sensors): ACTS
    /// fake rate 2.46 / 2.71 % without, 2.19 / 2.45 % with; the CLICdp fake
    /// rate 0.230 / 0.286 % and 0.234 / 0.295 %.
    bool followJumps = true;
    /// The z distance of a turn hit from the first half-turn's helix, and
    /// the mean transverse distance of its hits, are divided by
    /// 1 + path / scale, path being the arc length from the first
    /// half-turn's last hit [mm] and scale this value times p / 1 GeV
    /// below 1 GeV (p of the first half-turn's free circle and
    /// tanLambda): scattering, energy loss and the tanLambda error make
    /// the position of a turn a metre on uncertain by tens of millimetres,
    /// in proportion to 1 / p (CLICdet tt-bar + 30 BX, before the p
    /// factor: the duplicate rate 5.3 -> 5.05 %, 500 mm 4.98 %, 2 m
    /// 5.13 %, with one particle of 0.1-1 GeV in 3047 lost).
    double turnDzPathScale = 1000.0;
    /// Largest diameter of a circle that can loop inside the tracker [mm]:
    /// a particle through the beam line reaches twice its circle's radius,
    /// so one that turns back inside the tracker has a diameter below the
    /// outermost layer radius (mergeTracks takes it from the detector:
    /// CLICdet 1.5 m, pT < 0.9 GeV in 4 T).
    double maxLoopDiameter = 1500.0;
  };

  /// Throws std::invalid_argument for a non-positive or non-finite cut.
  TrackMerger(FinderState& state, Config config);

  /// Merges pairs of compatible live tracks, best merged fit first, in
  /// rounds until none is left; the absorbed track is marked dead (the
  /// caller compacts). Returns the number of merges.
  std::uint32_t run();

 private:
  /// A compatible pair: the merged hits and fits.
  struct Merge {
    double score = 0.0;
    std::uint32_t a = 0;
    std::uint32_t b = 0;
    TrackCandidate merged;
  };

  /// Tries to merge tracks a and b; fills `out` and returns true if they
  /// are compatible.
  bool tryMerge(std::uint32_t a, std::uint32_t b, TrackCandidate& out) const;
  /// Tries to merge `other` onto `ref`: other's hits tested against ref's
  /// circle and s-z line, then the union refitted.
  bool mergeOnto(const TrackCandidate& ref, const TrackCandidate& other,
                 TrackCandidate& out) const;
  /// A track's circle for the looper rule: the free circle of its hits,
  /// or of all but an end hit that lies further than
  /// Config::maxTurnDistance from the circle of the others (turnCircle).
  struct TurnCircle {
    TransverseCircle circle;
    bool skipsFront = false;  ///< the first hit is left out
    bool skipsBack = false;   ///< the last hit is left out
    /// The hits of `c` (the track it was made for) that it was fitted to.
    std::span<const ConfIndex> hitsOf(const TrackCandidate& c) const {
      return std::span<const ConfIndex>(c.hits).subspan(
          skipsFront ? 1 : 0,
          c.hits.size() - (skipsFront || skipsBack ? 1 : 0));
    }
  };
  /// The TurnCircle of track `c` (its conformal circle for a helix-step
  /// track, which has a free one already, and where no free fit exists).
  TurnCircle turnCircle(const TrackCandidate& c) const;
  /// The turn score of `turn` as a further half-turn of the helix of
  /// `first`, each with its TurnCircle (only the hits of the turn's circle
  /// are tested); nothing if it fails a gate or scores above
  /// Config::maxTurnScore.
  std::optional<double> furtherTurnScore(const TrackCandidate& first,
                                         const TurnCircle& firstFit,
                                         const TrackCandidate& turn,
                                         const TurnCircle& turnFit) const;
  /// Refits track `c` to `hits` (some of its own), circle and s-z line;
  /// leaves the track as it is if a fit fails.
  void refitTo(TrackCandidate& c, std::span<const ConfIndex> hits) const;
  /// Drops further half-turns (Config::dropTurns), joining the hits of
  /// those that score at most Config::maxJoinScore to their first
  /// half-turn's track; returns how many.
  std::uint32_t dropTurns();
  /// Turns beyond a track's last hit that the searches for hits on its
  /// further turns look (collectTurnHits, followTurns).
  static constexpr int kTurnSearchTurns = 3;
  /// The arc beyond the last hit of `track` (with its free `circle`) that
  /// those searches may cover: kTurnSearchTurns + 1 turns, and no further
  /// from its first hit than the chain's max_track_turns lets the
  /// extensions predict; nothing for a track that cannot loop (a circle
  /// wider than Config::maxLoopDiameter, or fewer than four hits, whose
  /// free circle is the conformal one) or has no arc left.
  std::optional<double> turnSearchReach(const TrackCandidate& track,
                                        const TransverseCircle& circle) const;
  /// Adds unused hits (`unused`, checked against FinderState::used) on
  /// further turns of the live tracks in `order` (with their TurnCircles
  /// by track index) to their turnHits (Config::maxTurnHitScore); returns
  /// how many.
  std::uint32_t collectTurnHits(std::span<const std::uint32_t> order,
                                std::span<const TurnCircle> circles,
                                const UnusedHits& unused);
  /// Follows each looping track in `order` hit by hit beyond its last
  /// hit over unused hits and its own turn hits, refitting circle and
  /// s-z line to its latest hits at each step; adds the unused hits it
  /// takes to turnHits. Returns how many.
  std::uint32_t followTurns(std::span<const std::uint32_t> order,
                            std::span<const TurnCircle> circles,
                            const UnusedHits& unused);
  /// True if hits of the two pieces share a sensor, or lie on one layer
  /// further apart than an overlap.
  bool conflict(std::span<const ConfIndex> a,
                std::span<const ConfIndex> b) const;

  FinderState& m_state;
  const ConformalHits& m_hits;
  Config m_config;
  /// Largest transverse radius of each track's hits (per round).
  std::vector<double> m_reach;
};

/// Runs the merger with the cuts of the chain (FinderConfig) and compacts
/// the tracks; counts the tracks it removed in stats.mergedTracks.
void mergeTracks(FinderState& state, StepStats& stats);

}  // namespace conftrack::detail
