#pragma once

/// @file FindingChain.hpp
/// The configurable chain of conformal-tracking steps (upstream.md 3, 12,
/// 13; conftrack's keys in docs/algorithm.md 2) and its TOML reader
/// (format: README "Chain files").

#include "conftrack/core/BeamLine.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/Detector.hpp"
#include "conftrack/reconstruction/finding/BeamSpotPrepass.hpp"
#include "conftrack/reconstruction/finding/VertexZPrepass.hpp"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace conftrack {

class ConfigTable;

/// Direction in which a step seeds and extends (upstream VertexToTracker).
enum class SearchDirection : std::uint8_t {
  eInsideOut,  ///< seed innermost, grow outwards (prompt tracks)
  eOutsideIn,  ///< seed outermost, grow inwards (displaced tracks)
};

/// The chi2 cut `cut` scaled for a candidate of transverse momentum `pt`
/// [GeV]: as (ptScale / pT)^2 below ptScale (0: no scaling). One formula
/// for the steps (FindingStep::chi2CutAt) and the extension and hole
/// filling units, which carry the two numbers in their own configurations.
inline double scaledChi2Cut(double cut, double ptScale, double pt) {
  if (ptScale > 0.0 && pt < ptScale) {
    double r = ptScale / std::max(pt, 1e-3);
    return cut * r * r;
  }
  return cut;
}

