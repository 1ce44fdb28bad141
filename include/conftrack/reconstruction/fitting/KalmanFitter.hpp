#pragma once

/// @file KalmanFitter.hpp
/// The final track fit (paper 4.2, upstream.md 11): a Kalman filter with
/// Rauch-Tung-Striebel smoother on the helix parameters in global
/// coordinates, with the same helix, navigation and material model as the
/// fast simulation, and the extrapolation to the point of closest
/// approach to the z axis.

#include "conftrack/core/Hit.hpp"
#include "conftrack/core/Track.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/Detector.hpp"
#include "conftrack/geometry/SurfaceNavigator.hpp"
#include "conftrack/reconstruction/fitting/FitInput.hpp"
#include "conftrack/reconstruction/fitting/HelixState.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace conftrack {

class ModuleLayout;

/// Why a fit failed (eSuccess if it did not).
enum class FitStatus : std::uint8_t {
  eSuccess = 0,
  eTooFewHits,          ///< fewer than Config::minHits hits on the candidate
  eUnknownLayer,        ///< a hit's detector id is not a layer of the detector
  ePrefitFailed,        ///< degenerate three-point helix
  eTooFewMeasurements,  ///< too few hits left after outliers/unreachable
  eParticleStopped,     ///< energy loss stopped the particle
  ePropagationFailed,   ///< the target could not be reached
  eNumericalProblem,    ///< singular or non-finite matrices
};

/// Diagnostics of one call of KalmanFitter::fit.
struct FitInfo {
  /// Outcome of the fit that was kept.
  FitStatus status = FitStatus::eSuccess;
  /// Outcome of the first direction.
  FitStatus firstStatus = FitStatus::eSuccess;
  /// True if the other direction was tried (first failure or
  /// Config::maxHitInvertedFit).
  bool retried = false;
  /// True if the result comes from the inverted direction.
  bool inverted = false;
  /// True if the fully diffuse start was tried (both directions failed
  /// with the informed one).
  bool diffuse = false;
  /// True if the kept fit is the refit of the majority (the hits a first
  /// fit flagged as outliers; Config::majorityRefit).
  bool majority = false;
};

/// Counters and output of fitting one event.
struct FittingResult {
  /// One track per candidate, in candidate order, with its hits and
  /// outlier flags; `fitted` false where the fit failed.
  std::vector<Track> tracks;
  /// Candidates whose fit failed in both directions.
  std::size_t failures = 0;
  /// Candidates refitted in the other direction.
  std::size_t retries = 0;
  /// Candidates refitted with the fully diffuse start.
  std::size_t fallbacks = 0;
  /// Candidates whose kept fit is the refit of their majority
  /// (Config::majorityRefit).
  std::size_t majorityRefits = 0;
  /// Hits flagged as outliers on fitted tracks.
  std::size_t outliers = 0;
  /// Wall time of run() [ms].
  double milliseconds = 0.0;
};

