#include "conftrack/simulation/Simulator.hpp"

#include "conftrack/core/PdgTable.hpp"
#include "conftrack/geometry/MaterialInteractions.hpp"
#include "conftrack/simulation/HitSmearing.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace conftrack {

namespace {

/// Rotates the unit vector `dir` by two projected angles theta1, theta2
/// about two orthogonal axes perpendicular to it. Implemented as a rotation
/// by the space angle theta = hypot(theta1, theta2) towards the azimuth
/// atan2(theta2, theta1), which is well defined for any angle and equals
/// the two projected rotations to O(theta^2).
Vector3 deflect(const Vector3& dir, double theta1, double theta2) {
  const double theta = std::sqrt(theta1 * theta1 + theta2 * theta2);
  if (theta == 0.0) {
    return dir;
  }
  const double dt = dir.head<2>().norm();
  // e1 horizontal and perpendicular to dir, e2 = dir x e1.
  const Vector3 e1 =
      dt > 0.0 ? Vector3(-dir.y() / dt, dir.x() / dt, 0.0) : Vector3::UnitX();
  const Vector3 e2 = dir.cross(e1);
  const double sinOverTheta = std::sin(theta) / theta;
  Vector3 out =
      std::cos(theta) * dir + sinOverTheta * (theta1 * e1 + theta2 * e2);
  return out.normalized();
}

/// Safety cap on the field steps of one particle (25 mm steps cross the
/// TrackML tracker's 6 m length in 240).
constexpr unsigned kMaxFieldSteps = 10000;

}  // namespace

Simulator::Simulator(const Detector& detector)
    : Simulator(detector, Config()) {}

Simulator::Simulator(const Detector& detector, const Config& config)
    : Simulator(detector, config, nullptr) {}

Simulator::Simulator(const Detector& detector, const Config& config,
                     std::shared_ptr<const ModuleLayout> modules)
    : m_config(config),
      m_field(detector.field()),
      m_envelopeR(detector.envelopeR()),
      m_envelopeZ(detector.envelopeZ()),
      m_layers(detector.layers()),
      m_navigator(detector),
      m_modules(std::move(modules)) {
  if (m_modules && m_modules->numLayers() != m_layers.size()) {
    throw std::invalid_argument(
        "Simulator: the module layout was built for another detector");
  }
  if (!(m_config.minMomentum >= 0.0)) {
    throw std::invalid_argument("Simulator: minMomentum must be >= 0");
  }
  if (!(m_config.fieldStep > 0.0)) {
    throw std::invalid_argument("Simulator: fieldStep must be positive");
  }
  if (!(m_config.minTransverseMomentum >= 0.0)) {
    throw std::invalid_argument(
        "Simulator: minTransverseMomentum must be >= 0");
  }
  if (!(m_config.maxTurns > 0.0)) {
    throw std::invalid_argument("Simulator: maxTurns must be positive");
  }
  if (m_config.maxSmearAttempts == 0 || m_config.maxCrossings == 0) {
    throw std::invalid_argument(
        "Simulator: maxSmearAttempts and maxCrossings must be positive");
  }
  if (!(m_config.innerSupportMinRadius >= 0.0)) {
    throw std::invalid_argument(
        "Simulator: innerSupportMinRadius must be >= 0");
  }
  if (!(m_config.diskInnerRingX0 >= 0.0 &&
        m_config.diskInnerRingRadius >= 0.0 &&
        std::isfinite(m_config.diskInnerRingX0) &&
        std::isfinite(m_config.diskInnerRingRadius))) {
    throw std::invalid_argument(
        "Simulator: diskInnerRingX0 and diskInnerRingRadius must be finite "
        "and >= 0");
  }
  if (!(m_config.interactionLengthX0 > 0.0)) {
    throw std::invalid_argument("Simulator: interactionLengthX0 must be > 0");
  }
  if (!(m_config.minHitCosIncidence >= 0.0 &&
        m_config.minHitCosIncidence < 1.0)) {
    throw std::invalid_argument(
        "Simulator: minHitCosIncidence must be in [0, 1)");
  }
  if (!(m_config.minCosIncidence > 0.0 && m_config.minCosIncidence <= 1.0)) {
    throw std::invalid_argument("Simulator: minCosIncidence must be in (0, 1]");
  }
  const std::vector<double>& edges = m_config.turnBandEdges;
  if (!std::all_of(edges.begin(), edges.end(),
                   [](double r) { return r > 0.0 && std::isfinite(r); }) ||
      !std::is_sorted(edges.begin(), edges.end()) ||
      std::adjacent_find(edges.begin(), edges.end()) != edges.end()) {
    throw std::invalid_argument(
        "Simulator: turnBandEdges must be positive, finite and increasing");
  }
  if (!(m_config.turnBandMinProductionRadius >= 0.0)) {
    throw std::invalid_argument(
        "Simulator: turnBandMinProductionRadius must be >= 0");
  }
  if (m_config.diskPhiNeighbourhood && m_modules) {
    m_neighbourhood = std::make_shared<const DiskPhiNeighbourhood>(*m_modules);
  }
}

