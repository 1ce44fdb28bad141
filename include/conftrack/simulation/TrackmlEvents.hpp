#pragma once

/// @file TrackmlEvents.hpp
/// TrackML-like events with truth: the particles of a real TrackML event
/// (Kaggle particles.csv) through conftrack's fast simulation with the
/// TrackML detector, plus optional uniform noise, with the TrackML score
/// weights in the truth. File I/O is the caller's (io: readParticles,
/// writeEvent); simulation does not depend on io.

#include "conftrack/core/BeamLine.hpp"
#include "conftrack/core/Event.hpp"
#include "conftrack/core/Hit.hpp"
#include "conftrack/core/Particle.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/Detector.hpp"
#include "conftrack/geometry/TrackmlDetector.hpp"
#include "conftrack/simulation/LuminousRegion.hpp"
#include "conftrack/simulation/Simulator.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace conftrack {

/// TrackML hit weights exactly as trackml-library weights.py
/// (evaluation.md A3): w = w_pT(pT of the particle) x w_order(rank of
/// |tz - vz| among the particle's hits, average rank for ties, profile
/// [10, 8, 6, 5, 3, 3, 3, 5, 6] interpolated onto min(nhits, 20) hits),
/// normalised to a sum of 1. Noise (particle 0), particles with fewer than 4
/// hits, hits beyond the 20th and particles missing from `particles` get 0.
/// The result is parallel to `truth`; all 0 if no hit has weight.
std::vector<double> computeTrackmlWeights(
    const std::vector<HitTruth>& truth, const std::vector<Particle>& particles);

/// The pT factor of the weights: 0 below 0.05 GeV, 0.2 up to 0.5 GeV,
/// linear to 1 at 3 GeV, 1 above.
double trackmlPtWeight(double pt);

/// The order factor for hit `ihit` (0-based rank) of a particle with
/// `nhits` hits (0 for nhits < 4 or ihit >= 20).
double trackmlOrderWeight(std::uint32_t ihit, std::uint32_t nhits);

/// Effective interaction length of the TrackML-like simulation [X0],
/// measured from the real files with the material placed where they
/// show it (trackmlSimulatorConfig; docs/validation.md items 3, 11, 12).
inline constexpr double kTrackmlInteractionLengthX0 = 1.3;

/// Extra material of the first pixel-disk sensor that a particle crosses
/// in front of a disk's surface below kTrackmlDiskInnerRingRadius [X0 at
/// normal incidence] (Simulator::Config::diskInnerRingX0). The real files'
/// production vertices lie there, on the front sensors' planes at r = 30-35
/// mm, 4.7 times as often per crossing as elsewhere on the disks (their
/// back sensors and supports at those radii: as elsewhere), and 3.3 % of
/// the prompt particles above 0.3 GeV at abs(eta) 3.5-4, which cross the
/// disks there, end after exactly one hit (the simulation without it: 0.45
/// %; with it: 3.2 %; docs/validation.md item 13).
inline constexpr double kTrackmlDiskInnerRingX0 = 0.045;
/// See kTrackmlDiskInnerRingX0 [mm].
inline constexpr double kTrackmlDiskInnerRingRadius = 35.0 * units::mm;

/// Mean noise hits per sensor and event of the Kaggle events: their hits
/// without a particle (hits less the particles' nhits) number 17,470,
/// 17,520, 17,805, 17,704 and 17,774 in events 1001-1010 (mean 17,655 on
/// 18,728 sensors), a spread of 140 where a Poisson count has 133 and a
/// fixed fraction of each event's hits would have 1,300 (15,600-19,000):
/// the noise does not follow the occupancy (docs/validation.md item 4).
inline constexpr double kTrackmlNoisePerSensor = 0.943;

/// The Simulator settings of TrackML-like events: the defaults with
/// maxTurns = 0.5 (the loop protection of the ACTS propagator that
/// simulated the Kaggle events: its path limit is half the helix
/// circumference, and the real prompt central particles indeed have the
/// hits of their outward half turn only), hadronicInteractions with the
/// effective interaction length kTrackmlInteractionLengthX0, drawn at
/// each sensor and at each layer's support, placed where the real files'
/// secondaries are produced (placedSupport), and minHitCosIncidence = 0.1
/// (all read off the real files; docs/validation.md).
Simulator::Config trackmlSimulatorConfig();

/// The vertex id of a TrackML particle_id: bits 52-63, the field
/// `vertex_id` of trackml-library's decode_particle_id (mask
/// 0xfff0000000000000). It numbers the interactions of the event: every
/// particle of one proton-proton interaction carries it, the secondaries of
/// the detector simulation included.
constexpr std::uint64_t trackmlVertexId(std::uint64_t particleId) {
  return particleId >> 52;
}

