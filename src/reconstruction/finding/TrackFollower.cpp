// Following a track hit by hit (detail/TrackFollower.hpp): the engine of
// ExtendTracks (upstream.md 10; paper 4.1.2) and of the inward completion.
//
// Upstream scans, for the low-pT pass, every hit of the step for every
// track (O(N_tracks x N_hits), upstream.md 14, item 11). Here every pass
// uses the track's current circle and s-z line to predict where it crosses
// each layer of the step (both crossings of a barrel layer, for loopers, in
// the catch-all pass) and examines only the hits in an azimuth window
// around each prediction. The acceptance criteria are upstream's: angle between
// the track direction and the new cell (FollowRules::angleFactor times the
// step's cuts), increases of chi2_uv/ndf and chi2_sz/ndf below the step's
// chi2 cut, no two hits on one sensor, and in the catch-all pass no hit on
// the other side in z; but the longitudinal angle is measured in the (s, z)
// plane, where the helix is straight, not between (z, R) chords, which
// curve below a few GeV. The chi2 increments are the exact ones of the
// track's fits, computed in O(1) per hit; when no hit of the next crossing
// passes, that crossing is tried again with an allowance for multiple
// scattering in the hit variances (FollowRules::scatteringAllowance). Of
// the layers with compatible hits, the one crossed first along the track is
// taken (ExtensionCuts::skipChi2: unless its best hit is poor and a later
// layer's is better by more than a missing hit's charge). Upstream takes
// the hit of lowest chi2_uv increase there; in dense jets that greedy
// choice swaps hits between particles a fraction of a mrad apart, because a
// vertex-detector track cannot predict its curvature well enough at the first
// tracker layer (only the next layers' lever arm tells them apart). So when
// several hits on that layer are compatible, each of the best few is scored by
// its chi2_uv + chi2_sz increase plus that of the best continuation on the
// following layers (a look-ahead of ExtensionCuts::lookahead layers), and the
// lowest total wins. These scores carry the scattering in the last layer in the
// hit variances (LayerCrossingSearch::scatter), which the cuts leave out:
// without it the hit nearest in (u, v) wins even where z, measured far less
// precisely on strips, rules it out. The hits examined per predicted crossing
// are bounded (ExtensionCuts::maxWindowHits, counted; the nearest to the
// predicted point are kept), so that the cost per track does not grow without
// bound with the hit density. With ExtensionCuts::szFilter the z part of that
// ranking is taken against the (s, z) filter of the chain's hits run towards
// its end (filterPathSz, each crossed layer's scattering in the slope's
// variance) instead of the straight line through all of them: at low momentum
// the slope wanders, and far beyond the end the line misses the track's own
// hit by more than a noise hit near it. With ExtensionCuts::uvScattering the
// (u, v) part carries the scattering of every layer the chain crossed
// (HelixPredictionError, as the helix steps), not only the last one's.

#include "conftrack/reconstruction/finding/detail/TrackFollower.hpp"

#include "conftrack/core/Units.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace conftrack::detail {

namespace {

/// The scattering allowance applies to hits on the nearest predicted layer
/// crossing, or at most this much further (the second sensor of a double
/// layer) [mm]: a track whose particle ended must not pick up a hit layers
/// away with an allowance that grows with the distance.
constexpr double kScatterReach = 5.0;
/// Extra half-angle of the (z, R) search cone around a predicted crossing,
/// for hits away from the predicted point [rad].
constexpr double kConeMargin = 0.01;
/// chi2 charged for a predicted layer crossing without a compatible hit in
/// the look-ahead (a missing hit costs about a 4 sigma deviation).
constexpr double kMissingHitChi2 = 16.0;
/// At most this many hits of one layer are followed in the look-ahead.
constexpr std::size_t kLookaheadBranches = 3;
/// Largest look-ahead depth (that of the chain validation): the work grows
/// as kLookaheadBranches^depth per added hit.
constexpr int kMaxLookahead = 5;
/// pT floor of the (s, z) filter's scattering (ExtensionCuts::szFilter):
/// the conformal fit of a short track can give any pT, and no track the
/// extensions follow is below this.
constexpr double kFilterMinPt = 0.1 * units::GeV;

/// One run of followTrack: the rules bound to the event.
class Follower {
 public:
  Follower(FinderState& state, const HitPool& pool, StepStats& stats,
           const ExtensionCuts& cuts, const FollowRules& rules,
           FollowWorkspace& work)
      : m_state(state),
        m_hits(state.hits),
        m_search(state, pool, stats, cuts.maxWindowHits, work.crossing),
        m_cuts(cuts),
        m_rules(rules),
        m_inward(rules.direction == Direction::eInward),
        m_work(work) {}