int Simulator::radialBand(double r) const {
  const std::vector<double>& edges = m_config.turnBandEdges;
  return static_cast<int>(std::upper_bound(edges.begin(), edges.end(), r) -
                          edges.begin());
}

bool Simulator::isBlind(int blindBand, const Vector3& position,
                        const Vector3& momentum) const {
  return blindBand >= 0 && position.head<2>().dot(momentum.head<2>()) >= 0.0 &&
         radialBand(position.head<2>().norm()) == blindBand;
}

double Simulator::massOf(std::int32_t pdg) {
  return pdg::mass(pdg).value_or(constants::kPionMass);
}

void Simulator::simulate(const std::vector<Particle>& particles,
                         RandomEngine& rng, Event& out) const {
  // One distribution for the whole call: its cached second value is part of
  // the (deterministic) state.
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uint64_t nextHitId = 1;
  for (const Hit& h : out.hits) {
    nextHitId = std::max(nextHitId, h.id + 1);
  }
  out.particles.reserve(out.particles.size() + particles.size());
  Scratch scratch;
  for (const Particle& particle : particles) {
    Particle copy = particle;
    copy.nHits = 0;
    if (particle.isStable() && particle.charge != 0.0) {
      copy.nHits =
          simulateParticle(particle, rng, normal, nextHitId, scratch, out);
    }
    out.particles.push_back(copy);
  }
  if (!std::is_sorted(
          out.particles.begin(), out.particles.end(),
          [](const Particle& a, const Particle& b) { return a.id < b.id; })) {
    out.sortParticles();
  }
}

Vector3 Simulator::transverseFieldKick(const Helix& helix, double s,
                                       double charge, const Vector3& field,
                                       const Vector3& momentum) {
  // dp/dl = q k (d x B): the segment's helix took B_z; the rest of the
  // field, (B_x, B_y, 0), turns the momentum by q k l (d x B_perp) over
  // its path l, without changing its magnitude.
  const Vector3 transverse(field.x(), field.y(), 0.0);
  const double magnitude = momentum.norm();
  const Vector3 direction = momentum / magnitude;
  const Vector3 kicked = momentum + charge * constants::kPtPerTeslaMm *
                                        helix.pathLength(s) *
                                        direction.cross(transverse);
  return magnitude * kicked.normalized();
}