/// The generation of a TrackML particle_id: bits 24-35 (`generation` of
/// decode_particle_id); 0 for the event generator's particles, >= 1 for
/// particles made in the detector simulation.
constexpr std::uint64_t trackmlGeneration(std::uint64_t particleId) {
  return (particleId >> 24) & 0xfff;
}

/// The radial edges between the pixel, short-strip and long-strip parts
/// of the TrackML tracker [mm] (Simulator::Config::turnBandEdges): in the
/// gaps between their sensors (pixels end at 180 mm, short strips span
/// 255-705 mm, long strips start at 750 mm).
inline constexpr double kTrackmlPixelBandEdge = 200.0 * units::mm;
inline constexpr double kTrackmlStripBandEdge = 730.0 * units::mm;
/// Particles produced inside this radius (the beam-pipe volume, around the
/// 19 mm beam pipe, inside the first pixel layer at 32 mm) are not
/// affected by turnBandEdges [mm].
inline constexpr double kTrackmlBeamPipeVolumeRadius = 25.0 * units::mm;

/// Production positions closer than this to the beam line can be an
/// interaction point [mm]. The Kaggle interaction points have a transverse
/// spread of 15 um; decay vertices beyond 1 mm are far more common than
/// interaction points there.
inline constexpr double kTrackmlBeamLineRadius = 1.0 * units::mm;

/// One interaction of a TrackML event: the particles with one vertex id.
struct TrackmlInteraction {
  /// The vertex id (trackmlVertexId), >= 1.
  std::uint64_t vertexId = 0;
  /// The interaction point [mm]: of the production positions within
  /// kTrackmlBeamLineRadius of the beam line, the one shared by the most
  /// generation-0 particles of the interaction (all its particles if none
  /// has generation 0; ties: the one nearest the beam line, then the lowest
  /// z). The other positions are decays and secondaries displaced from it.
  /// Unset if no particle of the interaction starts near the beam line (its
  /// primaries are missing from the list, e.g. only the decay products of
  /// a long-lived particle are there: 2 of the 715 interactions of the five
  /// shipped events).
  std::optional<Vector3> vertex;
  /// Indices of its particles in the particle list, increasing.
  std::vector<std::size_t> particles;
};

/// Groups a TrackML particle list into its interactions, in increasing
/// vertex id. Throws InputError ("particle_id N: no TrackML vertex id ...")
/// if a particle's vertex id is 0, i.e. the ids are not TrackML-encoded
/// (conftrack's own generators number particles 1..n).
std::vector<TrackmlInteraction> findTrackmlInteractions(
    const std::vector<Particle>& particles);

/// Moves every interaction of a TrackML particle list along z to a new
/// interaction point drawn from `region`.
///
/// For each interaction in increasing vertex id (findTrackmlInteractions)
/// one z is drawn, z' = region z + sigmaZ * N(0, 1) (one normal number from
/// `rng`, none if sigmaZ = 0), and all its particles move by z' - z of its
/// interaction point (by z' for an interaction without one, as if it were
/// at z = 0, the centre of the Kaggle events). The interaction points then
/// follow the region's z distribution while every particle keeps its
/// displacement from its interaction point, so decay products and
/// secondaries stay attached to their primaries. x, y and times are kept:
/// the transverse sizes of the
/// Kaggle events (15 um) and of HL-LHC (12.5 um) agree, and an interaction
/// whose primaries are missing from the list would otherwise be moved
/// across the detector.
/// @param particles a TrackML particle list (ids TrackML-encoded)
/// @param region the target luminous region (only its z is used)
/// @param rng the event's stream for the new interaction points
/// @return the particles, in the same order, with moved vertices
std::vector<Particle> moveTrackmlInteractions(std::vector<Particle> particles,
                                              const LuminousRegion& region,
                                              RandomEngine& rng);

