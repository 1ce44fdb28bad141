#include "conftrack/geometry/MaterialInteractions.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace conftrack {

double highlandTheta0(double p, double beta, double charge, double xOverX0) {
  const double z2 = charge * charge;
  const double bracket =
      std::max(0.0, 1.0 + 0.038 * std::log(xOverX0 * z2 / (beta * beta)));
  return 13.6 * units::MeV / (beta * p) * std::abs(charge) *
         std::sqrt(xOverX0) * bracket;
}

double scatteringTheta0(double p, double beta, double charge, double xOverX0,
                        bool electron) {
  return electron ? rossiGreisenTheta0(p, charge, xOverX0)
                  : highlandTheta0(p, beta, charge, xOverX0);
}

double rossiGreisenTheta0(double p, double charge, double xOverX0) {
  const double bracket =
      std::max(0.0, 1.0 + 0.125 * std::log10(10.0 * xOverX0));
  return 17.5 * units::MeV / p * std::abs(charge) * std::sqrt(xOverX0) *
         bracket;
}

double densityEffect(double betaGamma, const IonisationMaterial& material) {
  const double x = std::log10(betaGamma);
  const double twoLn10 = 2.0 * std::numbers::ln10;
  if (x >= material.x1) {
    return twoLn10 * x - material.cBar;
  }
  if (x >= material.x0) {
    return twoLn10 * x - material.cBar +
           material.a * std::pow(material.x1 - x, material.k);
  }
  return material.delta0 * std::pow(10.0, 2.0 * (x - material.x0));
}

double maxEnergyTransfer(double betaGamma, double mass) {
  const double me = constants::kElectronMass;
  const double gamma = std::sqrt(1.0 + betaGamma * betaGamma);
  const double ratio = me / mass;
  return 2.0 * me * betaGamma * betaGamma /
         (1.0 + 2.0 * gamma * ratio + ratio * ratio);
}

double betheStoppingPower(double betaGamma, double mass, double charge,
                          const IonisationMaterial& material) {
  const double me = constants::kElectronMass;
  const double bg2 = betaGamma * betaGamma;
  const double beta2 = bg2 / (1.0 + bg2);
  const double wMax = maxEnergyTransfer(betaGamma, mass);
  const double i = material.meanExcitation;
  const double logTerm = 0.5 * std::log(2.0 * me * bg2 * wMax / (i * i));
  const double bracket =
      logTerm - beta2 - 0.5 * densityEffect(betaGamma, material);
  return constants::kBetheK * charge * charge * material.zOverA / beta2 *
         bracket;
}

double betheMeanEnergyLoss(double p, double mass, double charge, double xOverX0,
                           const IonisationMaterial& material) {
  const double massThickness = xOverX0 * material.radiationLength;
  return betheStoppingPower(p / mass, mass, charge, material) * massThickness;
}

double bremsstrahlungMeanLossFraction(double xOverX0) {
  return -std::expm1(-xOverX0);
}

double betheHeitlerShape(double xOverX0) { return xOverX0 / std::numbers::ln2; }

}  // namespace conftrack
