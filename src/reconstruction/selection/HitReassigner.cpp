#include "conftrack/reconstruction/selection/HitReassigner.hpp"

#include "conftrack/reconstruction/fitting/HelixState.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <tuple>

namespace conftrack {

namespace {

bool positiveFinite(double x) { return x > 0.0 && std::isfinite(x); }

/// A track that can take a hit: fitted with a measurement to spare (so
/// with fitted hits at both ends), without further-turn hits (a looper's
/// turns are the finder's business).
bool eligible(const Track& t) {
  return t.fitted && t.ndf > 0 && t.outlier.size() == t.hits.size() &&
         t.numTurnHits() == 0;
}

/// Side of the grid cells of the offered hits [mm], and the step of the
/// walk along a track's helix (3-D path): every point within a cell of the
/// walk is searched.
constexpr double kCell = 50.0 * units::mm;

/// A hit and a track end whose prediction it passes.
struct Pair {
  HitIndex hit = 0;
  double chi2 = 0.0;
  std::uint32_t track = 0;
  bool last = false;
};

/// The point at transverse arc length s from the PCA of `state` (LCIO
/// parameters about its reference; Omega > 0 turns clockwise).
Vector3 helixPoint(const TrackState& state, double s) {
  const TrackVector& p = state.parameters;
  const double phi0 = p[ePhi0];
  const double omega = p[eOmega];
  const Vector3 pca =
      state.reference +
      Vector3(-p[eD0] * std::sin(phi0), p[eD0] * std::cos(phi0), p[eZ0]);
  const double phi = phi0 - omega * s;
  double dx = s * std::cos(phi0);
  double dy = s * std::sin(phi0);
  if (std::abs(omega * s) > 1e-9) {
    dx = (std::sin(phi0) - std::sin(phi)) / omega;
    dy = (std::cos(phi) - std::cos(phi0)) / omega;
  }
  return pca + Vector3(dx, dy, p[eTanLambda] * s);
}

/// Calls visit(point, unit direction) at steps of kCell along the helix of
/// `state`, from
/// its PCA forwards (`forward`) or backwards, over `length` of path (at
/// most half a turn).
template <typename Visit>
void walkHelix(const TrackState& state, bool forward, double length,
               Visit&& visit) {
  const double tanLambda = state.parameters[eTanLambda];
  const double stretch = std::sqrt(1.0 + tanLambda * tanLambda);
  const double omega = std::abs(state.parameters[eOmega]);
  double maxArc = length / stretch;
  if (omega > 0.0) {
    maxArc = std::min(maxArc, std::numbers::pi / omega);
  }
  const double step = kCell / stretch;
  const double sign = forward ? 1.0 : -1.0;
  const double phi0 = state.parameters[ePhi0];
  const double signedOmega = state.parameters[eOmega];
  for (double s = 0.0; s <= maxArc + 0.5 * step; s += step) {
    const double phi = phi0 - signedOmega * sign * s;
    const Vector3 direction =
        Vector3(std::cos(phi), std::sin(phi), tanLambda) / stretch;
    visit(helixPoint(state, sign * s), direction);
  }
}

/// The pair of hit h and the end (`last`) of `track` with state `state`, if
/// h lies beyond that end within the windows and its predicted chi2 passes.
std::optional<Pair> predictPair(const HitReassigner::Config& config,
                                std::span<const Hit> hits, const Track& track,
                                const TrackState& state, bool last,
                                HitIndex h) {
  const Hit& hit = hits[h];
  TrackVector moved;
  const double s =
      movePivot(state.parameters, state.reference, hit.position, 0.0, moved);
  // movePivot measures s from the state's PCA to the hit's, along the
  // motion; the hit must lie beyond the end.
  if (!std::isfinite(s) || (last ? s <= 0.0 : s >= 0.0) ||
      std::abs(moved[eD0]) > config.maxTransverse ||
      std::abs(moved[eZ0]) > config.maxLongitudinal) {
    return std::nullopt;
  }
  TrackJacobian jacobian;
  movePivot(state.parameters, state.reference, hit.position, s, moved,
            &jacobian);
  const TrackCovariance cov =
      jacobian * state.covariance * jacobian.transpose();
  const double phi = moved[ePhi0];
  const double tanLambda = moved[eTanLambda];
  const Vector3 normal(-std::sin(phi), std::cos(phi), 0.0);
  const Vector3 along(std::cos(phi), std::sin(phi), 0.0);
  auto hitVariance = [&](const Vector3& direction) {
    const double u = hit.sigmaU * hit.uAxis.dot(direction);
    const double v = hit.sigmaV * hit.vAxis.dot(direction);
    return u * u + v * v;
  };
  const double stretch2 = 1.0 + tanLambda * tanLambda;
  // The hit's error along the track moves the point of closest approach,
  // and so z there, by tanLambda per millimetre.
  const double hitT = hitVariance(normal);
  const double hitL = hitVariance(Vector3::UnitZ()) +
                      tanLambda * tanLambda * hitVariance(along);
  const double pt = std::max(track.ptEstimate, 0.05);
  const double path = std::abs(s) * std::sqrt(stretch2);
  const double scatter = config.scatteringPerMetre * (path / units::m) /
                         (pt * std::sqrt(stretch2));
  const double varT = cov(eD0, eD0) + hitT + scatter * scatter;
  const double varL = cov(eZ0, eZ0) + hitL + scatter * scatter * stretch2;
  const double chi2 =
      moved[eD0] * moved[eD0] / varT + moved[eZ0] * moved[eZ0] / varL;
  if (!(chi2 <= config.maxPredictedChi2)) {
    return std::nullopt;
  }
  Pair pair;
  pair.hit = h;
  pair.chi2 = chi2;
  pair.last = last;
  return pair;
}

/// Where hit pair.hit goes among track.hits: past the hits of that end
/// whose arc length from the end's state is beyond the hit's. The state is
/// the track's now: it may have taken a hit at that end since the pair was
/// found.
std::size_t insertionPoint(std::span<const Hit> hits, const Track& track,
                           const Pair& pair) {
  const TrackState& state = pair.last ? track.atLastHit : track.atFirstHit;
  auto arcOf = [&](HitIndex h) {
    TrackVector moved;
    return movePivot(state.parameters, state.reference, hits[h].position, 0.0,
                     moved);
  };
  const double arc = arcOf(pair.hit);
  std::size_t at = pair.last ? track.hits.size() : 0;
  if (pair.last) {
    while (at > 0 && arcOf(track.hits[at - 1]) > arc) {
      --at;
    }
  } else {
    while (at < track.hits.size() && arcOf(track.hits[at]) < arc) {
      ++at;
    }
  }
  return at;
}

constexpr std::uint32_t kNoTrack = std::numeric_limits<std::uint32_t>::max();

/// Rounds of the reassignment (a track followed again from the end it
/// reached).
constexpr int kMaxRounds = 3;

/// The hits on offer on a grid of cubes of side kCell over their bounding
/// box, stored by cell (compressed rows: one allocation, no hashing).
class HitGrid {
 public:
  HitGrid(std::span<const Hit> hits, const std::vector<std::uint8_t>& on) {
    bool any = false;
    for (HitIndex h = 0; h < hits.size(); ++h) {
      if (on[h] != 0) {
        for (int a = 0; a < 3; ++a) {
          const std::int64_t c = cellOf(hits[h].position[a]);
          m_low[a] = any ? std::min(m_low[a], c) : c;
          m_size[a] = any ? std::max(m_size[a], c) : c;  // the highest, first
        }
        any = true;
      }
    }
    if (!any) {
      m_size = {0, 0, 0};
      return;
    }
    for (int a = 0; a < 3; ++a) {
      m_size[a] = m_size[a] - m_low[a] + 1;
    }
    m_start.assign(
        static_cast<std::size_t>(m_size[0] * m_size[1] * m_size[2]) + 1, 0);
    for (HitIndex h = 0; h < hits.size(); ++h) {
      if (on[h] != 0) {
        ++m_start[flat(hits[h].position) + 1];
      }
    }
    for (std::size_t c = 1; c < m_start.size(); ++c) {
      m_start[c] += m_start[c - 1];
    }
    m_hits.resize(m_start.back());
    std::vector<std::uint32_t> fill(m_start.begin(), m_start.end() - 1);
    for (HitIndex h = 0; h < hits.size(); ++h) {
      if (on[h] != 0) {
        m_hits[fill[flat(hits[h].position)]++] = h;
      }
    }
  }