  void run(std::uint32_t t, StepStats& stats);

 private:
  /// Arc length of the end being followed (0 for the first hit).
  double endArc(const Chain& chain) const {
    return m_inward ? 0.0 : chain.sz.lastS;
  }

  /// Adds h at the end being followed.
  void attach(Chain& chain, ConfIndex h) const {
    if (m_inward) {
      chain.hits.insert(chain.hits.begin(), h);
    } else {
      chain.hits.push_back(h);
    }
  }

  /// Best total chi2 increase of the next `depth` layers after adding h.
  double lookahead(const Chain& chain, ConfIndex h, int depth);

  /// Compatible hits on the first layer crossed after the chain's end hit,
  /// best (lowest chi2 increase) first. `excluded` is a tentative hit of
  /// the look-ahead; crossings no further than `beyond` from the end hit
  /// are passed by (ExtensionCuts::skipChi2). Returns whether any crossing
  /// was predicted at all.
  /// Hits compatible within the hit resolutions are preferred; only when
  /// there are none are the chi2 increments recomputed with the allowance
  /// for multiple scattering. In dense jets the allowance alone let low-pT
  /// tracks take hits of neighbours a fraction of a mm away.
  bool collect(const Chain& chain, std::vector<Candidate>& out,
               ConfIndex excluded = kInvalidIndex, double beyond = -1.0);

  /// collect, without (`allowanceReach` null) or with the scattering
  /// allowance in the chi2 increments; with it, only crossings up to that
  /// distance from the end are searched. `nearest` receives the distance
  /// of the nearest predicted crossing.
  bool collectWith(const Chain& chain, std::vector<Candidate>& out,
                   ConfIndex excluded, const double* allowanceReach,
                   double* nearest, double beyond);

  /// What the ranking of one search knows of the chain beyond its fits
  /// (ExtensionCuts::szFilter, uvScattering).
  struct RankingModel {
    /// The (s, z) filter of the chain's hits run towards the end being
    /// followed (its slope and arc lengths in the direction of the
    /// search).
    bool szFilter = false;
    SzState filter;
    /// The transverse scattering of every layer the chain crossed
    /// (FollowWorkspace::uvError).
    bool uvScattering = false;
    /// The end's arc length in the chain's frame.
    double sEnd = 0.0;
    /// Arc length from the end to s, along the search.
    double along(double s, bool inward) const {
      return inward ? sEnd - s : s - sEnd;
    }
  };

  /// The ranking model of a chain of three or more hits (both parts off
  /// otherwise, or where the cuts leave them off).
  RankingModel rankingModel(const Chain& chain);