/// Kalman fitter of track candidates (FitInput: hit indices and the first
/// direction; it needs nothing of the finder).
///
/// Track model (HelixState.hpp): the five LCIO parameters relative to a
/// pivot that moves with the fit to each surface crossing (KalTest style),
/// transported with the exact pivot transformation and its analytic
/// Jacobian (physics.md 3); between surfaces the trajectory is the
/// geometry Helix and the crossings come from the SurfaceNavigator, as in
/// the simulation.
///
/// Per candidate (hits in path order, innermost first for prompt tracks):
///  1. prefit: the helix through the first, middle and last hit
///     (physics.md 2), at the first hit of the pass, with upstream's
///     diffuse covariance except sigma(Omega), which is taken relative to
///     the prefit curvature (Config::prefitOmegaFraction);
///  2. filter pass in the first direction (along the path, or against it
///     for FitInput::backward), hits with a chi2 increment above
///     Config::maxChi2Increment flagged as outliers (an outlier leaves no
///     node: the pass goes on from the last used one), hits whose surface
///     the predicted track does not reach skipped;
///  3. filter pass in the opposite direction, started from the end of
///     pass 2 with its covariance scaled by Config::refitCovarianceScale
///     (the "error rescaling" of CMS's KFFittingSmoother: a smoother over
///     pass 2 itself would invert the nearly singular predicted
///     covariances of its first, prior-dominated nodes), then the
///     Rauch-Tung-Striebel smoother (Frühwirth, NIM A262 (1987) 444,
///     eq. 19-21) over the nodes of pass 3;
///  4. the smoothed state at the innermost node propagated to the PCA to
///     the beam line (FitInput::beamLine, by default the z axis; reference
///     = its point at z = 0; the PCA within half a turn of the innermost
///     hit), with the material crossed on the way (beam pipe) as process
///     noise and energy-loss correction.
/// If 1-4 fail, they are retried in the other direction (paper 4.2,
/// upstream MaxHitInvertedFit), then once with the fully diffuse start
/// (Config::diffuseFallback). A fit that flags more hits as outliers than
/// it uses followed a few wrong hits (in the prefit, at the start of the
/// pass) away from the rest: the flagged hits are fitted alone and that
/// fit is kept if it uses more hits (Config::majorityRefit).
///
/// Measurements: 2-D, on the hit's own sensor plane (Config::sensorPlanes):
/// the plane through the hit with normal u x v of the hit's axes (or of its
/// sensor in the ModuleLayout given to the constructor), reached from the
/// layer crossing by an exact helix-plane intersection (Newton's method);
/// the residual is (u, v) in that plane. Sensors of a module-level
/// detector are flat, tilted and staggered by millimetres around the
/// layer's navigation surface, and two hits of one layer (overlapping
/// sensors) are two measurements on two planes. For a hit of an ideal
/// layer the plane is the tangent plane of the cylinder (or the disk
/// itself), which agrees with a measurement on the cylinder to second
/// order in the residual. The measurement matrix includes the shift of
/// the crossing point along the track when d0 or z0 change,
/// dX/da = (1 - t g^T / (g . t)) dX/da|_s, g the plane normal and t the
/// direction. The update is iterated (IEKF, Gauss-Newton on the node's
/// chi2, a step accepted only if it lowers it) where the exact crossing
/// deviates from the linear model, which matters near tangent crossings
/// (low pT) and after long extrapolations; the covariance update is in
/// Joseph form.
///
/// Navigation and material stay per layer: a node's state is moved from
/// the layer crossing to its plane for the update and back for the
/// propagation, and consecutive hits of one crossing of one layer are
/// linked by the plane-to-plane move only, so that the layer's material
/// is applied once per crossing (after all its hits along the motion, as
/// the simulation, which deflects the particle once per layer crossing).
///
/// Material, at every crossed surface (sensitive with or without a hit,
/// passive), as Simulator: x/X0 = t/|cos alpha| with the same caps,
/// Highland (Rossi-Greisen for electrons) theta0 (physics.md 4) with the
/// momentum before the loss, as process noise on phi0 (theta0^2 /
/// cos^2 lambda) and on lambda (theta0^2, mapped to tanLambda and, at fixed
/// p, to Omega), and the Bethe mean loss (physics.md 5) as a correction of
/// Omega, lost along the motion and added back against it. Node states are
/// on the inner side of the node's material (the side the particle comes
/// from): along the motion a node's material is applied after its update,
/// against it before.
///
/// Electrons: Rossi-Greisen scattering and the Bethe loss only; the
/// bremsstrahlung of the simulation is not modelled (a Gaussian-sum filter
/// would be needed).
///
/// Thread-safe: fit() and run() are const and keep no state.
class KalmanFitter;

/// Mass of the fit's particle hypothesis for a PDG code of either sign:
/// 11 (electron), 13 (muon), 211 (pion), 321 (kaon), 2212 (proton); none
/// for any other code (a mass the fitter would guess is a wrong fit).
std::optional<double> massHypothesis(std::int32_t pdg);

/// The PDG codes massHypothesis knows, for messages: "11, 13, 211, 321,
/// 2212 and their negatives".
const char* knownMassHypotheses();