/// Simulates TrackML-like events from given particles.
///
/// With a ModuleLayout of the real modules (buildTrackmlModuleLayout), the
/// default, every layer is made of its real, overlapping sensors (two hits
/// where a particle crosses an overlap, none in a gap; hits measured in the
/// sensor frame); particles stop after half a turn, as in the simulation of
/// the real files (trackmlSimulatorConfig). Without
/// a layout the layers are the ideal cylinders and disks of the detector
/// file (the simulation before module level; module ids from the layer
/// grid). How well either reproduces the real files is measured by
/// `conftrack validate-trackml` (docs/validation.md). Kaggle particles have
/// no PDG code, so all are simulated with the pion mass.
class TrackmlEventSimulation {
 public:
  struct Config {
    /// Fast-simulation settings (trackmlSimulatorConfig).
    Simulator::Config simulator = trackmlSimulatorConfig();
    /// Noise, so that a fraction f of all hits is noise: f / (1 - f) x the
    /// particle hits, the same expected number on every sensor, each
    /// uniform on its sensor. This per-sensor distribution is what the
    /// real files show: with it the hits per (volume, layer) of the five
    /// Kaggle events differ from the simulation by about the same few per
    /// cent on every layer, with noise in proportion to each layer's hits
    /// or area by up to 30-60 % (docs/validation.md). The Kaggle events
    /// have f = 16-19 % overall, but as a count that does not follow the
    /// occupancy: noisePerSensor describes them. Without a module layout:
    /// on every ideal layer, f / (1 - f) x its particle hits, uniform in
    /// phi and z (cylinders) or in area (disks). In [0, 1).
    double noiseFraction = 0.0;
    /// Noise as a rate: on each layer a Poisson number of noise hits of
    /// mean noisePerSensor x its sensors, each on a sensor drawn uniformly
    /// and uniform on it, whatever the event's occupancy (the real files:
    /// kTrackmlNoisePerSensor). Needs the module layout; exclusive with
    /// noiseFraction. >= 0.
    double noisePerSensor = 0.0;
    /// The TrackML simulation's pT cut [GeV]: a particle ends after the
    /// first crossing at which its transverse momentum is below it
    /// (Simulator::Config::minTransverseMomentum), so one produced below
    /// it ends at its first surface, after that surface's hits. The real
    /// files show the cut at 0.15 GeV applied so (docs/validation.md item
    /// 7): particles from the beam line below it have no hit (their first
    /// surface is the beam pipe), 27-43 % of those produced off it have
    /// exactly one, and prompt particles of 0.15-0.16 GeV, which energy
    /// loss takes below it, have half the hits of those of 0.16-0.17 GeV
    /// at abs(eta) < 1 (4.4 against 8.2).
    double minPt = 0.0;
    /// Run seed; every event's streams derive from (seed, event number).
    std::uint64_t seed = 1;
    /// Unset (the default): every particle keeps its own vertex, as in the
    /// input. Set: the interactions are first moved along z to points drawn
    /// from this region (moveTrackmlInteractions, stream eLuminousRegion of
    /// (seed, event number)), e.g. preset "hllhc" for an HL-LHC length of
    /// 50 mm instead of the Kaggle events' 5.5 mm.
    std::optional<LuminousRegion::Config> luminousRegion = std::nullopt;
    /// The transverse position (x, y) [mm] of the beam line where the
    /// beams of the sample collide: every particle of the input moves by
    /// it, after any move along z (the real events' beams lie on the
    /// detector axis to a micron, docs/luminous-region.md), a rigid move
    /// of the whole event, so the particles keep their displacements from
    /// their interactions. Finite, each coordinate within kMaxBeamLineOffset
    /// (core/BeamLine.hpp).
    Vector2 beamLine = Vector2::Zero();
  };

  /// `modules` (may be null: ideal layers) holds the sensors of `detector`;
  /// the detector must outlive this. Throws std::invalid_argument for a
  /// noise fraction outside [0, 1), a negative or non-finite noise rate, a
  /// noise rate without a layout or together with a noise fraction, a
  /// negative minPt, a beam line that is not finite or beyond
  /// kMaxBeamLineOffset, or a layout built for another detector; InputError for
  /// a bad luminous region.
  TrackmlEventSimulation(const Detector& detector,
                         std::shared_ptr<const ModuleLayout> modules,
                         Config config);

  const Config& config() const { return m_config; }

  /// The Simulator settings of `config`: its simulator ones with the
  /// minPt floor applied along the way.
  static Simulator::Config withPtFloor(const Config& config);

  /// Simulates `particles` (e.g. a Kaggle particles file: status 1 and
  /// pdg 0, simulated with the pion mass) as event `eventNumber`: with a
  /// luminous region, the interactions are moved first; particle hits,
  /// then noise; hits sorted by (TrackML volume, layer, module) as in the
  /// Kaggle files and numbered 1..N; truth with the TrackML weights;
  /// particles (moved, if so) with their simulated nhits.
  Event simulate(std::uint64_t eventNumber,
                 const std::vector<Particle>& particles) const;

 private:
  /// Adds the noise hits of one layer.
  void addNoise(std::size_t layer, std::size_t count, RandomEngine& rng,
                Event& event) const;

  const Detector* m_detector;
  std::shared_ptr<const ModuleLayout> m_modules;
  Config m_config;
  std::optional<LuminousRegion> m_region;
  Simulator m_simulator;
};

}  // namespace conftrack