  /// Calls visit(hit) for the hits of the cells that reach within `reach`
  /// of `at` (a superset of the hits that close), in hit index order
  /// within a cell.
  template <typename Visit>
  void forEachNear(const Vector3& at, double reach, Visit&& visit) const {
    std::int64_t lo[3];
    std::int64_t hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::max<std::int64_t>(cellOf(at[a] - reach) - m_low[a], 0);
      hi[a] = std::min<std::int64_t>(cellOf(at[a] + reach) - m_low[a],
                                     m_size[a] - 1);
      if (lo[a] > hi[a]) {
        return;
      }
    }
    for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
      for (std::int64_t j = lo[1]; j <= hi[1]; ++j) {
        const std::size_t row =
            static_cast<std::size_t>((i * m_size[1] + j) * m_size[2]);
        const std::uint32_t begin = m_start[row + lo[2]];
        const std::uint32_t end = m_start[row + hi[2] + 1];
        for (std::uint32_t k = begin; k < end; ++k) {
          visit(m_hits[k]);
        }
      }
    }
  }

 private:
  static std::int64_t cellOf(double x) {
    return static_cast<std::int64_t>(std::floor(x / kCell));
  }
  std::size_t flat(const Vector3& p) const {
    return static_cast<std::size_t>(
        ((cellOf(p.x()) - m_low[0]) * m_size[1] + (cellOf(p.y()) - m_low[1])) *
            m_size[2] +
        (cellOf(p.z()) - m_low[2]));
  }