/// One step of the chain. Defaults are those of the CLICdet chain's first
/// step (upstream.md 13.1).
struct FindingStep {
  std::string name;
  /// Subdetector indices whose hits form the step's pool; empty: reuse the
  /// previous step's pool (upstream: no CombineCollections).
  std::vector<std::uint16_t> collections;
  /// Subdetector indices whose hits may seed a build (a subset of the
  /// pool's); empty: every pool hit seeds (as upstream).
  std::vector<std::uint16_t> seedCollections;
  /// Helix steps: subdetector indices whose unused hits an accepted track
  /// may take when it is followed inwards, against its motion, from its
  /// first hit (besides the pool's own); empty: no inward following. A
  /// step seeded in an outer subdetector reaches back into the inner one
  /// that its seeds leave out (docs/algorithm.md 3.8).
  std::vector<std::uint16_t> inwardCollections;
  /// Helix steps with inwardCollections: after the inward following, the
  /// helix is followed on past its closest approach to the beam line, back
  /// along the particle's incoming leg, and the hits found there are added
  /// if they are at least this many (0, the default: off). A particle
  /// produced off the beam line moving inwards crosses the inner layers
  /// before it turns; TrackML's files have no hits after the turn in the
  /// part of the tracker where it turned (docs/validation.md item 5), so
  /// its inner hits lie only on the incoming leg, which the inward
  /// following, ending at the closest approach, never reaches
  /// (docs/algorithm.md 3.8).
  std::uint32_t pastTurnMinHits = 0;
  /// Actions, run in this order when set.
  bool build = false;   ///< BuildNewTracks
  bool extend = false;  ///< ExtendTracks
  bool sort = false;    ///< SortTracks by pT, descending
  /// Helix-triplet building of displaced tracks (a conftrack addition,
  /// HelixTracks.cpp): seeds are triplets of hits with a free circle, not
  /// one through the beam line; requires maxSeedLength.
  bool helix = false;
  /// Maximum angle between consecutive cells in (u, v) [rad].
  double maxCellAngle = 0.005;
  /// Maximum longitudinal angle between consecutive cells [rad], taken in
  /// (s, z) with s the transverse arc length (upstream: chords in (z, R)).
  double maxCellAngleRZ = 0.005;
  /// Maximum chi2/ndf of a candidate (each of uv and sz), and maximum
  /// increase of chi2/ndf when an extension adds a hit.
  double chi2Cut = 100.0;
  /// pT scale of the chi2 cuts [GeV] (0: off, as upstream). Below it the
  /// cuts grow as (chi2PtScale / pT)^2, pT being the candidate's estimate:
  /// the fits know only the hit errors, and multiple-scattering residuals
  /// grow as 1/p, so with thin, precise layers a fixed cut either rejects
  /// low-pT tracks or admits everything at high pT.
  double chi2PtScale = 0.0;
  /// The chi2 cut for a candidate of transverse momentum `pt` [GeV].
  double chi2CutAt(double pt) const;
  /// Minimum number of hits of a built candidate.
  std::uint32_t minHits = 4;
  /// Seeding disc radius, maximum seed-cell length, scale of the cell
  /// extension window [1/mm] (the paper's "max cell length").
  double maxDistance = 0.02;
  /// Maximum |dz/dR| of a seed cell.
  double slopeZRange = 10.0;
  /// Maximum azimuth difference between the two hits of a seed cell [rad]
  /// (pi: no cut, as upstream). With radial search in the outer tracker
  /// the conformal disc holds every hit of the inner layers at any
  /// azimuth, so without this cut a seed pairs with nearly all hits.
  double maxSeedDeltaPhi = 3.14159265358979323846;
  /// Maximum |z| at R = 0 of the straight line through the two hits of a
  /// seed cell in (R, z) [mm] (infinity: no cut, as upstream). For prompt
  /// steps in a long barrel with a short luminous region: without it a
  /// seed pairs with the hits of the next layer at every z that the slope
  /// cut admits.
  double maxSeedZ0 = std::numeric_limits<double>::infinity();
  /// Half-width of the z0 window about the vertex regions of the event
  /// [mm] (infinity: no window, the default). When finite, the z of a seed
  /// cell's (R, z) line at R = 0 must lie within this of a region found by
  /// the chain's vertex pre-pass (FinderConfig::vertexPrepass, required)
  /// times the cell's lever arm R_inner / |dR| where that exceeds 1 (at
  /// most 10 times: the error of z0 is the error of the cell's slope times
  /// R_inner), in addition to maxSeedZ0; in an event where the pre-pass
  /// finds no region only maxSeedZ0 applies. So the prompt steps follow
  /// the luminous region of each event instead of a beam spot fixed in the
  /// chain (algorithm.md 3.16).
  double vertexWindow = std::numeric_limits<double>::infinity();
  /// With vertexWindow: seed about the vertex regions of a pre-pass over
  /// the hits that no track holds when the step starts, instead of the
  /// event's (algorithm.md 3.16). After a prompt build, the hits of the
  /// vertices it missed, small interactions far from the luminous
  /// region's centre, are nearly all that is left, and their triplets
  /// stand out of a background that the found tracks no longer feed.
  /// Later steps seed about the event's regions again.
  bool vertexPrepassFreeHits = false;
  /// Maximum 3-D distance between the two hits of a seed cell [mm]
  /// (infinity: no cut, as upstream). In the outer tracker the conformal
  /// disc reaches across the whole detector, so an outside-in seed pairs
  /// with hits many layers further in; a real track's first cell skips at
  /// most a layer or two.
  double maxSeedLength = std::numeric_limits<double>::infinity();
  /// Helix steps: two adjacent layers (no layer between them) further
  /// apart than maxSeedLength but at most this far [mm] still pair, a seed
  /// segment between them reaching maxSeedLength beyond their distance
  /// (0, the default: no such pairs). Without it the region past a gap
  /// wider than the seed length (TrackML's outer pixel disks, 200 mm
  /// apart) could not be seeded at all.
  double maxSeedGap = 0.0;
  /// Helix steps: two layers within maxSeedLength of each other pair over
  /// a seed segment up to this factor times their distance [1], where
  /// that is longer than maxSeedLength but at most
  /// maxSeedLengthPerGap (0, the default: maxSeedLength on every
  /// pair). A length limit is also a slope limit that tightens as the
  /// layers part: between barrel layers 100 mm apart, 200 mm seeds reach
  /// |dz/dr| = 1.7, between layers 140 mm apart only 1.0. With the factor
  /// the same polar angles pair on every layer pair whose scaled length
  /// stays within the bound (algorithm.md 3.8).
  double seedLengthPerGap = 0.0;
  /// With seedLengthPerGap: the longest scaled seed segment [mm]; pairs
  /// whose scaled length exceeds it keep maxSeedLength (the triplets of
  /// a seed grow with the square of its length).
  double maxSeedLengthPerGap = 0.0;
  /// At most this many seed cells per seed, to its nearest neighbours (in
  /// the conformal plane with radial search, in azimuth otherwise) that
  /// pass the seed-cell cuts (0: all, as upstream). The paper seeds cells
  /// "to the nearest neighbours"; a fixed window holds more of them the
  /// denser the event, so without a bound the cost per seed grows with the
  /// occupancy.
  std::uint32_t maxSeedCells = 0;
  /// At most this many paths are enumerated per seed in this step (0: only
  /// the finder's guard FinderConfig::maxPathsPerSeed); beyond it each
  /// remaining leaf cell of the seed contributes its straightest path. A
  /// speed setting where hits come in overlapping pairs (TrackML): not
  /// counted as a guard.
  std::uint32_t maxPaths = 0;
  /// This step's work budget in cells (build steps) or triplets (helix
  /// steps) per pool hit, replacing the finder's guard
  /// FinderConfig::maxCellsPerHit for this step (0: the finder's). A step
  /// whose seeding is looser than the others' (TrackML's LowPt: wide z
  /// windows about the vertex regions at sigma_z = 50 mm) may need more
  /// than the budget that bounds the others on dense events.
  std::uint32_t maxCellsPerHit = 0;
  /// Helix steps: minimum pT of a seed triplet's circle [GeV].
  double minPt = 0.0;
  /// Helix steps: maximum transverse distance of closest approach of a
  /// seed triplet's circle to the beam line [mm].
  double maxD0 = std::numeric_limits<double>::infinity();
  /// Helix steps: at most this many predicted layer crossings without a
  /// compatible hit between two hits of a track.
  std::uint32_t maxMissedLayers = 1;
  /// Helix steps: a candidate that reached minHits within maxMissedLayers
  /// is followed on, before it is accepted, allowing up to this many
  /// crossings without a hit between two hits (0 or at most
  /// maxMissedLayers: no continuation). Tight building keeps random
  /// triplets from growing into fakes; the continuation takes the hits
  /// that a track which is already real leaves beyond a gap.
  std::uint32_t continueMissedLayers = 0;
  /// Helix steps: the chi2 cut per added hit (2 dof) while a candidate is
  /// followed on (0: chi2Cut). Building keeps the tight cut, against random
  /// triplets; an accepted track's further hits scatter more than the cut
  /// allows at low momentum, where the hit errors are small against the
  /// scattering (the helix filter only knows the last layer's).
  double continueChi2Cut = 0.0;
  /// Helix steps: seeds whose best candidate has at least this many hits
  /// accept it in a first pass over the seeds; the other candidates (at
  /// least minHits) wait for a second pass, so that a short random helix
  /// met early cannot take a hit of a long track met later (0, the
  /// default, or at most minHits: one pass, each seed's candidate
  /// accepted at once).
  std::uint32_t firstPassMinHits = 0;
  /// Tracks of this step with fewer hits than this after the step's
  /// overlap search must hold an overlap pair (two hits on one layer, on
  /// neighbouring sensors) or are dropped and their hits freed (0, the
  /// default: off; otherwise above minHits, and the chain's overlap_hits
  /// on). With minHits = 3, a prompt build finds the particles that end
  /// after three layers (a hadronic interaction in the material): three
  /// hits and an overlap partner, where the pair confirms the crossing
  /// that a fourth layer would have (docs/algorithm.md 3.20).
  std::uint32_t overlapPairBelowHits = 0;
  /// Tracks with pT estimate above this get the per-layer extension [GeV].
  double highPtCut = 10.0;
  /// Straight-line (no quadratic term) candidate fit (upstream HighPTFit).
  bool straightLineFit = true;
  /// Candidate chi2 cut on sz only (upstream OnlyZSchi2cut).
  bool onlySzChi2Cut = false;
  /// Seed with a disc in (u, v) instead of an azimuth window.
  bool radialSearch = false;
  SearchDirection direction = SearchDirection::eInsideOut;
  /// Remove-one-hit-and-refit recovery of rejected candidates (paper 4.1.1;
  /// never run upstream).
  bool recovery = false;
  /// Fit tracks of this step backwards first (upstream KalmanFitBackward).
  bool fitBackward = false;
};