std::uint32_t Simulator::simulateParticle(
    const Particle& particle, RandomEngine& rng,
    std::normal_distribution<double>& normal, std::uint64_t& nextHitId,
    Scratch& scratch, Event& out) const {
  Vector3 position = particle.vertex;
  if (!(position.head<2>().norm() < m_envelopeR &&
        std::abs(position.z()) < m_envelopeZ)) {
    return 0;  // produced outside the tracker
  }
  const double charge = particle.charge;
  const double mass = massOf(particle.pdg);
  const bool isElectron = std::abs(particle.pdg) == 11;
  const int absPdg = std::abs(particle.pdg);
  const bool isHadron =
      m_config.hadronicInteractions && !(absPdg >= 11 && absPdg <= 16);
  Vector3 momentum = particle.momentum;
  double p = momentum.norm();
  if (!(p >= m_config.minMomentum) || momentum.head<2>().squaredNorm() == 0.0) {
    return 0;
  }
  // Started towards the beam line: after its turning point the sensors of
  // the band it turned in give no hit (Config::turnBandEdges).
  int blindBand = -1;
  if (!m_config.turnBandEdges.empty() &&
      position.head<2>().norm() >= m_config.turnBandMinProductionRadius &&
      position.head<2>().dot(momentum.head<2>()) < 0.0) {
    blindBand = radialBand(
        Helix(position, momentum, charge, m_field.centralBz()).minRadius());
  }
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double energy = std::sqrt(p * p + mass * mass);
  double time = particle.time;
  double turns = 0.0;
  // With Config::loopPathFromProduction the loop limit is a path length
  // fixed at production: maxTurns circumferences of the helix of the
  // production momentum in the field at the production point.
  double pathLimit = kInf;
  if (m_config.loopPathFromProduction && charge != 0.0) {
    const double productionField = m_field.at(position).norm();
    if (productionField > 0.0) {
      pathLimit =
          m_config.maxTurns * 2.0 * std::numbers::pi * p /
          (constants::kPtPerTeslaMm * std::abs(charge) * productionField);
    }
  }
  double pathTravelled = 0.0;
  // Time, turns and path along the first s of a helix segment.
  auto travel = [&](const Helix& helix, double s) {
    time += helix.pathLength(s) / (p / energy * constants::c);
    turns += s * std::abs(helix.omega()) / (2.0 * std::numbers::pi);
    pathTravelled += helix.pathLength(s);
  };
  std::uint32_t nHits = 0;

  unsigned fieldSteps = 0;
  // True while the helix starts at the end of a field step rather than at a
  // surface: sensors of the next layer may then lie behind its start.
  bool afterFieldStep = false;
  // Surface crossings counted against maxCrossings; field steps are not.
  unsigned crossings = 0;
  while (crossings < m_config.maxCrossings) {
    // A non-uniform field is taken as constant along a helix segment of at
    // most fieldStep: the field at the segment's middle (predicted with the
    // B_z of its start), whose B_z bends the helix and whose transverse
    // part kicks at the segment's end.
    const bool uniform = m_field.isUniform();
    Vector3 field(0.0, 0.0, m_field.centralBz());
    double sStep = kInf;
    if (!uniform) {
      const double tanLambda = momentum.z() / momentum.head<2>().norm();
      sStep = m_config.fieldStep / std::sqrt(1.0 + tanLambda * tanLambda);
      const Helix start(position, momentum, charge, m_field.at(position).z());
      field = m_field.at(start.position(0.5 * sStep));
    }
    const Helix helix(position, momentum, charge, field.z());
    // Path limit: the envelope exit (cylinder or end plane) and the turns
    // left.
    double sLimit =
        helix.maxRadius() < m_envelopeR
            ? kInf
            : helix.nextCylinderCrossing(m_envelopeR, -kInf, kInf, 0.0, kInf);
    if (helix.tanLambda() != 0.0) {
      const double zEnd = helix.tanLambda() > 0.0 ? m_envelopeZ : -m_envelopeZ;
      sLimit = std::min(sLimit, (zEnd - position.z()) / helix.tanLambda());
    }
    if (m_config.loopPathFromProduction) {
      sLimit = std::min(
          sLimit, (pathLimit - pathTravelled) /
                      std::sqrt(1.0 + helix.tanLambda() * helix.tanLambda()));
    } else if (helix.omega() != 0.0) {
      sLimit = std::min(sLimit, (m_config.maxTurns - turns) * helix.period());
    }
    const SurfaceCrossing next =
        m_navigator.nextCrossing(helix, kMinStep, std::min(sLimit, sStep));
    if (!next.found()) {
      if (sStep < sLimit && ++fieldSteps < kMaxFieldSteps) {
        // No surface on this segment: move to its end and go on.
        Vector3 momentumOut;
        helix.positionAndMomentum(sStep, position, momentumOut);
        travel(helix, sStep);
        momentum =
            transverseFieldKick(helix, sStep, charge, field, momentumOut);
        if (momentum.head<2>().squaredNorm() == 0.0) {
          break;  // turned exactly along z: no helix
        }
        afterFieldStep = true;
        continue;
      }
      break;  // leaves the tracker or has looped enough
    }
    ++crossings;
    const double s = next.s;
    const bool lookBehind = afterFieldStep;
    afterFieldStep = false;
    Vector3 momentumIn;
    helix.positionAndMomentum(s, position, momentumIn);
    if (!uniform) {
      momentumIn = transverseFieldKick(helix, s, charge, field, momentumIn);
    }
    const double beta = p / energy;
    travel(helix, s);

    const NavigationSurface& surface = m_navigator.surfaces()[next.surface];
    Vector3 direction = momentumIn / p;
    double xOverX0 = 0.0;
    const bool modular =
        surface.isSensitive() && m_modules &&
        m_modules->hasModules(static_cast<std::uint32_t>(surface.layer));
    bool endedInSensor = false;
    if (modular) {
      xOverX0 = crossModules(
          helix, s, lookBehind, static_cast<std::uint32_t>(surface.layer),
          surface, direction, beta, time, particle.id, blindBand, isHadron, rng,
          normal, nextHitId, scratch, out, nHits, endedInSensor);
    } else if (surface.thicknessX0 > 0.0) {
      xOverX0 = surface.xOverX0(position, direction, m_config.minCosIncidence);
    }
    if (surface.isSensitive() && !modular &&
        !isBlind(blindBand, position, momentumIn)) {
      const SensitiveLayer& layer =
          m_layers[static_cast<std::size_t>(surface.layer)];
      Vector3 measured = position;
      if (!m_config.smearHits ||
          smearHitPosition(layer, position, rng, normal,
                           m_config.maxSmearAttempts, measured)) {
        Hit hit;
        hit.id = nextHitId++;
        hit.position = measured;
        hit.detId = layer.id;
        hit.detId.module = layer.moduleAt(position);
        layer.localAxes(measured, hit.uAxis, hit.vAxis);
        hit.sigmaU = layer.sigmaU;
        hit.sigmaV = layer.sigmaV;
        out.hits.push_back(hit);
        HitTruth truth;
        truth.particleId = particle.id;
        truth.position = position;
        truth.momentum = momentumIn;
        truth.time = time;
        out.truth.push_back(truth);
        ++nHits;
      }
    }

    // Material of the surface, traversed at the actual angle.
    if (xOverX0 > 0.0 && (m_config.multipleScattering || m_config.energyLoss)) {
      if (m_config.multipleScattering) {
        const double theta0 =
            scatteringTheta0(p, beta, charge, xOverX0, isElectron);
        const double theta1 = theta0 * normal(rng);
        const double theta2 = theta0 * normal(rng);
        direction = deflect(direction, theta1, theta2);
      }
      if (m_config.energyLoss) {
        energy -= betheMeanEnergyLoss(p, mass, charge, xOverX0);
        if (isElectron && m_config.bremsstrahlung && energy > mass) {
          // E_after/E_before = exp(-y), y ~ Gamma(t/ln2, 1).
          std::gamma_distribution<double> gamma(betheHeitlerShape(xOverX0),
                                                1.0);
          energy *= std::exp(-gamma(rng));
        }
        if (!(energy > mass)) {
          break;  // stopped in the material
        }
        p = std::sqrt((energy - mass) * (energy + mass));
        if (p < m_config.minMomentum) {
          break;
        }
      }
    }
    if (endedInSensor) {
      break;  // a nuclear interaction inside the layer (placedSupport)
    }
    // With placedSupport a layer of sensors drew its interactions itself.
    const bool drawnInLayer = modular && m_config.placedSupport;
    if (!drawnInLayer && interacts(xOverX0, isHadron, rng)) {
      break;  // a nuclear interaction: the particle ends here
    }
    momentum = p * direction;
    if (momentum.head<2>().squaredNorm() == 0.0) {
      break;  // scattered exactly along z: no helix
    }
    if (momentum.head<2>().norm() < m_config.minTransverseMomentum) {
      break;  // below the transverse-momentum floor
    }
  }
  return nHits;
}