  FinderState& m_state;
  const ConformalHits& m_hits;
  LayerCrossingSearch m_search;
  const ExtensionCuts& m_cuts;
  const FollowRules& m_rules;
  bool m_inward;
  FollowWorkspace& m_work;
};

void Follower::run(std::uint32_t t, StepStats& stats) {
  TrackCandidate& track = m_state.tracks[t];
  if (m_work.levels.size() < static_cast<std::size_t>(m_cuts.lookahead) + 1) {
    m_work.levels.resize(static_cast<std::size_t>(m_cuts.lookahead) + 1);
  }
  Chain& chain = m_work.chain;
  if (!m_search.begin(track, chain)) {
    return;
  }
  bool added = false;
  std::vector<Candidate>& cands = m_work.candidates;
  while (true) {
    collect(chain, cands);
    if (cands.empty()) {
      break;
    }
    std::size_t choice = 0;
    if (cands.size() > 1 && m_cuts.lookahead > 0) {
      double best = std::numeric_limits<double>::infinity();
      std::size_t n = std::min(cands.size(), kLookaheadBranches);
      for (std::size_t k = 0; k < n; ++k) {
        double score =
            cands[k].chi2 + lookahead(chain, cands[k].hit, m_cuts.lookahead);
        if (score < best) {
          best = score;
          choice = k;
        }
      }
    }
    ConfIndex h = cands[choice].hit;
    if (m_cuts.skipChi2 > 0.0 && cands[choice].chi2 > m_cuts.skipChi2) {
      // A poor hit on the nearest layer: pass the layer by if the layers
      // beyond have a hit better by more than a missing hit's charge.
      std::vector<Candidate>& later = m_work.later;
      collect(chain, later, kInvalidIndex,
              std::abs(cands[choice].s - endArc(chain)));
      if (!later.empty() &&
          later.front().chi2 + kMissingHitChi2 < cands[choice].chi2) {
        h = later.front().hit;
      }
    }
    attach(chain, h);
    claimHit(m_state, stats, h, t);
    added = true;
    if (!m_search.refit(chain, &chain.uv)) {
      if (m_inward) {
        chain.hits.erase(chain.hits.begin());
      } else {
        chain.hits.pop_back();
      }
      break;
    }
  }
  if (added) {
    storeChain(m_state, chain, track);
  }
}

double Follower::lookahead(const Chain& chain, ConfIndex h, int depth) {
  // Each depth has its own level: the recursion goes to depth - 1 only.
  FollowWorkspace::Level& level =
      m_work.levels[static_cast<std::size_t>(depth)];
  Chain& next = level.chain;
  next.hits = chain.hits;
  next.quadratic = chain.quadratic;
  attach(next, h);
  if (!m_search.refit(next, &chain.uv)) {
    return kMissingHitChi2 * depth;
  }
  std::vector<Candidate>& cands = level.candidates;
  bool predicted = collect(next, cands, h);
  if (cands.empty()) {
    return predicted ? kMissingHitChi2 : 0.0;
  }
  if (depth <= 1) {
    return cands.front().chi2;
  }
  double best = std::numeric_limits<double>::infinity();
  std::size_t n = std::min(cands.size(), kLookaheadBranches);
  for (std::size_t k = 0; k < n; ++k) {
    best = std::min(best,
                    cands[k].chi2 + lookahead(next, cands[k].hit, depth - 1));
  }
  return best;
}

Follower::RankingModel Follower::rankingModel(const Chain& chain) {
  RankingModel model;
  const std::size_t n = chain.hits.size();
  if (!(m_cuts.szFilter || m_cuts.uvScattering) || n < 3) {
    return model;
  }
  // Arc lengths in the chain's frame, each unwrapped against the previous
  // hit (the extensions follow at most half a turn).
  std::vector<double>& arcs = m_work.filterArcs;
  arcs.resize(n);
  arcs[0] = 0.0;
  for (std::size_t k = 1; k < n; ++k) {
    arcs[k] = chain.arc.hitArcLength(m_hits, chain.hits[k], arcs[k - 1]);
  }
  // Inwards the models run from the last hit to the first, s and the
  // slope reversed.
  HelixPath& path = m_work.filterPath;
  path.hits.resize(n);
  path.s.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t j = m_inward ? n - 1 - k : k;
    path.hits[k] = chain.hits[j];
    path.s[k] = m_inward ? -arcs[j] : arcs[j];
  }
  path.t = m_inward ? -chain.sz.tanLambda : chain.sz.tanLambda;
  model.sEnd = m_inward ? arcs[0] : arcs[n - 1];
  const double pt = chain.uv.pt(m_state.bzForPt);
  const std::vector<SensitiveLayer>& layers = m_state.detector.layers();
  if (m_cuts.szFilter) {
    model.filter = filterPathSz(m_hits, path, layers, kFilterMinPt, pt);
    model.szFilter = true;
  }
  if (m_cuts.uvScattering) {
    // As the helix steps take them (HelixFollower::nextCrossing).
    predictionErrorInputs(m_hits, layers, path.hits, kFilterMinPt, pt,
                          chain.sz.tanLambda, m_work.uvSigma, m_work.uvKink);
    model.uvScattering =
        m_work.uvError.reset(path.s, m_work.uvSigma, m_work.uvKink);
  }
  return model;
}

bool Follower::collect(const Chain& chain, std::vector<Candidate>& out,
                       ConfIndex excluded, double beyond) {
  double nearest = std::numeric_limits<double>::infinity();
  bool predicted = collectWith(chain, out, excluded, nullptr, &nearest, beyond);
  if (out.empty() && predicted && m_rules.scatteringAllowance) {
    const double reach = nearest + kScatterReach;
    collectWith(chain, out, excluded, &reach, nullptr, beyond);
  }
  return predicted;
}