inline double FindingStep::chi2CutAt(double pt) const {
  return scaledChi2Cut(chi2Cut, chi2PtScale, pt);
}

/// What is wrong with a list of subdetector indices (a step's
/// collections, seed_collections, inward_collections, a pre-pass's
/// collections): an index the detector does not have, or one listed
/// twice; nothing if valid.
std::optional<std::string> subdetectorListProblem(
    const std::vector<std::uint16_t>& list, const Detector& detector);

/// Settings of the whole finder plus its steps.
struct FinderConfig {
  std::vector<FindingStep> steps;
  /// Azimuth window of non-radial seeding [rad] (upstream ThetaRange).
  double thetaRange = 0.05;
  /// Candidates sharing at least this many hits are clones.
  std::uint32_t cloneSharedHits = 2;
  // Combinatorics guards (docs/robustness.md). Each bounds one kind of
  // work that otherwise grows with the hit density, cuts by a deterministic
  // order (never by time), and is counted per step (StepStats::guards,
  // Guard). The defaults lie above what the shipped chains need on their
  // normal events (CLICdet with 30 BX, the real TrackML events), where no
  // guard bites; they bound the cost per seed, cell and window at ten
  // times those occupancies.

  /// At most this many paths are enumerated per seed (upstream
  /// TooManyTracks); the remaining leaf cells of the seed get only their
  /// straightest path.
  std::uint32_t maxPathsPerSeed = 2000;
  /// At most this many cells per seed; growth stops there.
  std::uint32_t maxCellsPerSeed = 2000;
  /// At most this many seed cells per seed hit, to its nearest neighbours
  /// (the order of the seed search). Applies after a step's own
  /// maxSeedCells (a physics setting, not counted). A fixed seed window
  /// holds more hits the denser the event.
  std::uint32_t maxSeedNeighbours = 256;
  /// At most this many children per cell, those nearest to the virtual
  /// hit on its prolongation (the order of the search).
  std::uint32_t maxCellNeighbours = 64;
  /// At most this many leaf cells (path ends) of one seed's automaton are
  /// evaluated, the longest first; beyond maxPathsPerSeed each is one
  /// path and fit, so without a bound a dense seed fits thousands.
  std::uint32_t maxLeavesPerSeed = 256;
  /// Helix steps: at most this many of a seed hit's triplets are followed,
  /// the straightest first. Applies after a step's own maxSeedCells (a
  /// physics setting, not counted). The triplets of a seed grow with the
  /// square of the hit density and each is followed through the tracker:
  /// five real TrackML events in one made the Helix step follow 625 per
  /// seed (153 s); on the single events no seed has more than 100.
  std::uint32_t maxTripletsPerSeed = 100;
  /// Work budget of a build step: once the automata of its seeds have held
  /// more cells than this times the step's hits (StepStats::cells over the
  /// pool size), the remaining seeds are skipped (counted). Seeds come
  /// innermost first (outermost first outside-in), so what is lost are the
  /// tracks that only the later seeds would start. The per-seed guards
  /// bound the work of one seed; this one bounds their number times that
  /// work, so that the cost of a build grows no faster than the hits even
  /// where the combinations per seed grow with the density.
  std::uint32_t maxCellsPerHit = 100;
  /// The work budget of `step`: its own FindingStep::maxCellsPerHit, or
  /// else maxCellsPerHit.
  std::uint32_t cellsPerHitOf(const FindingStep& step) const {
    return step.maxCellsPerHit > 0 ? step.maxCellsPerHit : maxCellsPerHit;
  }
  /// Extensions and hole filling: at most this many hits of one predicted
  /// layer crossing (its search window) are examined, those nearest (in
  /// 3-D) to the predicted crossing point.
  std::uint32_t maxWindowHits = 256;
  /// Memory bound of a build step's cell cache (cells and their children
  /// are computed once per step and shared by all seeds): when it holds
  /// more cells than this between two seeds, it is emptied and refilled on
  /// demand (counted: StepStats::cellCacheFlushes). Cells depend on their
  /// hits and the used flags, which change during a build only where the
  /// completion of a new track claims hits; cells made again after an
  /// emptying see those claims, so where the bound acts results can differ
  /// slightly from an unbounded cache's (never where no hit was claimed).
  /// About 100 bytes per cell.
  std::uint32_t maxCachedCells = 1000000;
  /// Half-width of the azimuth window around the predicted crossing on
  /// each layer during extension [rad].
  double extensionPhiWindow = 0.1;
  /// Layers of look-ahead when several hits of a layer are compatible
  /// with a track being extended (0: upstream's greedy choice).
  int extensionLookahead = 2;
  /// Extensions (outward and inward): a hit whose chi2 to the track (both
  /// projections, with the allowance for multiple scattering in the layer
  /// before it, as the candidates are ranked) exceeds this many times the
  /// track's chi2 per degree of freedom, and extensionHitChi2Floor, is no
  /// candidate (0: off). The chi2_cut of a step bounds the increase of
  /// chi2/ndf, which a long track meets even with one hit at thousands
  /// (TrackML: the hit of a neighbour where the particle crossed no
  /// module, after which the fit misses its own next hits). A conftrack
  /// addition (issue 15).
  double extensionHitChi2Ratio = 0.0;
  /// The smallest cut of extensionHitChi2Ratio: tracks that fit their hits
  /// well still take hits up to this chi2.
  double extensionHitChi2Floor = 100.0;
  /// Extensions (outward and inward): where the best hit of the nearest
  /// layer with candidates has a chi2 above this (as ranked, the scale of
  /// extensionHitChi2Floor), the layers beyond are searched too, and the
  /// track passes that layer by if their best hit's chi2 plus the charge
  /// of a missing hit (16) is lower (0: off, the nearest layer's hit is
  /// taken). The nearest layer is not always one the particle crossed:
  /// a track predicted at a disk's inner edge or a sensor's border takes
  /// a neighbour's or a noise hit there and misses its own hits further
  /// on. A conftrack addition (issue 15; docs/algorithm.md 3.4).
  double extensionSkipChi2 = 0.0;
  /// Extensions (outward and inward) rank a candidate hit's z against the
  /// (s, z) filter of the track's hits, which carries the multiple
  /// scattering of every layer crossed (the helix steps' filter,
  /// detail::filterPathSz), instead of the straight line fitted through
  /// all of them, whose slope is the mean over the whole track. Below a
  /// GeV the slope wanders from layer to layer, and 200 mm beyond the
  /// last hit the line can miss the track's own hit by 10-20 mm, a noise
  /// hit nearer the line winning (off by default; a conftrack addition,
  /// issue 15; docs/algorithm.md 3.4).
  bool extensionSzFilter = false;
  /// Extensions (outward and inward) rank a candidate's transverse residual
  /// with the multiple scattering of every layer the track crossed (the
  /// helix steps' HelixPredictionError: each kink moves the particle off
  /// the fitted circle by its angle times the distance, less what the
  /// later hits let the fit follow) instead of the last layer's only
  /// (off by default; a conftrack addition, issue 15; docs/algorithm.md
  /// 3.4).
  bool extensionUvScattering = false;
  /// Use upstream's hard-coded 4 T in the pT estimate (for comparisons
  /// only; wrong for CLD).
  bool legacyFourTesla = false;
  /// After the last step, fill every track's holes (layers of the chain's
  /// collections crossed between its first and last hit without a hit on
  /// the track) with compatible unused hits. A conftrack addition: an
  /// extension step searches only its own collections, so a layer it
  /// skipped (e.g. the outer sensor of a vertex double layer when the
  /// tracker step extends a vertex track) is otherwise never revisited.
  bool finalHoleFilling = true;
  /// After the last step, before the final hole filling, resolve the
  /// tracks' shared hits as the selection would (SharedHitResolution):
  /// best first, a track that shares cloneSharedHits hits with one kept
  /// track, or shares hits and has fewer than this many of its own, is
  /// dropped and its hits are released, so that the final hole filling and
  /// overlap search can give them to the kept tracks (0: off; chain key
  /// final_min_unique_hits). Match the selection's min_unique_hits. A
  /// conftrack addition (issue 15): on TrackML, short tracks through
  /// several real ones held the second hits of those tracks' overlaps,
  /// and the selection dropped them with those hits.
  std::uint32_t finalMinUniqueHits = 0;
  /// With finalMinUniqueHits: a conformal track that breaks the clone or
  /// ambiguity rule keeps the hits that no better track holds, if they are
  /// at least finalMinUniqueHits, instead of being dropped (finder key
  /// final_trim_shared_hits; off by default). Two particles' tracks that
  /// share a pair of hits (one took the other's on a disk) are no clones:
  /// the worse one loses those hits, not its own.
  bool finalTrimSharedHits = false;
  /// With finalMinUniqueHits: the same shared-hit resolution runs after
  /// every step too, not only after the last (finder key
  /// shared_hits_each_step; off by default). The tracks it drops held hits
  /// while the later steps ran: on TrackML 419 tracks of event 1001 before
  /// the helix step alone, whose particles those steps then missed
  /// (algorithm.md 3.13).
  bool sharedHitsEachStep = false;
  /// Extensions and hole filling allow for multiple scattering in the
  /// material of the layer before a candidate hit (Highland, with the
  /// track's momentum estimate) in its chi2 increments. A conftrack
  /// addition: upstream's conformal chi2 knows only the hit resolutions.
  bool scatteringAllowance = true;
  /// The same allowance for the inward completion of newly built tracks
  /// (InwardExtension), on its own key: the innermost layers are the
  /// thickest relative to the hit resolution, and a forward track's kink
  /// there moves the innermost hit in z by (1 + tan^2 lambda) times the
  /// deflection (chain key inward_scattering_allowance; the TrackML chain
  /// keeps it while switching scattering_allowance off).
  bool inwardScatteringAllowance = true;
  /// After the last step and the shared-hit resolution, before the final
  /// hole filling: every conformal track is followed outwards once more
  /// from its last hit over the hits no track holds, in all the chain's
  /// collections, with its step's cuts loosened (detail/EndExtension.hpp;
  /// chain key final_extension, off by default). A conftrack addition
  /// (issue 15): on TrackML the extensions stopped before a tenth of the
  /// found particles' weight, mostly where scattering or the solenoid's
  /// end bent the track more than their cuts allow; on CLICdet the same
  /// pass took other particles' hits (algorithm.md 3.23).
  bool finalExtension = false;
  /// Multiplier of the step's cell-angle cuts in that pass (chain key
  /// final_extension_angle_factor).
  double finalExtensionAngleFactor = 3.0;
  /// Half-width of its azimuth window around a predicted crossing [rad]
  /// (chain key final_extension_phi_window).
  double finalExtensionPhiWindow = 0.06;
  /// In a non-uniform field (a solenoid's, Detector::field()), map each
  /// hit to the conformal plane at the radius where a track from the beam
  /// line in the central field would cross its azimuth (PromptBending), and
  /// predict the extensions' layer crossings the same way, so that forward
  /// tracks stay straight lines there (chain key field_correction). No
  /// effect in a uniform field. A conftrack addition (issue 15).
  bool fieldCorrection = true;
  /// Transverse position of the beam line, x and y [mm] (chain keys
  /// beam_spot_x_mm, beam_spot_y_mm; reconstruct --beam-spot): the
  /// conformal map is taken about it (makeConformalHits), since a prompt
  /// track is a straight line in the conformal plane only if its circle
  /// passes through the map's origin. Within 10 mm of the detector axis.
  /// With beamSpotPrepass, the event's own beam line where it is measured.
  /// A conftrack addition: with the map about the axis, CLICdet tt̄
  /// events whose beams collide 0.5 mm off it had a CLICdp duplicate rate
  /// of 15 % instead of 0.7 % (docs/algorithm.md 3.24).
  double beamSpotX = 0.0;
  double beamSpotY = 0.0;
  /// After each step, tracks take the unused hits of the step's pool on
  /// other sensors of the layers they have hits on (overlapping sensors,
  /// detail/OverlapHits.hpp). A conftrack addition (issue 15): real layers
  /// give a particle two hits where sensors overlap.
  bool overlapHits = true;
  /// Largest chi2 (2 dof) of an overlap hit relative to the track's hit on
  /// the same layer (chain key overlap_max_chi2).
  double overlapMaxChi2 = 20.0;
  /// Largest transverse arc length between a track's hit and an overlap
  /// hit of the same layer [mm] (chain key overlap_max_arc_mm).
  double overlapMaxArc = 25.0 * units::mm;
  /// Largest distance of two sensors of one layer along its normal
  /// (radial on barrels, z on disks) [mm] (chain key overlap_max_gap_mm).
  double overlapMaxGap = 12.0 * units::mm;
  /// Largest arc length of a conformal track's predicted layer crossings
  /// from its first hit, in turns of its circle (0: no limit, the default).
  /// Where the data's simulation ends particles after half a turn (the
  /// TrackML files, ACTS's loop protection: docs/validation.md item 1), a
  /// crossing further on can only give another particle's hit, and a hit
  /// there placed at the wrong end of the track's (s, z) line spoils its
  /// fit (chain key max_track_turns). A conftrack addition (issue 15).
  double maxTrackTurns = 0.0;
  /// The vertex-z pre-pass, run once per event before the first step
  /// (unset: not run, the default). Its vertex regions are the seeds' z
  /// windows of the steps with a finite FindingStep::vertexWindow.
  std::optional<VertexZPrepass::Config> vertexPrepass;
  /// The beam-line pre-pass, run once per event before the vertex-z
  /// pre-pass (unset: not run, the default; chain table
  /// [beam_spot_prepass]). Where it measures the beam line, the conformal
  /// map is taken about it instead of beamSpotX, beamSpotY, which remain
  /// its start and fallback (algorithm.md 3.24).
  std::optional<BeamSpotPrepass::Config> beamSpotPrepass;
  /// After the final hole filling, join tracks that are pieces of one
  /// particle: compatible circles and s-z lines, no two hits on one sensor
  /// or far apart on one layer, a merged fit passing the pieces' chi2 cuts
  /// (detail/TrackMerging.hpp). A conftrack addition (issue 15, chain key
  /// track_merging).
  bool trackMerging = true;
  /// Largest azimuth difference of two pieces' circle centres seen from
  /// the origin [rad] (chain key merge_max_dphi).
  double mergeMaxDeltaPhi = 0.1;
  /// Largest transverse distance of a piece's hits from the other piece's
  /// circle [mm] (chain key merge_max_distance_mm).
  double mergeMaxDistance = 10.0 * units::mm;
  /// Largest z distance of a piece's hits from the other piece's s-z line
  /// [mm] (chain key merge_max_dz_mm).
  double mergeMaxDz = 20.0 * units::mm;
  /// Largest ratio of the merged fit's chi2/ndf to the pieces' own (each
  /// at least 1), in uv and in s-z (chain key merge_max_chi2_ratio).
  double mergeMaxChi2Ratio = 10.0;
  /// With trackMerging, also drop the tracks that are further half-turns
  /// of a better track's looper (TrackMerger::Config::dropTurns; chain key
  /// merge_drop_turns). Off where the data's particles end within half a
  /// turn (TrackML): no track can be a further turn there, and the search
  /// for them cost half of the merging (algorithm.md 3.17).
  bool mergeDropTurns = true;
};

