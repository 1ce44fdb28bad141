#pragma once

/// @file GammaGammaOverlay.hpp
/// The parametric gamma gamma -> hadrons background of physics.md 7.3 (an
/// assumption to be tuned, not a published model).

#include "conftrack/core/Units.hpp"
#include "conftrack/simulation/LuminousRegion.hpp"
#include "conftrack/simulation/generators/EventGenerator.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

namespace conftrack {

/// gamma gamma -> hadrons overlay of a bunch train around the physics BX.
///
/// For each bunch crossing i = 1 .. numBunchCrossings, with offset
/// k = i - physicsBunchCrossing (-9 .. +20 for the defaults, detectors.md
/// 1.8): N_ev ~ Poisson(eventsPerBunchCrossing) events; each has its own
/// interaction point drawn from the luminous region, and N_ch ~
/// Poisson(meanCharged) charged particles (pi+-, optionally K+- and p/pbar)
/// with pT exponential (slope ptMean) truncated to [ptMin, ptMax], eta flat
/// in [-etaMax, etaMax], phi flat, charges +1/-1 in pairs (odd one random).
/// Every particle has time k * bunchSpacing (plus the interaction point's
/// time offset, 0 at CLIC) and origin eBackground.
///
/// Tuning estimate of meanCharged (target: about 460 reconstructable
/// background particles per 30 BX, i.e. 550 with the ttbar's 90): with
/// ptMean 0.35 GeV and ptMin 0.02 GeV, P(pT > 0.1 GeV) = exp(-0.08/0.35) =
/// 0.796; with |eta| < 3 flat, P(|cos theta| < 0.99) = 2.647/3 = 0.882;
/// together 0.702. A particle with pT > 0.1 GeV reaches R = 2 rho = 167 mm
/// at 4 T, past the vertex detector, so it is taken as reconstructable.
/// 460 / (30 * 3.2 * 0.702) = 6.8 charged per gamma gamma event. With the
/// full simulation and the 10 ns readout window (EventSimulation), that
/// gave 413 reconstructable background particles (>= 4 layers inside the
/// window) per tt + 30 BX event, so meanCharged was raised to 7.7: the
/// simulated tt + 30 BX events then have about 550 reconstructable
/// particles, as in the paper (README, "Samples").
class GammaGammaOverlay final : public EventGenerator {
 public:
  /// Configuration; defaults are the CLIC 3 TeV overlay.
  struct Config {
    /// Bunch crossings in the overlaid train.
    std::size_t numBunchCrossings = 30;
    /// 1-based index of the physics BX in the train (BX offsets run from
    /// 1 - physicsBunchCrossing to numBunchCrossings - physicsBunchCrossing).
    std::size_t physicsBunchCrossing = 10;
    /// Bunch spacing [ns].
    double bunchSpacing = 0.5 * units::ns;
    /// Mean gamma gamma -> hadrons events per BX (Poisson).
    double eventsPerBunchCrossing = 3.2;
    /// Mean charged particles per event (Poisson): the tuning parameter.
    double meanCharged = 7.7;
    /// Slope of the exponential pT spectrum [GeV] (its mean before the
    /// truncation).
    double ptMean = 0.35 * units::GeV;
    /// Lowest pT [GeV].
    double ptMin = 0.02 * units::GeV;
    /// Highest pT [GeV].
    double ptMax = 5.0 * units::GeV;
    /// Pseudorapidity range |eta| < etaMax.
    double etaMax = 3.0;
    /// Fraction of charged particles that are K+- (rest pions).
    double kaonFraction = 0.0;
    /// Fraction of charged particles that are p/pbar.
    double protonFraction = 0.0;
    /// Where the interactions take place (default: preset clic3tev, a
    /// Gaussian in z with sigma 0.044 mm).
    LuminousRegion::Config luminousRegion = LuminousRegion::clic3TeV();
  };

  /// Validates the configuration; throws InputError naming the bad field.
  explicit GammaGammaOverlay(const Config& config);

  /// "GammaGammaOverlay".
  std::string name() const override { return "GammaGammaOverlay"; }
  /// The configuration.
  const Config& config() const { return m_cfg; }

  /// BX offset (relative to the physics BX) of train position i (0-based).
  std::int64_t bunchCrossingOffset(std::size_t i) const {
    return static_cast<std::int64_t>(i + 1) -
           static_cast<std::int64_t>(m_cfg.physicsBunchCrossing);
  }

 private:
  std::vector<Particle> doGenerate(RandomEngine& rng,
                                   std::uint64_t eventNumber) const override;

  Config m_cfg;
  LuminousRegion m_region;
};

}  // namespace conftrack