bool Follower::collectWith(const Chain& chain, std::vector<Candidate>& out,
                           ConfIndex excluded, const double* allowanceReach,
                           double* nearest, double beyond) {
  out.clear();
  const bool allowance = allowanceReach != nullptr;
  // The end of the chain being extended.
  const std::size_t n = chain.hits.size();
  const ConfIndex last = m_inward ? chain.hits[0] : chain.hits[n - 1];
  const ConformalFitResult& uv = chain.uv;
  const SzFitResult& sz = chain.sz;
  const double factor = m_rules.angleFactor;
  // Track direction at that hit from the fitted curve (more precise than
  // the chord of the last two hits), reversed when going inwards.
  double xl = uv.cosA * m_hits.u[last] + uv.sinA * m_hits.v[last];
  double slope = uv.params(1) + 2.0 * uv.params(2) * xl;
  double norm = (m_inward ? -1.0 : 1.0) * norm2(1.0, slope);
  double tu = (uv.cosA - uv.sinA * slope) / norm;
  double tv = (uv.sinA + uv.cosA * slope) / norm;
  // The longitudinal angle cut is taken in the (s, z) plane, where the
  // helix is a straight line, against the fitted s-z direction. Upstream
  // compares chords in (z, R); below a few GeV the track curves in that
  // plane (R grows slower than s), and at the outer tracker layers a 1 GeV
  // track's consecutive chords differ by more than 3 x 0.05 rad.
  const double szNorm = (m_inward ? -1.0 : 1.0) * norm2(1.0, sz.tanLambda);
  const double ts = 1.0 / szNorm;
  const double tz = sz.tanLambda / szNorm;
  const double rzCut = factor * m_cuts.maxCellAngleRZ;
  const double sLast = endArc(chain);
  const double chi2Cut = m_cuts.chi2CutAt(uv.pt(m_state.bzForPt));
  const double maxHitChi2 = m_cuts.maxHitChi2(uv, sz);
  bool predicted = false;
  // Arc length of the nearest layer with compatible hits so far, as a
  // distance from the end being extended.
  double firstS = std::numeric_limits<double>::infinity();
  const SearchStart from =
      m_search.start(chain.arc, sz, sLast, m_rules.direction);
  // The ranking model, made when the first hit passes the cuts: on real
  // TrackML event 1001, 27,000 of the 78,000 searches that would make one.
  RankingModel model;
  bool modelMade = allowance;
  for (std::uint32_t layer : m_search.pool().layers()) {
    const std::vector<Prediction>& predictions =
        m_search.predict(layer, from, m_rules.branches);
    predicted = predicted || !predictions.empty();
    for (const Prediction& p : predictions) {
      double dist = std::abs(p.s - sLast);
      if (dist <= beyond + 1e-6) {
        continue;
      }
      // (A crossing of the end hit's own layer right at the hit is not
      // the next layer.)
      if (nearest != nullptr && layer != m_hits.layer[last]) {
        *nearest = std::min(*nearest, dist);
      }
      if (dist > firstS + 1e-6 || (allowance && dist > *allowanceReach)) {
        continue;  // a later layer than one that already has hits
      }
      // Only the layer bins near the predicted crossing are searched: a
      // (z, R) cone from the last hit towards it. An (s, z) angle a
      // there spans a (z, R) angle a (1 + t^2) c / (c^2 + t^2), with
      // t = dz/ds and c = dR/ds of the chord (on barrels and disks
      // alike); the cone gets half as much again, plus a margin for
      // hits away from the predicted point.
      const Vector2 at = chain.arc.pointAt(p.s);
      const double coneDz = sz.z0 + sz.tanLambda * p.s - m_hits.z[last];
      const double coneDr = at.norm() - m_hits.radius[last];
      const double coneNorm = norm2(coneDz, coneDr);
      const double chordS = std::abs(p.s - sLast);
      const double c = chordS > 0.0 ? std::abs(coneDr) / chordS : 1.0;
      const double t2 = sz.tanLambda * sz.tanLambda;
      const double spread = c > 0.0 ? (1.0 + t2) * c / (c * c + t2) : 1.5;
      const HitPool::RzCone rzCone{
          m_hits.z[last], m_hits.radius[last], coneDz / coneNorm,
          coneDr / coneNorm, std::min(1.5, 1.5 * rzCut * spread + kConeMargin)};
      const std::vector<ConfIndex>& window = m_search.coneWindow(
          layer, p.phi, m_cuts.phiWindow, coneNorm > 0.0 ? &rzCone : nullptr,
          Vector3(at.x(), at.y(), sz.z0 + sz.tanLambda * p.s));
      for (ConfIndex h : window) {
        if (h == excluded || m_state.used[h] != 0 ||
            m_search.onSensorOf(chain.hits, h)) {
          continue;
        }
        if (m_rules.sameZSide && (m_hits.z[h] > 0) != (m_hits.z[last] > 0)) {
          continue;
        }
        if (m_rules.radiusOrdered &&
            (m_inward ? m_hits.radius[h] >= m_hits.radius[last]
                      : m_hits.radius[h] <= m_hits.radius[last])) {
          continue;
        }
        double du = m_hits.u[h] - m_hits.u[last];
        double dv = m_hits.v[h] - m_hits.v[last];
        double l = std::sqrt(du * du + dv * dv);
        if (!(l > 0.0) || angleBetween(tu, tv, du / l, dv / l) >
                              factor * m_cuts.maxCellAngle) {
          continue;
        }
        double s = chain.arc.hitArcLength(m_hits, h, p.s);
        if (m_inward ? !(s < sLast) : !(s > sLast)) {
          continue;
        }
        double ds = s - sLast;
        double dz = m_hits.z[h] - m_hits.z[last];
        double lsz = std::sqrt(ds * ds + dz * dz);
        if (!(lsz > 0.0) || angleBetween(ts, tz, ds / lsz, dz / lsz) > rzCut) {
          continue;
        }
        const Scatter ms =
            allowance ? m_search.scatter(uv, sz, last, h, ds) : Scatter{};
        double dUv = uv.deltaChi2(m_hits, h, ms.uv);
        double dSz = sz.deltaChi2(s, m_hits.z[h], m_hits.varZ[h] + ms.z,
                                  m_hits.varRxy[h]);
        if (LayerCrossingSearch::increase(uv.chi2, uv.ndf, dUv) > chi2Cut ||
            LayerCrossingSearch::increase(sz.chi2, sz.ndf, dSz) > chi2Cut) {
          continue;
        }
        // Candidates are ranked with the scattering in the last layer in
        // their variances even where the cut above leaves it out: below a
        // few GeV it moves the track by more than the hits' errors, so
        // without it the hit nearest in (u, v) wins however far it lies
        // in z (TrackML long strips: a noise hit 0.2 mm beside the track's
        // own and 15 mm off in z, 5 sigma).
        double rankUv = dUv;
        double rankSz = dSz;
        if (!allowance) {
          const Scatter rank = m_search.scatter(uv, sz, last, h, ds);
          rankUv = uv.deltaChi2(m_hits, h, rank.uv);
          rankSz = sz.deltaChi2(s, m_hits.z[h], m_hits.varZ[h] + rank.z,
                                m_hits.varRxy[h]);
          if (!modelMade) {
            model = rankingModel(chain);
            modelMade = true;
          }
          const double along = model.along(s, m_inward);
          if (model.uvScattering) {
            // Every crossed layer's kink, moved into the conformal plane
            // (a distance d there is d / R^2).
            const double r2 = m_hits.radius[h] * m_hits.radius[h];
            rankUv = uv.deltaChi2(
                m_hits, h,
                m_work.uvError.scatteringVariance(along) / (r2 * r2));
          }
          if (model.szFilter) {
            // The filter's prediction a distance ds along the search, with
            // the last layer's scattering as above.
            const SzState& f = model.filter;
            const double dz = m_hits.z[h] - f.zAt(along);
            const double variance = f.varAt(along) + rank.z + m_hits.varZ[h] +
                                    f.t * f.t * m_hits.varRxy[h];
            rankSz = dz * dz / variance;
          }
        }
        // A hit far beyond the track's own fit quality is another
        // particle's, however little it raises chi2/ndf of a long track;
        // refused, it leaves the next layer to be searched.
        if (rankUv + rankSz > maxHitChi2) {
          continue;
        }
        if (dist < firstS - 1e-6) {
          firstS = dist;
          out.clear();
        }
        out.push_back({h, p.s, rankUv + rankSz, dUv});
      }
    }
  }
  std::sort(out.begin(), out.end(), [](const Candidate& a, const Candidate& b) {
    return a.chi2 != b.chi2 ? a.chi2 < b.chi2 : a.hit < b.hit;
  });
  return predicted;
}

}  // namespace