class KalmanFitter {
 public:
  /// Settings. Defaults follow upstream (upstream.md 11.1) where it has
  /// an equivalent.
  struct Config {
    /// PDG code of the mass hypothesis: 211 (pion, default), 13, 11
    /// (electron: Rossi-Greisen scattering), 321, 2212, of either sign;
    /// others are rejected by the constructor (massHypothesis).
    std::int32_t pdg = 211;
    /// Multiple scattering as process noise.
    bool multipleScattering = true;
    /// Mean ionisation loss as a momentum correction.
    bool energyLoss = true;
    /// Hits whose chi2 increment exceeds this are outliers (upstream
    /// MaxChi2PerHit = 100).
    double maxChi2Increment = 100.0;
    /// Initial covariance of the prefit, diagonal in (d0, phi0, Omega, z0,
    /// tanLambda), at the first hit: upstream's 1e6 mm^2, 1e2, 1e-4 mm^-2,
    /// 1e6 mm^2, 1e2.
    TrackVector initialVariance =
        (TrackVector() << 1e6 * units::mm * units::mm, 1e2,
         1e-4 / (units::mm * units::mm), 1e6 * units::mm * units::mm, 1e2)
            .finished();
    /// If > 0, the initial sigma(Omega) is prefitOmegaFraction |Omega| +
    /// prefitOmegaFloor of the prefit (capped at the initialVariance
    /// value), instead of upstream's 1e-2 mm^-1: see KalmanFitter.cpp.
    /// The final result does not depend on it (the second pass starts from
    /// the first with 100 times its covariance).
    double prefitOmegaFraction = 0.3;
    /// Floor of the initial sigma(Omega) [1/mm] (pT = 120 GeV at 4 T).
    double prefitOmegaFloor = 1e-5 / units::mm;
    /// If the fit fails in both directions with the informed start, try
    /// once more with initialVariance (a wrong hit among the three of the
    /// prefit).
    bool diffuseFallback = true;
    /// Covariance scale of the start of the second pass (CMS uses 100):
    /// the second pass counts the first pass's information with weight
    /// 1/scale, i.e. covariances come out 1/(1 + 1/scale) too small.
    double refitCovarianceScale = 100.0;
    /// Maximum linearisations of one measurement update (iterated
    /// extended Kalman filter; 1 = plain EKF). Iteration stops when the
    /// exact crossing residual agrees with the linear model to 2 % of the
    /// resolution, which takes one evaluation except near tangent
    /// crossings.
    unsigned maxUpdateIterations = 5;
    /// Minimum number of hits used in the fit (ndf = 2 n - 5 >= 1); upstream
    /// MinClustersOnTrackAfterFit = 3.
    std::uint32_t minHits = 3;
    /// Retry in the other direction when the first fails.
    bool retryInverted = true;
    /// Also retry if the first direction used fewer hits than this; the
    /// result with more hits is kept (upstream MaxHitInvertedFit = 0).
    std::uint32_t maxHitInvertedFit = 0;
    /// When a fit flags more hits as outliers than it uses, fit the
    /// outliers alone and keep that fit if it uses more hits (the others
    /// then are the outliers). On TrackML events 3 % of the true tracks
    /// came out with more than 40 % outliers: a noise or foreign hit at
    /// the end of the path carried the three-hit prefit and the first
    /// nodes, and the filter then rejected the particle's own hits.
    bool majorityRefit = true;
    /// Lower bound on |cos alpha| in x/X0 = t/|cos alpha| (as
    /// Simulator::Config::minCosIncidence).
    double minCosIncidence = 0.01;
    /// A particle whose momentum falls below this is stopped (as
    /// Simulator::Config::minMomentum).
    double minMomentum = 10.0 * units::MeV;
    /// Include the material between the innermost hit and the IP.
    bool materialToIp = true;
    /// Safety cap on the surfaces crossed between two nodes.
    unsigned maxCrossingsPerStep = 200;
    /// Measure each hit on its sensor's plane (see the class comment);
    /// false: on the layer's navigation surface (cylinder with u the arc
    /// r phi, or disk), the fit before sensor planes, kept for comparison.
    bool sensorPlanes = true;
    /// In a non-uniform field (Detector::field(), a solenoid's), transport
    /// each segment between two surfaces on the helix of the local bending
    /// at its middle, b = (B_z - tanLambda B_T . t) / B0 (t the transverse
    /// direction; the transverse field bends a track as much as B_z does),
    /// with Omega the curvature in the central field B0 (q/pT): the fit's
    /// model of the field's weakening towards the solenoid's ends. false:
    /// the field is taken as uniform B0 (the fit before; for comparison).
    /// No effect in a uniform field.
    bool followField = true;
    /// With followField, the longest path [mm] on one helix where the
    /// field's bending changes by more than 1 % between two surfaces.
    double fieldStep = 100.0 * units::mm;
  };

