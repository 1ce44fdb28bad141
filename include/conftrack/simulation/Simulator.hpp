#pragma once

/// @file Simulator.hpp
/// The fast detector simulation: exact helices between thin material
/// surfaces, multiple scattering and energy loss at each crossing, one
/// smeared hit per crossing of a sensitive layer (physics.md 2, 4-6).

#include "conftrack/core/Event.hpp"
#include "conftrack/core/Particle.hpp"
#include "conftrack/core/Random.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/Detector.hpp"
#include "conftrack/geometry/DiskPhiNeighbourhood.hpp"
#include "conftrack/geometry/MaterialInteractions.hpp"
#include "conftrack/geometry/ModuleCrossings.hpp"
#include "conftrack/geometry/ModuleLayout.hpp"
#include "conftrack/geometry/SurfaceNavigator.hpp"

#include <cstdint>
#include <limits>
#include <memory>
#include <random>
#include <vector>

namespace conftrack {

/// Simulates charged particles through a Detector.
///
/// Each stable (status 1) charged particle produced inside the tracker
/// envelope follows its helix from the vertex to the nearest surface
/// crossing (sensitive layer or passive surface, SurfaceNavigator), where
///  1. a hit is recorded if the surface is sensitive (true position, the
///     incoming momentum and the time in HitTruth; the measured position
///     smeared in the layer's local frame, HitSmearing.hpp);
///  2. the material x/X0 = t/|cos alpha| is applied, alpha being the angle
///     between the direction and the surface normal: multiple scattering
///     with the pre-loss momentum, then the mean ionisation loss and, for
///     electrons, Bethe-Heitler bremsstrahlung (the Fatras order);
/// and a new helix starts. A particle stops when it leaves the envelope,
/// falls below minMomentum, or has made maxTurns turns.
///
/// With a ModuleLayout, a layer that has sensors is crossed sensor by
/// sensor: every sensor whose mid-plane the helix crosses near the layer
/// crossing (findModuleCrossings) records a hit, smeared in the sensor's
/// (u, v) frame and kept inside it, so that overlapping sensors give two
/// hits and gaps none; the material is that of the sensors crossed, each
/// at its own angle, plus the layer's support, applied once at the layer
/// crossing (with Config::placedSupport the nuclear interactions are
/// drawn at each sensor and at the support, where it lies).
///
/// Thread-safe: simulate() is const and all randomness comes from the
/// engine passed in, so the output is a function of (particles, engine
/// state) only.
class Simulator {
 public:
  /// Settings, with the defaults of the fast simulation.
  struct Config {
    /// Gaussian multiple scattering at every crossing (Highland; electrons
    /// Rossi-Greisen, as ACTS).
    bool multipleScattering = true;
    /// Mean ionisation loss at every crossing (Bethe, silicon constants).
    bool energyLoss = true;
    /// Bethe-Heitler bremsstrahlung of electrons (sampled fraction; no
    /// photon is produced). Needs energyLoss.
    bool bremsstrahlung = true;
    /// Hadronic interactions end a hadron in the material: at each
    /// crossing with probability 1 - exp(-x / lambda_I), x / lambda_I =
    /// (x / X0) / interactionLengthX0. The secondaries
    /// are not produced: a particle list with truth (TrackML, HepMC from a
    /// full simulation) has them already. Hadrons are all codes but e, mu,
    /// tau and their neutrinos; pdg 0 (Kaggle particles) counts as a pion.
    bool hadronicInteractions = false;
    /// The interaction length used for hadronicInteractions, in radiation
    /// lengths of the material [X0] (silicon: 108.4 / 21.82 = 4.97).
    double interactionLengthX0 = kSiliconInteractionOverRadiationLength;
    /// No hit where a track crosses a sensor with |cos alpha| below this
    /// (alpha: angle to the sensor normal; path in the sensor above
    /// thickness / minHitCosIncidence). 0: every crossing. The real TrackML
    /// files show such a cut at 0.10: on the innermost pixel barrel layer
    /// (r = 32 mm) the hit density drops eightfold at |z| = 9.8 r
    /// (docs/validation.md). Only with a ModuleLayout.
    double minHitCosIncidence = 0.0;
    /// Smear measured positions; if false the hit is the true crossing.
    bool smearHits = true;
    /// Particles below this momentum are not simulated or are stopped
    /// [GeV]. 10 MeV: at 4 T the diameter is then below 17 mm.
    double minMomentum = 10.0 * units::MeV;
    /// A particle ends after a crossing (its hits recorded, its material
    /// applied) at which its transverse momentum is below this [GeV] (0:
    /// never). The TrackML simulation applies its 0.15 GeV cut so
    /// (TrackmlEventSimulation::Config::minPt).
    double minTransverseMomentum = 0.0;
    /// Stop a looper after this many turns (transverse path / (2 pi rho),
    /// summed over its helix segments); Geant4 has no such limit. Most
    /// loopers leave the vertex barrel along z or range out before: for
    /// 3000 soft pions in CLICdet, 3 / 10 / 30 turns give 33.0k / 34.5k /
    /// 35.4k hits in 27 / 30 / 31 ms. The TrackML simulation stops at half
    /// a turn (TrackmlEvents.hpp).
    double maxTurns = 10.0;
    /// Count maxTurns as the ACTS propagator's loop protection does: a
    /// three-dimensional path of maxTurns circumferences 2 pi p / (q |B|),
    /// with the momentum and the field at production, fixed then. It ends
    /// a particle earlier than counting its turns where the field weakens
    /// along its path (the TrackML solenoid's ends) and later where it
    /// loses momentum. Used for the TrackML simulation (TrackmlEvents.hpp).
    bool loopPathFromProduction = false;
    /// Smearing draws per hit before it is dropped (MaxTries of
    /// DDPlanarDigiProcessor).
    unsigned maxSmearAttempts = 10;
    /// Safety cap on the surface crossings of one particle.
    unsigned maxCrossings = 1000;
    /// In a non-uniform field (Detector::field()), the longest path [mm]
    /// along which the field is taken as constant: the field at the
    /// segment's middle, its B_z bending the helix and its transverse part
    /// kicking at the segment's end. With 25 mm, hits lie within 0.5 mm of
    /// the Lorentz-force path in the TrackML solenoid (FieldSimulation
    /// tests; 50 mm: up to 0.9 mm).
    double fieldStep = 25.0 * units::mm;
    /// Lower bound on |cos alpha| in x/X0 = t/|cos alpha|: a grazing track
    /// sees at most 1/minCosIncidence times the normal thickness (the thin-
    /// surface model has no other limit on disks; cylinders and cones are
    /// further capped at the chord of a tangent track through the shell,
    /// NavigationSurface::grazingCos).
    double minCosIncidence = 0.01;
    /// Radii [mm], increasing, that divide the tracker into radial bands
    /// (the navigation volumes of the simulation being reproduced). A
    /// particle produced at or beyond turnBandMinProductionRadius while
    /// moving towards the beam line (x px + y py < 0) leaves no hit, once
    /// past its smallest radius, on the sensors of the band that holds
    /// that radius; its material is still crossed. The real TrackML files
    /// show this (docs/validation.md item 5): such particles have 2.5-3
    /// hits fewer than those produced at the same place moving outward,
    /// at every momentum and whatever their turning radius. Empty: off.
    std::vector<double> turnBandEdges;
    /// See turnBandEdges [mm]: particles produced inside it (the beam-pipe
    /// volume of TrackML) are not affected.
    double turnBandMinProductionRadius = 0.0;
    /// On disk layers with sensors, only the sensors in the azimuthal
    /// neighbourhood of the layer crossing (DiskPhiNeighbourhood: its bin
    /// and the two beside it) are crossed; sensors overlapping deeper than
    /// that give no hit and no material, as in the ACTS navigation of the
    /// real TrackML files (docs/validation.md item 6).
    bool diskPhiNeighbourhood = false;
    /// On layers with sensors, the layer's support is a surface of its
    /// own, where the real TrackML files place it (docs/validation.md item
    /// 11), and each sensor crossed and the support draw a hadron's
    /// nuclear interaction in the order crossed, ending the particle
    /// there: a disk's support lies at the layer surface, between its two
    /// planes of sensors; a barrel layer's on its inner side if its radius
    /// is at least innerSupportMinRadius, else on its outer side. Off: the
    /// interaction is drawn once for the layer, after all its sensors.
    bool placedSupport = false;
    /// See placedSupport [mm]; >= 0.
    double innerSupportMinRadius = std::numeric_limits<double>::infinity();
    /// Extra material [X0 at normal incidence] of the disk sensors in front
    /// of their layer surface (nearer z = 0) where a particle crosses them
    /// below diskInnerRingRadius: added to the sensor's own in its
    /// scattering, energy loss and (placedSupport) nuclear interaction,
    /// drawn after its hit, on the first such sensor crossed only. The
    /// real TrackML files' secondaries are produced there 4.7 times as
    /// often per crossing as elsewhere on the pixel disks (docs/
    /// validation.md item 13). >= 0; 0: none.
    double diskInnerRingX0 = 0.0;
    /// See diskInnerRingX0 [mm]; >= 0.
    double diskInnerRingRadius = 0.0;
  };