ExtensionCuts ExtensionCuts::fromStep(const FindingStep& step,
                                      const FinderConfig& finder) {
  ExtensionCuts c;
  c.maxCellAngle = step.maxCellAngle;
  c.maxCellAngleRZ = step.maxCellAngleRZ;
  c.chi2Cut = step.chi2Cut;
  c.chi2PtScale = step.chi2PtScale;
  c.phiWindow = finder.extensionPhiWindow;
  c.maxWindowHits = finder.maxWindowHits;
  c.lookahead = finder.extensionLookahead;
  c.hitChi2Ratio = finder.extensionHitChi2Ratio;
  c.hitChi2Floor = finder.extensionHitChi2Floor;
  c.skipChi2 = finder.extensionSkipChi2;
  c.szFilter = finder.extensionSzFilter;
  c.uvScattering = finder.extensionUvScattering;
  return c;
}

double ExtensionCuts::maxHitChi2(const ConformalFitResult& uv,
                                 const SzFitResult& sz) const {
  if (!(hitChi2Ratio > 0.0)) {
    return std::numeric_limits<double>::infinity();
  }
  const int ndf = uv.ndf + sz.ndf;
  const double perDof = ndf > 0 ? (uv.chi2 + sz.chi2) / ndf : 0.0;
  return std::max(hitChi2Floor, hitChi2Ratio * perDof);
}