  /// A fitter for `detector` (copied; no reference is kept). Throws
  /// std::invalid_argument for a zero field or invalid settings.
  explicit KalmanFitter(const Detector& detector);
  /// With `sensors` (a module layout of `detector`), a hit whose layer has
  /// sensors there is measured on the plane of its sensor (DetectorId
  /// module number); its u and v axes become the sensor's (the one nearer
  /// to the hit's u is u, so Hit::sigmaU stays along it). Without, or for
  /// a module number the layout does not have, the hit's own axes: hits
  /// read from files carry their layer's axes, simulated ones their
  /// sensor's. Throws std::invalid_argument for a layout of another
  /// detector.
  KalmanFitter(const Detector& detector, const Config& config,
               const std::shared_ptr<const ModuleLayout>& sensors = nullptr);

  /// The settings.
  const Config& config() const { return m_config; }
  /// The surfaces and crossing search (shared with the simulation code).
  const SurfaceNavigator& navigator() const { return m_navigator; }

  /// Fits one candidate. `hits` is the event's hit array that
  /// input.hits indexes. The result carries the hits (all, in input order)
  /// with outlier flags and, if fitted, the states at the IP (reference
  /// (input.beamLine, 0)), first and last used hit, chi2 and ndf = 2
  /// n_used - 5; its finding fields are left at their defaults. Throws
  /// std::out_of_range for a hit index beyond `hits`,
  /// std::invalid_argument for a beam line that is not finite.
  Track fit(std::span<const Hit> hits, const FitInput& input,
            FitInfo* info = nullptr) const;

  /// Fits all candidates of an event.
  FittingResult run(std::span<const Hit> hits,
                    std::span<const FitInput> inputs) const;

  /// Mass of the hypothesis [GeV].
  double mass() const { return m_mass; }

 private:
  struct Pass;
  struct Node;
  struct Propagation;
  struct Measurement;

