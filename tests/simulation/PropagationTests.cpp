// Helix propagation and surface crossings (physics.md section 2): the
// Helix class against the textbook formulas, the analytic cylinder/disk
// crossings and the cone root search against brute-force scans, and the
// material-free simulator against the analytic helix.

#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/geometry/Helix.hpp"
#include "conftrack/geometry/SurfaceNavigator.hpp"
#include "conftrack/simulation/Simulator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "IdealSimulatorConfig.hpp"

namespace conftrack {
namespace {

using namespace units;

constexpr double kPi = std::numbers::pi;

/// physics.md section 2, written out literally (independent of Helix).
Vector3 textbookHelix(const Vector3& x0, const Vector3& p, double charge,
                      double bz, double s) {
  const double pt = p.head<2>().norm();
  const double phi0 = std::atan2(p.y(), p.x());
  const double omega = charge * constants::kPtPerTeslaMm * bz / pt;
  const double tanLambda = p.z() / pt;
  return {x0.x() + (std::sin(phi0) - std::sin(phi0 - omega * s)) / omega,
          x0.y() - (std::cos(phi0) - std::cos(phi0 - omega * s)) / omega,
          x0.z() + s * tanLambda};
}

/// Momentum of given pT [GeV] at polar angle theta and azimuth phi.
Vector3 momentumOf(double pt, double theta, double phi) {
  return {pt * std::cos(phi), pt * std::sin(phi), pt / std::tan(theta)};
}

/// First s in (sMin, sMax] where f changes sign, by a fine scan and
/// bisection; infinity if none (reference for the crossing methods).
template <typename F>
double bruteForceRoot(F f, double sMin, double sMax, double step) {
  double a = sMin;
  double fa = f(a);
  while (a < sMax) {
    const double b = std::min(a + step, sMax);
    const double fb = f(b);
    if ((fa < 0) != (fb < 0)) {
      double lo = a;
      double hi = b;
      for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        if ((f(mid) < 0) == (fa < 0)) {
          lo = mid;
        } else {
          hi = mid;
        }
      }
      return 0.5 * (lo + hi);
    }
    a = b;
    fa = fb;
  }
  return Helix::kNoCrossing;
}

TEST(PropagationHelix, MatchesTextbookFormulas) {
  const Vector3 x0(3.0, -2.0, 5.0);
  for (double charge : {1.0, -1.0, 2.0}) {
    for (double pt : {0.05, 1.0, 100.0}) {
      const Vector3 p = momentumOf(pt, 1.1, 0.7);
      const Helix helix(x0, p, charge, 4.0 * T);
      for (double s : {0.0, 1.0, 50.0, 400.0, 3000.0}) {
        const Vector3 expected = textbookHelix(x0, p, charge, 4.0 * T, s);
        EXPECT_NEAR((helix.position(s) - expected).norm(), 0.0, 1e-9)
            << "q " << charge << " pT " << pt << " s " << s;
        // |p| and pz are conserved.
        EXPECT_NEAR(helix.momentum(s).norm(), p.norm(), 1e-12 * p.norm());
        EXPECT_DOUBLE_EQ(helix.momentum(s).z(), p.z());
      }
    }
  }
}

TEST(PropagationHelix, PositiveChargeTurnsClockwise) {
  // Along +x in B = +z: q v x B points to -y for q > 0 (physics.md 2).
  const Helix plus(Vector3::Zero(), Vector3(1, 0, 0), 1.0, 4.0 * T);
  const Helix minus(Vector3::Zero(), Vector3(1, 0, 0), -1.0, 4.0 * T);
  EXPECT_GT(plus.omega(), 0.0);
  EXPECT_LT(plus.position(10.0).y(), 0.0);
  EXPECT_GT(minus.position(10.0).y(), 0.0);
  EXPECT_LT(plus.momentum(10.0).y(), 0.0);
  // Radius for pT = 1 GeV at 4 T: 834 mm (physics.md 1).
  EXPECT_NEAR(1.0 / plus.omega(), 833.9, 0.1);
  EXPECT_NEAR(plus.period(), 2 * kPi / plus.omega(), 1e-9);
}

TEST(PropagationHelix, ReachableRadii) {
  const Vector3 x0(10.0, 5.0, 0.0);
  const Vector3 p = momentumOf(0.1, 1.0, 2.0);
  const Helix helix(x0, p, -1.0, 4.0 * T);
  double rMin = 1e9;
  double rMax = 0.0;
  for (int i = 0; i <= 100000; ++i) {
    const double r =
        helix.position(helix.period() * i / 100000.0).head<2>().norm();
    rMin = std::min(rMin, r);
    rMax = std::max(rMax, r);
  }
  EXPECT_NEAR(helix.minRadius(), rMin, 1e-3);
  EXPECT_NEAR(helix.maxRadius(), rMax, 1e-3);
  // Straight line: closest approach of the line, no maximum.
  const Helix line(x0, p, -1.0, 0.0);
  const Vector3 d = p.normalized();
  const double dca =
      std::abs(x0.x() * p.y() - x0.y() * p.x()) / p.head<2>().norm();
  EXPECT_NEAR(line.minRadius(), dca, 1e-12);
  EXPECT_TRUE(std::isinf(line.maxRadius()));
  (void)d;
}

TEST(PropagationCylinder, FirstCrossingAgainstScan) {
  // Helices from several start points (inside and outside the cylinder),
  // charges and momenta; the analytic crossing must be the first one a
  // fine scan of r(s) - R finds, and lie on the cylinder.
  const double radius = 60.0;
  int found = 0;
  for (double charge : {1.0, -1.0}) {
    for (double pt : {0.04, 0.2, 5.0}) {
      for (const Vector3& x0 :
           {Vector3(0, 0, 0), Vector3(20, -10, 3), Vector3(70, 5, -2)}) {
        for (double phi : {0.3, 2.5, -1.8}) {
          const Vector3 p = momentumOf(pt, 1.3, phi);
          const Helix helix(x0, p, charge, 4.0 * T);
          const double sMax = 2000.0;
          const double s =
              helix.nextCylinderCrossing(radius, -1e9, 1e9, 1e-6, sMax);
          const double ref = bruteForceRoot(
              [&](double t) {
                return helix.position(t).head<2>().norm() - radius;
              },
              1e-6, sMax, 0.05);
          if (std::isinf(ref)) {
            EXPECT_TRUE(std::isinf(s));
            continue;
          }
          ++found;
          EXPECT_NEAR(s, ref, 1e-7);
          EXPECT_NEAR(helix.position(s).head<2>().norm(), radius, 1e-9);
        }
      }
    }
  }
  EXPECT_GT(found, 20);
}

TEST(PropagationCylinder, LooperCrossesEveryTurn) {
  // pT = 50 MeV at 4 T: rho = 41.7 mm, reaches r = 83 mm; crosses r = 40
  // twice per turn. Successive calls starting after each crossing give
  // s_k + n * period.
  const Helix helix(Vector3::Zero(), momentumOf(0.05, 1.5, 0.2), 1.0, 4.0 * T);
  std::vector<double> crossings;
  double s = 1e-6;
  while (true) {
    s = helix.nextCylinderCrossing(40.0, -1e9, 1e9, s + 1e-6,
                                   3.0 * helix.period());
    if (std::isinf(s)) {
      break;
    }
    crossings.push_back(s);
  }
  ASSERT_EQ(crossings.size(), 6u);  // out and in, three turns
  for (std::size_t i = 2; i < crossings.size(); ++i) {
    EXPECT_NEAR(crossings[i] - crossings[i - 2], helix.period(), 1e-9);
  }
  // The z window selects a later turn: z advances by period * tanL.
  const double zLate = helix.position(crossings[4]).z();
  const double s2 =
      helix.nextCylinderCrossing(40.0, zLate - 1.0, zLate + 1.0, 1e-6, 1e9);
  EXPECT_NEAR(s2, crossings[4], 1e-9);
}

TEST(PropagationCylinder, StraightLineLimit) {
  // Omega = 0 exactly and Omega tiny agree with the straight line.
  const Vector3 x0(5.0, 7.0, -3.0);
  const Vector3 p = momentumOf(2.0, 0.9, 0.4);
  const Helix line(x0, p, 1.0, 0.0);
  const Helix almost(x0, p, 1.0, 1e-12 * T);
  const double sLine = line.nextCylinderCrossing(500.0, -1e9, 1e9, 0.0, 1e9);
  const double sAlmost =
      almost.nextCylinderCrossing(500.0, -1e9, 1e9, 0.0, 1e9);
  // |x0 + s t| = R for the unit transverse direction t.
  const Vector2 t = p.head<2>().normalized();
  const double b = x0.head<2>().dot(t);
  const double expected =
      -b + std::sqrt(b * b - x0.head<2>().squaredNorm() + 500.0 * 500.0);
  EXPECT_NEAR(sLine, expected, 1e-10);
  EXPECT_NEAR(sAlmost, expected, 1e-8);
  EXPECT_NEAR(almost.position(sAlmost).head<2>().norm(), 500.0, 1e-10);
  // A stiff track (10 TeV) far from the axis: still precise.
  const Helix stiff(x0, momentumOf(10000.0, 0.9, 0.4), 1.0, 4.0 * T);
  const double sStiff = stiff.nextCylinderCrossing(1400.0, -1e9, 1e9, 0, 1e9);
  EXPECT_NEAR(stiff.position(sStiff).head<2>().norm(), 1400.0, 1e-9);
}

TEST(PropagationDisk, CrossingAndRadialRange) {
  const Vector3 x0(1.0, 2.0, 3.0);
  const Vector3 p = momentumOf(0.5, 0.3, 1.0);
  const Helix helix(x0, p, -1.0, 4.0 * T);
  const double z = 800.0;
  const double s = helix.nextDiskCrossing(z, 0.0, 1e4, 0.0, 1e9);
  EXPECT_NEAR(s, (z - x0.z()) * std::tan(0.3), 1e-9);
  const Vector3 at = helix.position(s);
  EXPECT_NEAR(at.z(), z, 1e-9);
  const double r = at.head<2>().norm();
  EXPECT_TRUE(std::isinf(helix.nextDiskCrossing(z, r + 1.0, 1e4, 0.0, 1e9)));
  EXPECT_TRUE(std::isinf(helix.nextDiskCrossing(z, 0.0, r - 1.0, 0.0, 1e9)));
  // Behind the start, beyond sMax, or parallel: none.
  EXPECT_TRUE(std::isinf(helix.nextDiskCrossing(-z, 0.0, 1e4, 0.0, 1e9)));
  EXPECT_TRUE(std::isinf(helix.nextDiskCrossing(z, 0.0, 1e4, 0.0, s - 1.0)));
  const Helix flat(x0, momentumOf(0.5, kPi / 2, 1.0), -1.0, 4.0 * T);
  EXPECT_TRUE(std::isinf(flat.nextDiskCrossing(z, 0.0, 1e4, 0.0, 1e9)));
}

TEST(PropagationCone, FirstCrossingAgainstScan) {
  // CLICdet's beam-pipe cone (z 337..2080, r 31.4..237.6) and a steeper
  // one, crossed by stiff and looping helices, from inside and outside.
  struct ConeCase {
    double zMin, zMax, r1, r2;
  };
  int found = 0;
  for (const ConeCase& cone : {ConeCase{337.0, 2080.0, 31.4, 237.6},
                               ConeCase{500.0, 900.0, 300.0, 100.0}}) {
    const double slope = (cone.r2 - cone.r1) / (cone.zMax - cone.zMin);
    for (double charge : {1.0, -1.0}) {
      for (double pt : {0.03, 0.3, 3.0}) {
        for (double theta : {0.05, 0.15, 0.4}) {
          for (const Vector3& x0 : {Vector3(0, 0, 0), Vector3(40, 30, 600)}) {
            const Helix helix(x0, momentumOf(pt, theta, 0.8), charge, 4.0 * T);
            const double sMax = 3000.0;
            auto g = [&](double s) {
              const Vector3 at = helix.position(s);
              return at.head<2>().norm() -
                     (cone.r1 + (at.z() - cone.zMin) * slope);
            };
            auto inZ = [&](double s) {
              const double z = helix.position(s).z();
              return z >= cone.zMin && z <= cone.zMax;
            };
            const double s = helix.nextConeCrossing(cone.zMin, cone.zMax,
                                                    cone.r1, slope, 1e-6, sMax);
            // Reference: scan only inside the z window.
            double lo = (cone.zMin - x0.z()) * std::tan(theta);
            double hi = (cone.zMax - x0.z()) * std::tan(theta);
            lo = std::max(lo, 1e-6);
            hi = std::min(hi, sMax);
            double ref = Helix::kNoCrossing;
            if (lo < hi) {
              ref = bruteForceRoot(g, lo, hi, 0.01);
            }
            if (std::isinf(ref)) {
              EXPECT_TRUE(std::isinf(s)) << "s " << s;
              continue;
            }
            ++found;
            EXPECT_NEAR(s, ref, 1e-7);
            EXPECT_NEAR(g(s), 0.0, 1e-9);
            EXPECT_TRUE(inZ(s));
          }
        }
      }
    }
  }
  EXPECT_GT(found, 10);
}

TEST(PropagationNavigator, NearestCrossingMatchesBruteForce) {
  // The pruned search equals the minimum over all surfaces, for random
  // helices from random points in CLICdet (stiff, soft and looping).
  const Detector detector = loadDetector("clicdet");
  const SurfaceNavigator navigator(detector);
  const auto& surfaces = navigator.surfaces();
  ASSERT_EQ(surfaces.size(),
            detector.layers().size() + detector.passives().size());
  RandomEngine rng(77);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  int cones = 0;
  int found = 0;
  for (int i = 0; i < 3000; ++i) {
    const double r = 1400.0 * uniform(rng);
    const double phi = 2 * kPi * uniform(rng);
    const Vector3 x0(r * std::cos(phi), r * std::sin(phi),
                     -2200.0 + 4400.0 * uniform(rng));
    const double pt = std::exp(std::log(0.02) + std::log(500.0) * uniform(rng));
    const double theta =
        i % 3 == 0 ? 0.02 + 0.2 * uniform(rng) : 0.02 + 3.1 * uniform(rng);
    const Helix helix(x0, momentumOf(pt, theta, 2 * kPi * uniform(rng)),
                      uniform(rng) < 0.5 ? -1.0 : 1.0, detector.bz());
    const double sMax = 5000.0;
    const SurfaceCrossing nav = navigator.nextCrossing(helix, 1e-4, sMax);
    double best = sMax;
    std::uint32_t bestIndex = kInvalidIndex;
    for (std::uint32_t k = 0; k < surfaces.size(); ++k) {
      const NavigationSurface& c = surfaces[k];
      double s = Helix::kNoCrossing;
      switch (c.shape) {
        case SurfaceShape::eCylinder:
          s = helix.nextCylinderCrossing(c.r, c.zMin, c.zMax, 1e-4, sMax);
          break;
        case SurfaceShape::eDisk:
          s = helix.nextDiskCrossing(c.zMin, c.rMin, c.rMax, 1e-4, sMax);
          break;
        case SurfaceShape::eCone:
          s = helix.nextConeCrossing(c.zMin, c.zMax, c.coneR1, c.coneSlope,
                                     1e-4, sMax);
          break;
      }
      if (s < best) {
        best = s;
        bestIndex = k;
      }
    }
    EXPECT_EQ(nav.surface, bestIndex) << "helix " << i;
    if (bestIndex != kInvalidIndex) {
      ++found;
      EXPECT_NEAR(nav.s, best, 1e-12 * (1.0 + best));
      cones += surfaces[bestIndex].shape == SurfaceShape::eCone;
    }
  }
  EXPECT_GT(found, 2000);
  EXPECT_GT(cones, 10);
}

TEST(PropagationMaterial, GrazingCapBoundsOnlyTheTransversePath) {
  // The TrackML beam pipe (r = 19 mm, 0.8 mm Be): a track tangent to it in
  // the transverse plane traverses at most the chord sqrt(2 r t); a forward
  // track (theta = 2.7 deg) crossing it radially traverses t / sin(theta),
  // more than that chord allows a transverse track, and keeps it; a
  // forward track tangent to it traverses the chord over sin(theta).
  const Detector detector = loadDetector("trackml");
  const SurfaceNavigator navigator(detector);
  const NavigationSurface* pipe = nullptr;
  for (const NavigationSurface& s : navigator.surfaces()) {
    if (!s.isSensitive() && s.shape == SurfaceShape::eCylinder &&
        std::abs(s.r - 19.0 * mm) < 1e-9) {
      pipe = &s;
    }
  }
  ASSERT_NE(pipe, nullptr);
  const double t = pipe->thicknessX0;
  const double sinTheta = std::sin(2.7 * degree);
  ASSERT_GT(pipe->grazingCos, 1.5 * sinTheta);  // the case that matters
  const Vector3 onPipe(19.0 * mm, 0.0, 400.0 * mm);
  const double minCos = 0.01;
  EXPECT_NEAR(pipe->xOverX0(onPipe, Vector3(0.0, 1.0, 0.0), minCos),
              t / pipe->grazingCos, 1e-12);
  EXPECT_NEAR(
      pipe->xOverX0(onPipe, Vector3(sinTheta, 0.0, std::cos(2.7 * degree)),
                    minCos),
      t / sinTheta, 1e-12);
  EXPECT_NEAR(pipe->xOverX0(
                  onPipe, Vector3(0.0, sinTheta, std::cos(2.7 * degree)), 1e-3),
              t / (pipe->grazingCos * sinTheta), 1e-9);
  // ... unless minCosIncidence caps it first.
  EXPECT_NEAR(
      pipe->xOverX0(onPipe, Vector3(0.0, sinTheta, std::cos(2.7 * degree)),
                    minCos),
      t / minCos, 1e-9);
}

TEST(PropagationMaterial, ConeChordCapActsAcrossItsSlopeLine) {
  // CLICdet's steel beam-pipe cone: a track tangent to it azimuthally is
  // capped at the chord across its curvature; one running along its slope
  // line inside the wall is not (only minCosIncidence bounds it).
  const Detector detector = loadDetector("clicdet");
  const SurfaceNavigator navigator(detector);
  const NavigationSurface* cone = nullptr;
  for (const NavigationSurface& s : navigator.surfaces()) {
    if (s.shape == SurfaceShape::eCone && s.thicknessX0 > 0.1) {
      cone = &s;
    }
  }
  ASSERT_NE(cone, nullptr);
  ASSERT_GT(cone->grazingCos, 0.1);
  const double z = 0.5 * (cone->zMin + cone->zMax);
  const Vector3 onCone(cone->coneR1 + cone->coneSlope * (z - cone->zMin), 0.0,
                       z);
  const double minCos = 0.01;
  EXPECT_NEAR(cone->xOverX0(onCone, Vector3(0.0, 1.0, 0.0), minCos),
              cone->thicknessX0 / cone->grazingCos, 1e-12);
  const Vector3 alongSlope = Vector3(cone->coneSlope, 0.0, 1.0).normalized();
  EXPECT_NEAR(cone->xOverX0(onCone, alongSlope, minCos),
              cone->thicknessX0 / minCos, 1e-9);
}

TEST(PropagationNavigator, SoftForwardTrackCrossesBeamPipeCone) {
  // Straight tracks from the IP stay on one side of the steel beam-pipe
  // cone (its opening angle is 6.75 deg); a soft forward track, whose
  // radius oscillates between 0 and 2 rho = 167 mm, crosses it.
  const Detector detector = loadDetector("clicdet");
  const SurfaceNavigator navigator(detector);
  const Helix helix(Vector3::Zero(), momentumOf(0.1, 10.0 * degree, 0.3), 1.0,
                    detector.bz());
  std::vector<std::string> names;
  double s = 0.0;
  for (int i = 0; i < 50; ++i) {
    const SurfaceCrossing next = navigator.nextCrossing(helix, s + 1e-4, 1e5);
    if (!next.found() || std::abs(helix.position(next.s).z()) > 2306.0) {
      break;
    }
    s = next.s;
    const NavigationSurface& c = navigator.surfaces()[next.surface];
    names.push_back(
        c.isSensitive()
            ? detector.layers()[c.layer].name
            : detector.passives()[next.surface - detector.layers().size()]
                  .name);
  }
  EXPECT_NE(std::find(names.begin(), names.end(), "BeamPipeCone_pos"),
            names.end());
}

Particle makeParticle(std::uint64_t id, std::int32_t pdg, double charge,
                      const Vector3& vertex, const Vector3& momentum) {
  Particle particle;
  particle.id = id;
  particle.pdg = pdg;
  particle.charge = charge;
  particle.vertex = vertex;
  particle.momentum = momentum;
  return particle;
}

TEST(PropagationSimulator, HitsOnAnalyticHelixWithoutMaterial) {
  const Detector detector = loadDetector("clicdet");
  const Simulator simulator(detector, test::idealSimulatorConfig());
  struct Case {
    double charge;
    double pt;
    double theta;
    Vector3 vertex;
    const char* what;
  };
  const std::vector<Case> cases = {
      {1.0, 10.0, 1.5, Vector3::Zero(), "stiff central"},
      {-1.0, 1.0, 1.0, Vector3(0.01, -0.02, 5.0), "1 GeV, 57 deg"},
      {1.0, 0.5, 0.35, Vector3::Zero(), "forward: disks"},
      {-1.0, 0.3, 2.8, Vector3(0.0, 0.0, -10.0), "backward: disks"},
      {2.0, 2.0, 0.8, Vector3(3.0, 4.0, 20.0), "charge 2, displaced"},
      {1.0, 0.05, 1.54, Vector3::Zero(), "looper"},
  };
  std::uint64_t id = 1;
  for (const Case& c : cases) {
    const Vector3 p = momentumOf(c.pt, c.theta, 0.4 + id);
    Event event;
    RandomEngine rng(42);
    simulator.simulate({makeParticle(id, 211 * static_cast<int>(c.charge),
                                     c.charge, c.vertex, p)},
                       rng, event);
    ASSERT_GE(event.hits.size(), 3u) << c.what;
    std::map<std::uint32_t, int> perLayer;
    double lastS = 0.0;
    for (std::size_t i = 0; i < event.hits.size(); ++i) {
      const HitTruth& truth = event.truth[i];
      const Hit& hit = event.hits[i];
      // Without smearing the measured position is the true one.
      EXPECT_EQ(hit.position, truth.position);
      // s from z (tanL != 0 in all cases), then x, y from physics.md.
      const double s = (truth.position.z() - c.vertex.z()) * std::tan(c.theta);
      EXPECT_GT(s, lastS) << c.what;
      lastS = s;
      const Vector3 expected = textbookHelix(c.vertex, p, c.charge, 4.0, s);
      EXPECT_NEAR((truth.position - expected).norm(), 0.0, 1e-9) << c.what;
      // Momentum is the tangent of the helix, |p| unchanged.
      EXPECT_NEAR(truth.momentum.norm(), p.norm(), 1e-12 * p.norm());
      // On the surface of its layer.
      const auto layerIndex = detector.findLayer(hit.detId);
      ASSERT_TRUE(layerIndex.has_value());
      const SensitiveLayer& layer = detector.layers()[*layerIndex];
      if (layer.isDisk()) {
        EXPECT_NEAR(truth.position.z(), layer.z(), 1e-9);
      } else {
        EXPECT_NEAR(truth.position.head<2>().norm(), layer.r, 1e-9);
      }
      // Time of flight along the 3-D path (beta from the pion mass).
      const double path = s / std::sin(c.theta);
      const double e = std::hypot(p.norm(), constants::kPionMass);
      EXPECT_NEAR(truth.time, path * e / (p.norm() * constants::c), 1e-9);
      ++perLayer[*layerIndex];
    }
    if (std::string(c.what) == "looper") {
      // Crosses each vertex layer out and in on every turn, for 3 turns.
      EXPECT_GE(perLayer.size(), 6u);
      for (const auto& [layer, n] : perLayer) {
        EXPECT_GE(n, 5) << detector.layers()[layer].name;
      }
    }
    if (c.theta < 0.5 || c.theta > 2.6) {
      int disks = 0;
      for (const auto& [layer, n] : perLayer) {
        disks += detector.layers()[layer].isDisk() ? n : 0;
      }
      EXPECT_GE(disks, 3) << c.what;
    }
    ++id;
  }
}

TEST(PropagationSimulator, LooperStopsAfterMaxTurns) {
  const Detector detector = loadDetector("clicdet");
  for (double turns : {1.0, 2.0, 4.0}) {
    Simulator::Config config = test::idealSimulatorConfig();
    config.maxTurns = turns;
    const Simulator simulator(detector, config);
    Event event;
    RandomEngine rng(1);
    // pT 50 MeV, theta 89.9 deg: stays in the vertex barrel; 12 crossings
    // of its 6 layers per turn.
    simulator.simulate({makeParticle(1, 211, 1.0, Vector3::Zero(),
                                     momentumOf(0.05, 1.569, 0.0))},
                       rng, event);
    EXPECT_EQ(event.hits.size(), static_cast<std::size_t>(12 * turns));
  }
}

TEST(PropagationSimulator, StartsAtDisplacedVertexAndSkipsOutside) {
  const Detector detector = loadDetector("clicdet");
  const Simulator simulator(detector, test::idealSimulatorConfig());
  Event event;
  RandomEngine rng(3);
  // Produced between the inner and outer tracker, moving outwards: only
  // outer-tracker barrel hits (and no hit of the layers inside).
  const Vector3 vertex(600.0, 0.0, 0.0);
  simulator.simulate(
      {makeParticle(1, 13, -1.0, vertex, momentumOf(20.0, 1.55, 0.0)),
       makeParticle(2, 13, -1.0, Vector3(1600.0, 0.0, 0.0),
                    momentumOf(20.0, 1.55, 0.0))},
      rng, event);
  ASSERT_EQ(event.hits.size(), 3u);
  for (const Hit& hit : event.hits) {
    EXPECT_EQ(detector.subdetectors()[hit.detId.subdetector].name,
              "OuterTrackerBarrel");
  }
  ASSERT_EQ(event.particles.size(), 2u);
  EXPECT_EQ(event.particles[0].nHits, 3u);
  EXPECT_EQ(event.particles[1].nHits, 0u);
}

}  // namespace
}  // namespace conftrack
