#pragma once

/// @file MaterialInteractions.hpp
/// Pure formulas for the interactions of a charged particle with a thin
/// layer of material: multiple-scattering width (Highland, Rossi-Greisen),
/// mean ionisation loss (Bethe with density effect) and the mean
/// bremsstrahlung loss of electrons (physics.md sections 4 and 5).
///
/// Functions of numbers only, independent of the simulator, so that the
/// track fit uses the same physics. Native units (GeV); mass thickness in
/// g/cm^2 and stopping powers in GeV cm^2/g, which have no unit constant.

#include "conftrack/core/Units.hpp"

namespace conftrack {

/// Constants of a material for the Bethe formula and the radiation length.
struct IonisationMaterial {
  /// <Z/A> [mol/g].
  double zOverA = 0.0;
  /// Mean excitation energy I [GeV].
  double meanExcitation = 0.0;
  /// Radiation length as mass thickness [g/cm^2].
  double radiationLength = 0.0;
  /// Density [g/cm^3].
  double density = 0.0;
  /// Sternheimer density-effect parameters (PDG): C-bar, x0, x1, a, k and
  /// delta0 (the value of delta at x0 for conductors; 0 for insulators).
  double cBar = 0.0;
  double x0 = 0.0;
  double x1 = 0.0;
  double a = 0.0;
  double k = 0.0;
  double delta0 = 0.0;
};

/// Silicon (physics.md section 5 table). The simulation uses it for all
/// tracker material (modules, carbon fibre, beam pipe): the material is
/// given only as x/X0, and converting with X0(Si) keeps the ionisation per
/// X0 of silicon (an approximation; carbon fibre and beryllium lose more
/// per X0, iron less).
inline constexpr IonisationMaterial kSilicon{
    0.49848, 173.0 * units::eV, 21.82,  2.329, 4.4355, 0.2015,
    2.8716,  0.14921,           3.2546, 0.14};

/// Nuclear interaction length over radiation length of silicon (PDG
/// atomic and nuclear properties: lambda_I = 108.4 g/cm^2, X0 = 21.82
/// g/cm^2), to turn the x/X0 of the tracker material into x/lambda_I.
inline constexpr double kSiliconInteractionOverRadiationLength = 108.4 / 21.82;

/// Radiation length of a material as a length [mm]: X0[g/cm^2] / density.
constexpr double radiationLengthMm(const IonisationMaterial& material) {
  return material.radiationLength / material.density * units::cm;
}

/// Highland width of the projected scattering angle [rad] (PDG RPP 2018
/// eq. 33.15, as ACTS computeMultipleScatteringTheta0):
///
///     theta0 = 13.6 MeV / (beta p) |z| sqrt(x/X0)
///              [1 + 0.038 ln(x z^2 / (X0 beta^2))].
///
/// @param p momentum [GeV]
/// @param beta velocity v/c
/// @param charge charge z [e]
/// @param xOverX0 traversed material (path length) in radiation lengths
/// @return theta0 [rad]; the bracket is clamped at 0 for tiny x/X0 where
///         the formula is invalid anyway (valid for 1e-3 < x/X0 < 100).
double highlandTheta0(double p, double beta, double charge, double xOverX0);

/// Rossi-Greisen width for electrons, as used by ACTS for e+-:
///
///     theta0 = 17.5 MeV / p |z| sqrt(x/X0) [1 + 0.125 log10(10 x/X0)].
///
/// @param p momentum [GeV]
/// @param charge charge [e]
/// @param xOverX0 traversed material in radiation lengths
/// @return theta0 [rad] (bracket clamped at 0)
double rossiGreisenTheta0(double p, double charge, double xOverX0);

/// The scattering width used by conftrack's simulation and fit alike:
/// Rossi-Greisen for electrons, Highland otherwise.
double scatteringTheta0(double p, double beta, double charge, double xOverX0,
                        bool electron);

/// Sternheimer density-effect correction delta(beta gamma) (PDG): with
/// x = log10(beta gamma), delta = 2 ln10 x - C + a (x1 - x)^k for
/// x0 <= x < x1, 2 ln10 x - C above x1, delta0 10^(2 (x - x0)) below x0.
double densityEffect(double betaGamma,
                     const IonisationMaterial& material = kSilicon);

/// Maximum energy transfer to an electron in one collision [GeV]:
/// W_max = 2 me b^2 g^2 / (1 + 2 g me/M + (me/M)^2).
double maxEnergyTransfer(double betaGamma, double mass);

/// Mean stopping power -<dE/dx> of the Bethe formula with density effect
/// (PDG RPP 2018 eq. 33.5, as ACTS computeEnergyLossBethe):
///
///     K z^2 (Z/A) / beta^2 [ 1/2 ln(2 me b^2 g^2 W_max / I^2) - beta^2
///                            - delta/2 ].
///
/// For electrons this is only an approximation (no Moller/Bhabha terms).
/// @param betaGamma p/M
/// @param mass particle mass M [GeV]
/// @param charge charge z [e]
/// @return mass stopping power [GeV cm^2/g]
double betheStoppingPower(double betaGamma, double mass, double charge,
                          const IonisationMaterial& material = kSilicon);

/// Mean ionisation energy loss in a thin layer [GeV]: the stopping power
/// at the incoming momentum times the mass thickness
/// x/X0 * X0[g/cm^2] (thin-layer approximation: the change of dE/dx
/// inside the layer is neglected).
/// @param p momentum before the layer [GeV]
/// @param mass particle mass [GeV]
/// @param charge charge [e]
/// @param xOverX0 traversed material (path length) in radiation lengths
double betheMeanEnergyLoss(double p, double mass, double charge, double xOverX0,
                           const IonisationMaterial& material = kSilicon);

/// Mean fraction of the energy an electron loses by bremsstrahlung in
/// x/X0 = t radiation lengths: 1 - exp(-t) (Bethe-Heitler, physics.md 5).
double bremsstrahlungMeanLossFraction(double xOverX0);

/// Shape parameter c = t/ln 2 of the Bethe-Heitler distribution: the
/// fraction z = E_after/E_before has -ln z ~ Gamma(c, 1), whose density
/// is f(z) = (-ln z)^(c-1) / Gamma(c) and whose mean is exp(-t).
double betheHeitlerShape(double xOverX0);

}  // namespace conftrack
