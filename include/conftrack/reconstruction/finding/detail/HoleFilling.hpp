#pragma once

/// @file HoleFilling.hpp
/// Hole filling (a conftrack addition): a track takes unused hits on the
/// layers that it crosses between its first and last hit but has no hit
/// on, best chi2 first. Such holes are left where a short cell (between the
/// two sensors of a double layer, 2 mm apart) failed an angle cut and the
/// automaton skipped the layer, or where an extension step searched only
/// its own collections. Run on each newly built track (with the inward
/// extension, completeTrack) and, with neighbour residuals, on every track
/// after the last step (FinderConfig::finalHoleFilling, fillHoles).

#include "conftrack/reconstruction/finding/detail/LayerCrossingSearch.hpp"

#include <cstdint>
#include <vector>

namespace conftrack::detail {

/// Fills the holes of one track.
class HoleFilling {
 public:
  /// How a hit in a hole is judged against the hole cut.
  enum class Residuals : std::uint8_t {
    /// By its chi2 increase to the track's fits (the completion of newly
    /// built tracks).
    eToFits,
    /// By its residuals to the fits minus those interpolated between the
    /// track's hits on either side of the hole (the final hole filling).
    /// Below a few GeV multiple scattering bends a track away from its
    /// fitted circle and s-z line by far more than the hit resolution
    /// (chi2/ndf ~ 100 at 1 GeV), but smoothly: the neighbours' residuals
    /// carry the local deviation, which the difference removes.
    eToNeighbours,
  };

  /// The cuts of the hole filling.
  struct Config {
    /// Largest increase of chi2_uv/ndf and of chi2_sz/ndf when a hit is
    /// added (the step key chi2_cut of the step that built the track),
    /// scaled below chi2PtScale.
    double chi2Cut = 100.0;
    /// pT scale of chi2Cut [GeV] (chi2_cut_pt_scale_GeV; 0: off).
    double chi2PtScale = 0.0;
    /// Half-width of the azimuth window around a predicted crossing [rad]
    /// (finder key extension_phi_window).
    double phiWindow = 0.1;
    /// At most this many hits examined per predicted crossing (finder key
    /// max_window_hits; counted as Guard::eWindowHits).
    std::uint32_t maxWindowHits = 256;
    /// When no hit fills a hole within the hit resolutions, look again
    /// with the allowance for multiple scattering in the material of the
    /// layer before the hole (finder key scattering_allowance).
    bool scatteringAllowance = true;
    /// How a hit is judged against the hole cut.
    Residuals residuals = Residuals::eToFits;

    /// The chi2 cut for a track of transverse momentum `pt` [GeV].
    double chi2CutAt(double pt) const {
      return scaledChi2Cut(chi2Cut, chi2PtScale, pt);
    }
    /// The configuration of `step` in `finder`, judging by `residuals`.
    static Config fromStep(const FindingStep& step, const FinderConfig& finder,
                           Residuals residuals);
  };

  /// Throws std::invalid_argument naming the key of a bad value.
  explicit HoleFilling(const Config& config);

  const Config& config() const { return m_config; }

  /// Fills the holes of track t of state.tracks with unused hits of
  /// `pool`, one at a time, the best of all holes first, refitting after
  /// each; each hit is claimed at once (used flag, clone index,
  /// StepStats::extendedHits). Tracks with fewer than three hits and
  /// helix-step tracks are left alone.
  void run(FinderState& state, const HitPool& pool, StepStats& stats,
           std::uint32_t t) const;

 private:
  /// The best hole hit of the chain (see run), with or without the
  /// scattering allowance; `best` stays kInvalidIndex if none.
  void findHole(LayerCrossingSearch& search, const Chain& chain, bool allowance,
                ConfIndex& best, double& bestS) const;

  /// chi2 of hit h (arc length s) in the hole after the chain's hit
  /// `before`, by Residuals::eToNeighbours.
  double localHoleChi2(const ConformalHits& hits, const Chain& chain,
                       std::size_t before, ConfIndex h, double s,
                       const Scatter& ms) const;

  Config m_config;
  /// Scratch buffers, reused from track to track (not shared between
  /// threads: one unit per step and event).
  struct Workspace {
    CrossingScratch crossing;
    Chain chain;
    /// Arc lengths of the chain's hits, unwrapped along the track.
    std::vector<double> hitS;
  };
  mutable Workspace m_work;
};

}  // namespace conftrack::detail