bool Simulator::interacts(double xOverX0, bool isHadron,
                          RandomEngine& rng) const {
  return isHadron && xOverX0 > 0.0 &&
         std::uniform_real_distribution<double>(0.0, 1.0)(rng) <
             -std::expm1(-xOverX0 / m_config.interactionLengthX0);
}

double Simulator::crossModules(
    const Helix& helix, double s, bool lookBehind, std::uint32_t layerIndex,
    const NavigationSurface& surface, const Vector3& direction, double beta,
    double time, std::uint64_t particleId, int blindBand, bool isHadron,
    RandomEngine& rng, std::normal_distribution<double>& normal,
    std::uint64_t& nextHitId, Scratch& scratch, Event& out,
    std::uint32_t& nHits, bool& interacted) const {
  const ModuleLayout& layout = *m_modules;
  const SensitiveLayer& layer = m_layers[layerIndex];
  scratch.crossings.clear();
  // A layer whose sensors reach past the neighbouring layers' surfaces
  // (CLICdet's spiral petals) can have sensors behind the previous
  // crossing, where this helix starts: look backwards too.
  // So can a helix that starts at the end of a field step, inside the
  // shell of sensors in front of the layer surface (lookBehind): the
  // previous segment did not reach the surface, so none of them is taken.
  const double sMin =
      lookBehind || layout.shellHalfThickness(layerIndex) > kBackwardSearchShell
          ? -std::numeric_limits<double>::infinity()
          : kMinStep;
  findModuleCrossings(helix, s, sMin, layerIndex, layout, scratch.candidates,
                      scratch.crossings);
  // The support, with the geometry of the layer surface.
  const Vector3 layerPosition = helix.position(s);
  const double supportX0 =
      surface.thicknessX0 > 0.0
          ? surface.xOverX0(layerPosition, direction,
                            m_config.minCosIncidence) *
                (layout.supportX0(layerIndex) / surface.thicknessX0)
          : 0.0;
  double xOverX0 = supportX0;
  const bool placed = m_config.placedSupport;
  // With Config::placedSupport: where the support lies along this crossing,
  // as an arc length (before or after all sensors on a barrel layer, at
  // the layer surface between a disk's planes of sensors).
  double sSupport = s;
  if (placed && !layer.isDisk()) {
    const bool innerSide = layer.r >= m_config.innerSupportMinRadius;
    const bool outward =
        layerPosition.x() * direction.x() + layerPosition.y() * direction.y() >
        0.0;
    sSupport = innerSide == outward ? -std::numeric_limits<double>::infinity()
                                    : std::numeric_limits<double>::infinity();
  }
  bool supportCrossed = !placed;
  // Config::diskInnerRingX0: only on disks, for sensors in front of the
  // layer surface.
  bool innerRing = layer.isDisk() && m_config.diskInnerRingX0 > 0.0;
  const double ringRadius2 =
      m_config.diskInnerRingRadius * m_config.diskInnerRingRadius;
  const double layerPhi =
      m_neighbourhood ? std::atan2(layerPosition.y(), layerPosition.x()) : 0.0;
  // Below the pT floor the particle ends in the first sensor it meets
  // (the real TrackML files: one hit, never two; docs/validation.md).
  const bool belowFloor = helix.pt() < m_config.minTransverseMomentum;
  // A crossed sensor's hit, unless the track grazes it, is blind there or
  // is smeared out of it.
  auto recordHit = [&](const ModuleCrossing& crossing,
                       const PlanarModule& module, const Vector3& truePosition,
                       const Vector3& momentum, double cosIncidence) {
    if (cosIncidence < m_config.minHitCosIncidence) {
      return;  // too long a path in the sensor: no hit (real TrackML)
    }
    if (isBlind(blindBand, truePosition, momentum)) {
      return;  // after an inward start's turn (Config::turnBandEdges)
    }
    double u = crossing.u;
    double v = crossing.v;
    if (m_config.smearHits) {
      bool inside = false;
      for (unsigned attempt = 0; attempt < m_config.maxSmearAttempts && !inside;
           ++attempt) {
        u = crossing.u + module.sigmaU * normal(rng);
        v = crossing.v + module.sigmaV * normal(rng);
        inside = module.contains(u, v);
      }
      if (!inside) {
        return;  // DDPlanarDigiProcessor drops it
      }
    }
    Hit hit;
    hit.id = nextHitId++;
    hit.position = module.toGlobal(u, v);
    hit.detId = layer.id;
    hit.detId.module = module.module;
    hit.uAxis = module.uAxis();
    hit.vAxis = module.vAxis();
    hit.sigmaU = module.sigmaU;
    hit.sigmaV = module.sigmaV;
    out.hits.push_back(hit);
    HitTruth truth;
    truth.particleId = particleId;
    truth.position = truePosition;
    truth.momentum = momentum;
    truth.time =
        time + helix.pathLength(crossing.s - s) / (beta * constants::c);
    out.truth.push_back(truth);
    ++nHits;
  };
  bool metOne = false;
  for (const ModuleCrossing& crossing : scratch.crossings) {
    if (m_neighbourhood &&
        !m_neighbourhood->contains(layerIndex, crossing.module, layerPhi)) {
      continue;  // not looked up at this crossing: never reached
    }
    if (belowFloor && metOne) {
      break;
    }
    metOne = true;
    if (!supportCrossed && crossing.s > sSupport) {
      supportCrossed = true;
      if (interacts(supportX0, isHadron, rng)) {
        interacted = true;  // ends in the support, before this sensor
        return xOverX0;
      }
    }
    const PlanarModule& module = layout.modules()[crossing.module];
    Vector3 truePosition;
    Vector3 momentum;
    helix.positionAndMomentum(crossing.s, truePosition, momentum);
    const double cosIncidence =
        std::max(std::abs(momentum.normalized().dot(module.normal())),
                 m_config.minCosIncidence);
    double sensorX0 = module.thicknessX0 / cosIncidence;
    if (innerRing && truePosition.head<2>().squaredNorm() < ringRadius2 &&
        std::abs(module.center.z()) < std::abs(layerPosition.z())) {
      sensorX0 += m_config.diskInnerRingX0 / cosIncidence;
      innerRing = false;  // on the first such sensor crossed only
    }
    xOverX0 += sensorX0;
    recordHit(crossing, module, truePosition, momentum, cosIncidence);
    if (placed && interacts(sensorX0, isHadron, rng)) {
      interacted = true;  // ends after this sensor's hit
      return xOverX0;
    }
  }
  if (!supportCrossed && interacts(supportX0, isHadron, rng)) {
    interacted = true;  // ends in the support, after the sensors
  }
  return xOverX0;
}

}  // namespace conftrack