  std::array<std::int64_t, 3> m_low = {0, 0, 0};
  std::array<std::int64_t, 3> m_size = {0, 0, 0};
  /// Per cell (x slowest, z fastest) the first of its hits in m_hits.
  std::vector<std::uint32_t> m_start;
  std::vector<HitIndex> m_hits;
};

/// Every pair of an available hit and an end of a track marked in `walk`
/// whose prediction passes (predictPair), into `pairs` (cleared first):
/// from a walk along the track's helix beyond each of its ends.
void collectPairs(const HitReassigner::Config& config,
                  std::span<const Hit> hits, const std::vector<Track>& tracks,
                  const HitGrid& grid,
                  const std::vector<std::uint8_t>& available,
                  const std::vector<std::uint32_t>& holder,
                  const std::vector<std::uint8_t>& walk,
                  std::vector<Pair>& pairs) {
  pairs.clear();
  // A hit within the windows lies within `tube` of the path; it is
  // examined at the walk's point nearest to it along the path (kCell
  // apart; the windows' z offset moves a hit along a steep track too).
  const double tube = std::hypot(config.maxTransverse, config.maxLongitudinal);
  const double halfSlice = 0.5 * kCell + tube;
  const double reach = std::hypot(halfSlice, tube);
  // Each hit once per track end.
  std::vector<std::uint32_t> stamp(hits.size(), 0);
  std::uint32_t visit = 0;
  for (std::uint32_t t = 0; t < tracks.size(); ++t) {
    const Track& track = tracks[t];
    if (walk[t] == 0 || !eligible(track)) {
      continue;
    }
    for (const bool last : {false, true}) {
      const TrackState& state = last ? track.atLastHit : track.atFirstHit;
      ++visit;
      walkHelix(
          state, last, config.maxEndDistance,
          [&](const Vector3& at, const Vector3& direction) {
            grid.forEachNear(at, reach, [&](HitIndex h) {
              if (available[h] == 0 || stamp[h] == visit || holder[h] == t) {
                return;
              }
              const Vector3 offset = hits[h].position - at;
              const double along = offset.dot(direction);
              if (std::abs(along) > halfSlice ||
                  offset.squaredNorm() - along * along > tube * tube) {
                return;
              }
              stamp[h] = visit;
              if (std::optional<Pair> pair =
                      predictPair(config, hits, track, state, last, h)) {
                pair->track = t;
                pairs.push_back(*pair);
              }
            });
          });
    }
  }
}

}  // namespace

std::optional<HitReassigner::Problem> HitReassigner::findProblem(
    const Config& c) {
  if (!positiveFinite(c.maxEndDistance)) {
    return Problem{"max_end_distance_mm", "must be > 0 and finite"};
  }
  if (!positiveFinite(c.maxTransverse)) {
    return Problem{"max_transverse_mm", "must be > 0 and finite"};
  }
  if (!positiveFinite(c.maxLongitudinal)) {
    return Problem{"max_longitudinal_mm", "must be > 0 and finite"};
  }
  if (!positiveFinite(c.maxPredictedChi2)) {
    return Problem{"max_predicted_chi2", "must be > 0 and finite"};
  }
  if (!positiveFinite(c.scatteringPerMetre)) {
    return Problem{"scattering_mm_per_m_gev", "must be > 0 and finite"};
  }
  if (c.refitsPerHit < 1) {
    return Problem{"refits_per_hit", "must be at least 1"};
  }
  if (!positiveFinite(c.maxChi2Increase)) {
    return Problem{"max_chi2_increase", "must be > 0 and finite"};
  }
  return std::nullopt;
}

HitReassigner::HitReassigner(const KalmanFitter& fitter, const Config& config)
    : m_fitter(&fitter), m_config(config) {
  if (std::optional<Problem> p = findProblem(m_config)) {
    throw std::invalid_argument("HitReassigner: " + p->key + " " + p->what);
  }
}