  /// The smallest transverse step between two crossings [mm]: a surface
  /// just crossed is not found again within this distance.
  static constexpr double kMinStep = 1e-4 * units::mm;
  /// Layers with sensors farther than this from their surface
  /// (ModuleLayout::shellHalfThickness; CLICdet's spiral vertex-endcap
  /// petals, 21 mm) look for sensor crossings also before the previous
  /// surface crossing, along the same helix extrapolated backwards: their
  /// sensors can lie behind the neighbouring layer (the petals of VXD_E_L1
  /// at z = 161-202 mm behind the disk of VXD_E_L0 at 179.7 mm). Such a
  /// hit ignores the scattering at the surfaces in between and comes after
  /// later hits in the hit list. All other layers (the TrackML sensors:
  /// at most 6.1 mm) look forward only.
  static constexpr double kBackwardSearchShell = 10.0 * units::mm;

  /// Simulator with the default Config. Copies what it needs from
  /// `detector` (no reference is kept).
  explicit Simulator(const Detector& detector);
  /// Simulator with `config`; throws std::invalid_argument for invalid
  /// settings (negative minMomentum, maxTurns <= 0, zero attempts or
  /// crossings, minCosIncidence outside (0, 1]).
  Simulator(const Detector& detector, const Config& config);
  /// Simulator with `config` whose layers are made of the sensors of
  /// `modules` (built for `detector`; shared, not copied; may be null).
  /// Throws std::invalid_argument as above, and if `modules` was built for
  /// a detector with another number of layers.
  Simulator(const Detector& detector, const Config& config,
            std::shared_ptr<const ModuleLayout> modules);