/// A problem of a chain, named by the chain-file key it comes from, so that
/// the reader of a file can point at the line and a chain built in code
/// gets the same words.
struct ChainProblem {
  /// The step, or none for the [finder] settings and the chain as a whole.
  std::optional<std::size_t> step;
  /// The key: within the step's table for a step; "finder.<key>" for the
  /// [finder] settings; "step" for the chain as a whole.
  std::string key;
  std::string what;
  /// "key 'step[2].chi2_cut': what".
  std::string describe() const;
};

/// The one validation of a chain, whether read from a file or built in
/// code (ConformalTrackFinder's constructor runs it): subdetector indices
/// of the detector, listed once, seed collections among the step's
/// collections, a first step with collections, at least one action,
/// unique non-empty step names, every cut in its range (in native units)
/// and the helix action's required cuts. Returns the first problem, or
/// nothing if the chain is valid.
std::optional<ChainProblem> findChainProblem(const FinderConfig& config,
                                             const Detector& detector);

/// Reads and validates a chain file against a detector. Values are taken
/// in the units their keys name (`_mm`, `_GeV`; angles in rad, conformal
/// distances in 1/mm) and converted with Units.hpp. Throws InputError
/// "file:line: key 'step[2].x': problem" for unknown keys, subdetectors the
/// detector does not have and nonsense values (findChainProblem).
FinderConfig readChain(const std::filesystem::path& file,
                       const Detector& detector);
FinderConfig parseChain(std::string_view text, const std::string& sourceName,
                        const Detector& detector);
/// parseChain on a parsed chain file (its root table): one parse, read
/// against several detectors.
FinderConfig readChainTable(const ConfigTable& root, const Detector& detector);

/// Resolves a chain argument: a path, or a shipped chain name ("clicdet")
/// in the chains/ folder.
std::filesystem::path resolveChainPath(const std::string& nameOrPath);

}  // namespace conftrack