HitReassigner::Result HitReassigner::run(std::span<const Hit> hits,
                                         std::vector<Track> tracks) const {
  Result result;
  if (!m_config.enabled) {
    result.tracks = std::move(tracks);
    return result;
  }
  // Who holds each hit (the first track in order) and how many do.
  std::vector<std::uint32_t> holder(hits.size(), kNoTrack);
  std::vector<std::uint8_t> holders(hits.size(), 0);
  for (std::uint32_t t = 0; t < tracks.size(); ++t) {
    for (HitIndex h : tracks[t].hits) {
      if (h >= hits.size()) {
        throw std::out_of_range("HitReassigner: hit index out of range");
      }
      if (holder[h] == kNoTrack) {
        holder[h] = t;
      }
      holders[h] = static_cast<std::uint8_t>(std::min(holders[h] + 1, 2));
    }
  }
  // The hits on offer: if asked, hits of no track, and the outliers of
  // fitted tracks that no other track holds (a hit that another track
  // fits is that track's).
  std::vector<std::uint8_t> available(hits.size(), 0);
  for (HitIndex h = 0; h < hits.size(); ++h) {
    available[h] = m_config.freeHits && holders[h] == 0 ? 1 : 0;
  }
  for (const Track& t : tracks) {
    if (t.fitted && t.outlier.size() == t.hits.size()) {
      for (std::size_t k = 0; k < t.hits.size(); ++k) {
        if (t.outlier[k] == kOutlierHit && holders[t.hits[k]] == 1) {
          available[t.hits[k]] = 1;
        }
      }
    }
  }
  const HitGrid grid(hits, available);
  // Rounds: a track that took a hit is followed again from its new end,
  // where the next layer's hit may lie beyond the first walk.
  std::vector<std::uint8_t> walk(tracks.size(), 1);
  std::vector<Pair> pairs;
  std::vector<HitIndex> refitHits;
  for (int round = 0; round < kMaxRounds; ++round) {
    collectPairs(m_config, hits, tracks, grid, available, holder, walk, pairs);
    std::fill(walk.begin(), walk.end(), 0);
    // Hits by id (not index: the result must not depend on the input hit
    // order), each hit's track ends best prediction first.
    std::sort(pairs.begin(), pairs.end(), [&](const Pair& a, const Pair& b) {
      return std::tie(hits[a.hit].id, a.chi2, a.track, a.last) <
             std::tie(hits[b.hit].id, b.chi2, b.track, b.last);
    });
    bool anyTaken = false;
    for (std::size_t first = 0; first < pairs.size();) {
      std::size_t end = first;
      while (end < pairs.size() && pairs[end].hit == pairs[first].hit) {
        ++end;
      }
      const HitIndex h = pairs[first].hit;
      const std::size_t tries = std::min(
          end - first, static_cast<std::size_t>(m_config.refitsPerHit));
      for (std::size_t c = first; c < first + tries; ++c) {
        const Pair& pair = pairs[c];
        Track& taker = tracks[pair.track];
        const std::size_t at = insertionPoint(hits, taker, pair);
        refitHits.assign(taker.hits.begin(), taker.hits.end());
        refitHits.insert(refitHits.begin() + static_cast<std::ptrdiff_t>(at),
                         h);
        ++result.refits;
        Track refit = m_fitter->fit(
            hits, FitInput{refitHits, false, taker.atIp.reference.head<2>()});
        if (!refit.fitted || refit.outlier[at] != kFittedHit ||
            refit.numOutliers() > taker.numOutliers() ||
            !(refit.chi2 - taker.chi2 <= m_config.maxChi2Increase)) {
          continue;
        }
        taker.hits = std::move(refit.hits);
        taker.outlier = std::move(refit.outlier);
        taker.takeFit(refit);
        if (holder[h] != kNoTrack) {
          // An outlier: its track used it in no fit, whose result stands.
          Track& from = tracks[holder[h]];
          const auto it = std::find(from.hits.begin(), from.hits.end(), h);
          from.outlier.erase(from.outlier.begin() + (it - from.hits.begin()));
          from.hits.erase(it);
          ++result.outliersMoved;
        } else {
          ++result.freeHitsAdded;
        }
        holder[h] = pair.track;
        available[h] = 0;
        walk[pair.track] = 1;
        anyTaken = true;
        break;
      }
      first = end;
    }
    if (!anyTaken) {
      break;
    }
  }
  result.tracks = std::move(tracks);
  return result;
}

}  // namespace conftrack
