#pragma once

/// @file VertexZPrepass.hpp
/// Fast vertex-z pre-pass of the conformal finder (algorithm.md 3.16): finds
/// the z of the interaction vertices of an event from triplets of hits on
/// the three innermost barrel layers, before any track is built, so that
/// prompt steps seed around the vertices (FindingStep::vertexWindow) instead
/// of around a beam spot fixed in the chain. Truth is never used.

#include "conftrack/geometry/Detector.hpp"
#include "conftrack/reconstruction/finding/ConformalHits.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace conftrack {

/// Sorted, disjoint z intervals (the union of the vertices' windows).
class ZWindows {
 public:
  ZWindows() = default;
  /// The union of [lo - grow, hi + grow] over `intervals` (any order,
  /// lo <= hi); grow >= 0.
  ZWindows(const std::vector<std::pair<double, double>>& intervals,
           double grow);
  /// True if no interval is held (no vertex).
  bool empty() const { return m_lo.empty(); }
  std::size_t size() const { return m_lo.size(); }
  /// True if z lies in one of the intervals (closed).
  bool contains(double z) const { return near(z, 0.0); }
  /// True if z lies within `margin` (>= 0) of one of the intervals.
  bool near(double z, double margin) const;
  /// Lowest and highest z covered (empty(): undefined).
  double lowest() const { return m_lo.front(); }
  double highest() const { return m_hi.back(); }
  /// Total length covered [mm].
  double length() const;

 private:
  std::vector<double> m_lo;  ///< interval starts, ascending
  std::vector<double> m_hi;  ///< interval ends (m_hi[i] < m_lo[i + 1])
};

/// The vertex-z pre-pass.
///
/// Hits of the three innermost barrel layers of `collections` are combined
/// into triplets compatible with a prompt track: a pair on the first two
/// layers within `maxDeltaPhi` in azimuth, whose straight line in (R, z)
/// meets R = 0 within `maxAbsZ`, confirmed by a hit on the third layer
/// within `confirmPhi` of the azimuth extrapolated linearly in R (a circle
/// through the origin) and within `confirmZ` of the (R, z) line. The z0 of
/// each triplet (its pair's line at R = 0) is histogrammed. Random
/// triplets are counted the same way with the outer two hits taken from
/// the opposite azimuth (phi + pi), which cannot hold a track but has the
/// same combinatorics; their histogram is the background, subtracted bin
/// by bin. A bin is active if the excess summed over `2 * smoothBins + 1`
/// bins about it is at least `minExcess` triplets and `minSignificance`
/// standard deviations of the two counts. The runs of active bins are the
/// vertex regions, which the seeding widens by each step's window
/// (ZWindows): around an isolated vertex a region is a few bins wide,
/// where vertices are closer than the smoothing (200 pile-up interactions
/// with sigma_z = 5.5 mm) it covers them all, so that no vertex is lost
/// for lack of a resolved peak. The vertices are the local maxima of the
/// summed excess among the active bins, at the centroid of the excess in
/// their window (reported; the seeding uses the regions).
///
/// Hits are visited in ConformalHits order and counted in integers, so the
/// result depends neither on the input order nor on threads.
class VertexZPrepass {
 public:
  struct Config {
    /// Subdetectors whose three innermost barrel layers (by radius) are
    /// used; there must be at least three.
    std::vector<std::uint16_t> collections;
    /// Histogram range: |z0| below this [mm]; > 0.
    double maxAbsZ = 300.0;
    /// Bin width of the z0 histogram [mm]; > 0, at most maxAbsZ.
    double binWidth = 0.5;
    /// Excess summed over this many bins either side of a bin; >= 0.
    std::uint32_t smoothBins = 2;
    /// Maximum azimuth difference of the pair on the first two layers
    /// [rad] (sets the lowest pT found); in (0, pi/2].
    double maxDeltaPhi = 0.05;
    /// Half-width of the third hit's azimuth window about the prediction
    /// [rad]; in (0, pi/2].
    double confirmPhi = 0.005;
    /// Half-width of the third hit's z window about the (R, z) line [mm];
    /// > 0.
    double confirmZ = 2.0;
    /// Minimum excess of triplets in a vertex's window; >= 1.
    double minExcess = 4.0;
    /// Minimum excess in standard deviations of the counts (signal and
    /// background, Poisson); >= 0.
    double minSignificance = 3.0;
  };

  /// What the pre-pass found in one event.
  struct Result {
    /// z of the vertices found, ascending [mm].
    std::vector<double> vertices;
    /// Excess of triplets (signal minus background) in each vertex's window.
    std::vector<double> excess;
    /// The vertex regions: [lo, hi] of each run of active bins (bin edges),
    /// ascending and disjoint [mm].
    std::vector<std::pair<double, double>> regions;
    /// Triplets counted in the histogram range (signal and background).
    std::uint64_t triplets = 0;
    std::uint64_t background = 0;
    /// Time of the pre-pass [ms].
    double milliseconds = 0.0;
  };

  /// The first problem of `config` for `detector` as (chain-file key, what),
  /// keys those of the chain's [vertex_prepass] table; nothing if valid.
  static std::optional<std::pair<std::string, std::string>> findProblem(
      const Config& config, const Detector& detector);

  /// Throws std::invalid_argument "VertexZPrepass: key 'k': what" for an
  /// invalid config (findProblem). `detector` must outlive this.
  VertexZPrepass(const Detector& detector, Config config);

  const Config& config() const { return m_config; }
  /// The three layers used (indices into Detector::layers()), innermost
  /// first.
  const std::vector<std::uint32_t>& layers() const { return m_layers; }

  /// Finds the vertices among `hits` (all hits of the event; those off
  /// the three layers are ignored). With `excluded` (one flag per hit),
  /// the hits flagged non-zero are ignored too (FindingStep::
  /// vertexPrepassFreeHits: the hits tracks already hold).
  Result run(const ConformalHits& hits,
             const std::vector<std::uint8_t>* excluded = nullptr) const;

 private:
  const Detector* m_detector;
  Config m_config;
  std::vector<std::uint32_t> m_layers;
};

}  // namespace conftrack
