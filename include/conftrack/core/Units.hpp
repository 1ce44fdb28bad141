#pragma once

/// @file Units.hpp
/// The one place where conftrack's units and physical constants are defined.
///
/// Native units: mm, GeV, tesla, ns, rad, elementary charge. A quantity is
/// stored as a plain double in native units. Multiply by a unit constant when
/// a value enters (`3 * units::um`), divide when it leaves (`x / units::um`).
/// Conversions happen only at the edges: file readers, CLI, printers.

#include <numbers>

namespace conftrack {

namespace units {
// Length
inline constexpr double mm = 1.0;
inline constexpr double um = 1e-3 * mm;
inline constexpr double nm = 1e-6 * mm;
inline constexpr double cm = 10.0 * mm;
inline constexpr double m = 1000.0 * mm;
// Energy, momentum, mass (c = 1 in momenta and masses)
inline constexpr double GeV = 1.0;
inline constexpr double MeV = 1e-3 * GeV;
inline constexpr double keV = 1e-6 * GeV;
inline constexpr double eV = 1e-9 * GeV;
inline constexpr double TeV = 1e3 * GeV;
// Magnetic field
inline constexpr double T = 1.0;
// Time
inline constexpr double ns = 1.0;
inline constexpr double ps = 1e-3 * ns;
// Angles
inline constexpr double rad = 1.0;
inline constexpr double mrad = 1e-3 * rad;
inline constexpr double degree = std::numbers::pi / 180.0 * rad;
}  // namespace units

namespace constants {
/// Speed of light in mm/ns.
inline constexpr double c = 299.792458 * units::mm / units::ns;
/// pT = kPtPerTeslaMm * |q| * B * R: the momentum-radius relation for a unit
/// charge (0.299792458 GeV/(T m), here per mm). physics.md section 1.
inline constexpr double kPtPerTeslaMm =
    0.299792458e-3 * units::GeV / (units::T * units::mm);

// Particle masses (PDG).
inline constexpr double kElectronMass = 0.51099895 * units::MeV;
inline constexpr double kMuonMass = 105.6583755 * units::MeV;
inline constexpr double kPionMass = 139.57039 * units::MeV;
inline constexpr double kKaonMass = 493.677 * units::MeV;
inline constexpr double kProtonMass = 938.27208816 * units::MeV;

/// K = 4 pi N_A r_e^2 m_e c^2 of the Bethe formula, in GeV cm^2/mol.
inline constexpr double kBetheK = 0.307075 * units::MeV;
}  // namespace constants

}  // namespace conftrack