  /// Where hit `hit` of layer `surface` is measured.
  Measurement measurementOf(const Hit& hit, std::uint32_t surface) const;
  /// Fits in one first direction (+1 along the hit order, -1 against),
  /// with the informed or the fully diffuse start.
  FitStatus fitDirection(std::span<const Hit> hits, const FitInput& input,
                         const std::vector<Measurement>& measurements,
                         int direction, bool diffuse, Track& track) const;
  /// Config::majorityRefit on a successful `attempt` in first direction
  /// `direction`: replaces it by the fit of its outliers if that uses
  /// more hits.
  void refitMajority(std::span<const Hit> hits, const FitInput& input,
                     const std::vector<Measurement>& measurements,
                     int direction, Track& attempt, FitInfo& info) const;
  /// One filter pass over the hits in `order` (indices into input.hits).
  FitStatus filter(std::span<const Hit> hits, const FitInput& input,
                   const std::vector<Measurement>& measurements,
                   const std::vector<std::uint32_t>& order, int direction,
                   const HelixState& start, const TrackCovariance& startCov,
                   std::vector<std::uint8_t>& skip, Pass& pass) const;
  /// Moves the state from the node of `from` to the measurement of `to`:
  /// through the material and the surfaces in between, or, for a hit of
  /// the same crossing of the same layer, plane to plane.
  FitStatus propagateToNode(Propagation& state, int direction,
                            const Measurement& from,
                            const Measurement& to) const;
  /// Propagates from the current node towards the surface `target`,
  /// applying the material of every surface crossed.
  FitStatus propagateToSurface(Propagation& state, int direction,
                               std::uint32_t fromSurface,
                               std::uint32_t target) const;
  /// Propagates the state at the innermost node (inner side of the
  /// surface `fromSurface`) to the PCA to the line parallel to z through
  /// (beamLine, 0), which becomes its pivot (FitInput::beamLine).
  FitStatus propagateToIp(Propagation& state, std::uint32_t fromSurface,
                          const Vector2& beamLine) const;
  /// Measurement update at a node (iterated where non-linear): the
  /// filtered state and the chi2 increment.
  FitStatus update(const Hit& hit, const Measurement& measurement,
                   const Vector3& pivot, const TrackVector& x0,
                   const TrackCovariance& c0, TrackVector& x,
                   TrackCovariance& c, double& chi2) const;
  /// The state re-expressed at the crossing of its helix with `surface`
  /// nearest to its PCA, with the Jacobian of the move.
  FitStatus crossing(const HelixState& state, const NavigationSurface& surface,
                     HelixState& moved, TrackJacobian& jacobian) const;
  /// The state re-expressed at the crossing of its helix with the
  /// measurement's plane nearest to its PCA (Newton's method), with the
  /// Jacobian of the move; ePropagationFailed if there is none within
  /// reach.
  FitStatus planeCrossing(const HelixState& state,
                          const Measurement& measurement, HelixState& moved,
                          TrackJacobian& jacobian) const;
  /// The crossing where `measurement` is measured: its plane, or its
  /// layer without Config::sensorPlanes.
  FitStatus measurementCrossing(const HelixState& state,
                                const Measurement& measurement,
                                HelixState& moved,
                                TrackJacobian& jacobian) const;
  /// Moves the pivot of `state` to the crossing of its helix with
  /// `surface` nearest to the PCA (no-op if already there or if the helix
  /// does not reach the surface).
  FitStatus moveToCrossing(Propagation& state,
                           const NavigationSurface& surface) const;
  /// Moves the pivot of `state` to where `measurement` is measured: as
  /// moveToCrossing without Config::sensorPlanes, else to the plane
  /// crossing, ePropagationFailed (state unchanged) if there is none.
  FitStatus moveToMeasurement(Propagation& state,
                              const Measurement& measurement) const;
  /// The local bending b of the field (Config::followField) at `position`
  /// for a particle moving along `direction` (unit vector); 1 in a uniform
  /// field or without followField.
  double bendingAt(const Vector3& position, const Vector3& direction) const;
  /// bendingAt the PCA of `state` along its momentum.
  double bendingAt(const HelixState& state) const;
  /// The helix of `state` in the field of bending b (makeHelix).
  Helix helixIn(const HelixState& state, double bending, int direction) const;
  /// movePivot along the helix of bending b: Omega is the central field's
  /// curvature, the geometric one is b Omega.
  double movePivotIn(const TrackVector& params, const Vector3& from,
                     const Vector3& to, double sExpected, double bending,
                     TrackVector& moved,
                     TrackJacobian* jacobian = nullptr) const;
  /// The change of pT along a segment of transverse length
  /// `transversePath` (> 0 along the motion) by the field across the
  /// track's transverse direction (Config::followField), taken at the
  /// segment's `middle` with the particle's `direction` there: Omega and
  /// tanLambda change, |p| does not.
  void transverseFieldKick(Propagation& state, const Vector3& middle,
                           const Vector3& direction,
                           double transversePath) const;
  /// Applies the material of surface `surface` crossed at the pivot.
  FitStatus applyMaterial(const NavigationSurface& surface, int direction,
                          Propagation& state) const;

  Config m_config;
  double m_bz;
  /// Config::followField in a non-uniform field.
  bool m_followField;
  double m_mass;
  bool m_electron;
  Detector m_detector;
  SurfaceNavigator m_navigator;
  /// Sensor axes by (layer << 32 | module number), sorted by key; empty
  /// without a module layout.
  std::vector<std::pair<std::uint64_t, std::pair<Vector3, Vector3>>>
      m_sensorAxes;
};

}  // namespace conftrack
