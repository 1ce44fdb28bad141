#pragma once

// Synthetic detectors and hits for finder unit tests (no simulation).

#include "conftrack/core/Hit.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace conftrack::test {

/// Eight barrel layers (one subdetector "Barrel"; at `radii` [mm]) and a
/// disk layer set, each of xOverX0 radiation lengths.
inline Detector barrelDetector(double xOverX0 = 0.001,
                               const std::vector<double>& radii = {
                                   30.0, 40.0, 50.0, 65.0, 80.0, 100.0, 120.0,
                                   150.0}) {
  const std::string material = "x_over_x0 = " + std::to_string(xOverX0) + "\n";
  std::string text = R"([detector]
name = "Synthetic"
bz_T = 4.0
envelope_r_mm = 1000.0
envelope_z_mm = 1000.0
[[subdetector]]
name = "Barrel"
kind = "barrel"
)";
  for (double r : radii) {
    text += "[[subdetector.layer]]\nname = \"L" + std::to_string(int(r)) +
            "\"\nr_mm = " + std::to_string(r) + "\nhalf_z_mm = 500.0\n" +
            material +
            "sigma_rphi_um = 5.0\nsigma_z_um = 5.0\nn_phi_modules = 64\n";
  }
  text += R"([[subdetector]]
name = "Endcap"
kind = "endcap"
[[subdetector.layer]]
name = "D0"
z_mm = 600.0
r_min_mm = 10.0
r_max_mm = 300.0
)" + material +
          R"(sigma_rphi_um = 5.0
sigma_r_um = 50.0
)";
  return parseDetector(text, "synthetic.toml");
}

/// One build step over the "Barrel" of barrelDetector() with loose angles
/// and chi2 (five hits).
inline FinderConfig oneBuildStep() {
  FinderConfig cfg;
  FindingStep s;
  s.name = "build";
  s.collections = {0};
  s.build = true;
  s.maxCellAngle = 0.05;
  s.maxCellAngleRZ = 0.05;
  s.chi2Cut = 50.0;
  s.minHits = 5;
  s.maxDistance = 0.05;
  s.radialSearch = true;
  cfg.steps.push_back(s);
  return cfg;
}

/// A hit on barrel layer `layer` of barrelDetector() at (x, y, z).
inline Hit barrelHit(const Detector& det, std::uint16_t layer, double x,
                     double y, double z, std::uint64_t id) {
  Hit h;
  h.id = id;
  h.position = Vector3(x, y, z);
  const SensitiveLayer& l = det.layers()[layer];
  h.detId = l.id;
  h.detId.module = l.moduleAt(h.position);
  l.localAxes(h.position, h.uAxis, h.vAxis);
  h.sigmaU = l.sigmaU;
  h.sigmaV = l.sigmaV;
  return h;
}

/// Hits of a helix from the origin (through (0,0,0)) on the barrel layers:
/// circle of radius rho, initial azimuth phi0, charge sign q, dip tanL.
inline std::vector<Hit> helixHits(const Detector& det, double rho, double phi0,
                                  int q, double tanL, std::uint64_t firstId,
                                  double d0 = 0.0) {
  std::vector<Hit> hits;
  // Positive charges turn clockwise (physics.md 2).
  double omega = q / rho;
  double x0 = -d0 * std::sin(phi0);
  double y0 = d0 * std::cos(phi0);
  for (std::uint16_t l = 0; l < 8; ++l) {
    double rl = det.layers()[l].r;
    // Solve |P(s)| = rl by bisection on s in the first half turn.
    auto pos = [&](double s) {
      double x = x0 + (std::sin(phi0) - std::sin(phi0 - omega * s)) / omega;
      double y = y0 - (std::cos(phi0) - std::cos(phi0 - omega * s)) / omega;
      return Vector3(x, y, s * tanL);
    };
    double lo = 0.0;
    double hi = M_PI * rho;
    if (pos(hi).head<2>().norm() < rl) {
      break;
    }
    for (int it = 0; it < 200; ++it) {
      double mid = 0.5 * (lo + hi);
      (pos(mid).head<2>().norm() < rl ? lo : hi) = mid;
    }
    Vector3 p = pos(0.5 * (lo + hi));
    hits.push_back(barrelHit(det, l, p.x(), p.y(), p.z(), firstId + l));
  }
  return hits;
}

}  // namespace conftrack::test