void ExtensionCuts::validate(std::string_view unit,
                             std::string_view phiWindowKey) const {
  // NaN fails every comparison, so each check is written to pass only
  // for good values.
  if (!(maxCellAngle > 0.0 && maxCellAngle <= kMaxSearchAngle)) {
    throwBadKey(unit, "max_cell_angle", "must be in (0, 3.14159] rad",
                maxCellAngle);
  }
  if (!(maxCellAngleRZ > 0.0 && maxCellAngleRZ <= kMaxSearchAngle)) {
    throwBadKey(unit, "max_cell_angle_rz", "must be in (0, 3.14159] rad",
                maxCellAngleRZ);
  }
  if (!(chi2Cut > 0.0 && std::isfinite(chi2Cut))) {
    throwBadKey(unit, "chi2_cut", "must be positive and finite", chi2Cut);
  }
  if (!(chi2PtScale >= 0.0 && std::isfinite(chi2PtScale))) {
    throwBadKey(unit, "chi2_cut_pt_scale_GeV", "must be >= 0 and finite",
                chi2PtScale);
  }
  if (!(phiWindow > 0.0 && phiWindow <= kMaxSearchAngle)) {
    throwBadKey(unit, phiWindowKey, "must be in (0, 3.14159] rad", phiWindow);
  }
  if (maxWindowHits < 1) {
    throwBadKey(unit, "max_window_hits", "must be at least 1",
                static_cast<double>(maxWindowHits));
  }
  if (!(hitChi2Ratio >= 0.0 && hitChi2Ratio <= 1e6)) {
    throwBadKey(unit, "extension_hit_chi2_ratio", "must be in [0, 1e6]",
                hitChi2Ratio);
  }
  if (!(hitChi2Floor > 0.0 && hitChi2Floor <= 1e6)) {
    throwBadKey(unit, "extension_hit_chi2_floor", "must be in (0, 1e6]",
                hitChi2Floor);
  }
  if (!(skipChi2 >= 0.0 && skipChi2 <= 1e6)) {
    throwBadKey(unit, "extension_skip_chi2", "must be in [0, 1e6]", skipChi2);
  }
  if (lookahead < 0 || lookahead > kMaxLookahead) {
    throwBadKey(unit, "extension_lookahead", "must be in [0, 5]",
                static_cast<double>(lookahead));
  }
}

void followTrack(FinderState& state, const HitPool& pool, StepStats& stats,
                 std::uint32_t t, const ExtensionCuts& cuts,
                 const FollowRules& rules, FollowWorkspace& work) {
  Follower(state, pool, stats, cuts, rules, work).run(t, stats);
}

}  // namespace conftrack::detail