  /// The settings.
  const Config& config() const { return m_config; }
  /// The surfaces and crossing search.
  const SurfaceNavigator& navigator() const { return m_navigator; }
  /// The sensors, or null for ideal layers.
  const ModuleLayout* modules() const { return m_modules.get(); }

  /// Simulates `particles` and appends to `out`: hits and their truth
  /// (parallel), in particle order then crossing order, with ids counting
  /// on from the largest hit id already in `out` (1 for an empty event);
  /// all particles (also neutral, decayed and skipped ones) with nHits set.
  /// out.particles is left sorted by id.
  void simulate(const std::vector<Particle>& particles, RandomEngine& rng,
                Event& out) const;

  /// Mass used for a PDG code [GeV]: the PDG table, the charged-pion mass
  /// for codes not in it.
  static double massOf(std::int32_t pdg);

 private:
  /// Reused per-call buffers of the sensor search.
  struct Scratch {
    std::vector<std::uint32_t> candidates;
    std::vector<ModuleCrossing> crossings;
  };

  /// The band of transverse radius `r` (turnBandEdges): the number of
  /// edges at or below it.
  int radialBand(double r) const;
  /// Whether a particle at `position` with `momentum` gets no hit there:
  /// it moves outward in `blindBand` (-1: never; turnBandEdges).
  bool isBlind(int blindBand, const Vector3& position,
               const Vector3& momentum) const;
  /// Propagates one particle, appending its hits; returns their number.
  std::uint32_t simulateParticle(const Particle& particle, RandomEngine& rng,
                                 std::normal_distribution<double>& normal,
                                 std::uint64_t& nextHitId, Scratch& scratch,
                                 Event& out) const;
  /// Records the hits of the sensors of `layer` crossed near arc length
  /// `s` of `helix` (time and particle as at the layer crossing); returns
  /// the material crossed [X0] along `direction`. Sensors in `blindBand`
  /// (turnBandEdges; -1: none) give no hit to a particle moving outward.
  /// With `lookBehind` (the helix starts at a field step's end), sensors
  /// behind its start are taken too. With Config::placedSupport the
  /// nuclear interactions of a hadron (`isHadron`) are drawn here, at each
  /// sensor and at the support, and `interacted` is set if one ended the
  /// particle; otherwise the caller draws one for the returned material.
  double crossModules(const Helix& helix, double s, bool lookBehind,
                      std::uint32_t layer, const NavigationSurface& surface,
                      const Vector3& direction, double beta, double time,
                      std::uint64_t particleId, int blindBand, bool isHadron,
                      RandomEngine& rng,
                      std::normal_distribution<double>& normal,
                      std::uint64_t& nextHitId, Scratch& scratch, Event& out,
                      std::uint32_t& nHits, bool& interacted) const;
  /// Whether a hadron (`isHadron`) interacts in `xOverX0` of material:
  /// probability 1 - exp(-xOverX0 / Config::interactionLengthX0), one
  /// draw from `rng` when there is material.
  bool interacts(double xOverX0, bool isHadron, RandomEngine& rng) const;

  /// `momentum` at the end of the first `s` of `helix` (built with the
  /// B_z of `field`), turned by `field`'s transverse part along it.
  static Vector3 transverseFieldKick(const Helix& helix, double s,
                                     double charge, const Vector3& field,
                                     const Vector3& momentum);

  Config m_config;
  MagneticField m_field;
  double m_envelopeR;
  double m_envelopeZ;
  std::vector<SensitiveLayer> m_layers;
  SurfaceNavigator m_navigator;
  std::shared_ptr<const ModuleLayout> m_modules;
  /// Set with Config::diskPhiNeighbourhood and a layout.
  std::shared_ptr<const DiskPhiNeighbourhood> m_neighbourhood;
};

}  // namespace conftrack
