#pragma once

/// @file GeneratorFactory.hpp
/// Named samples and TOML configuration of the event generators.
///
/// TOML keys carry their unit as a suffix and are converted to native
/// units on reading. Each read*Config() reads only its own keys from the
/// table (all optional, defaults as in the Config structs) and leaves
/// rejectUnknownKeys() to the caller; makeGenerator() / makeOverlay() call
/// it. Errors are InputError "file:line: key 'x': problem".
///
/// Particle gun keys:
///   particle = "mu-" | "mu+" | "e-" | "e+" | "pi-" | "pi+" | "K-" | "K+" |
///              "p" | "pbar"            (or pdg = 13; not both)
///   random_charge = false, multiplicity = 1
///   p_GeV = 10 | p_min_GeV + p_max_GeV | pt_GeV | pt_min_GeV + pt_max_GeV
///   log_momentum = false
///   theta_deg | theta_min_deg + theta_max_deg (theta_sampling =
///              "cos_theta" | "theta") | eta_min + eta_max
///   phi_min_deg = -180, phi_max_deg = 180
///   vertex_mm = [0, 0, 0] (position of the gun's luminous region, a
///              point by default), r_min_mm = 0, r_max_mm = 0 (displacement)
/// ttbar / bb500 keys (defaults from the sample):
///   sqrt_s_GeV, top_mass_GeV, w_mass_GeV, b_mass_GeV, br_w_hadrons,
///   br_w_enu, br_w_munu, br_w_taunu, nch_a, nch_b, nch_c, pi0_per_charged,
///   k0_per_charged, lambda_per_charged, kaon_fraction, proton_fraction,
///   frag_exponent, frag_p_min_GeV, kt_sigma_GeV, b_frag_min, b_frag_max,
///   b_ctau_mm, b_decay_charged_mean, b_decay_pi0_mean,
///   b_semileptonic_fraction, b_decay_kaon_fraction,
///   beam_sigma_z_mm = 0.044 (sigma z of the luminous region, clic3tev)
/// HepMC keys: path (relative to the TOML file's folder), max_radius_mm
/// gamma gamma overlay keys:
///   bunch_crossings = 30, physics_bx = 10, bunch_spacing_ns = 0.5,
///   events_per_bx = 3.2, mean_charged = 7.7, pt_mean_GeV = 0.35,
///   pt_min_GeV = 0.02, pt_max_GeV = 5, eta_max = 3, kaon_fraction = 0,
///   proton_fraction = 0, beam_sigma_z_mm = 0.044 (as for ttbar)
/// luminous region keys (a [luminous_region] table of the generator file,
/// for the signal and the overlay; docs/luminous-region.md):
///   preset = "clic3tev" | "fccee-z" | "fccee-ttbar" | "hllhc" |
///            "trackml-kaggle" | "point" (fields not given below are the
///            preset's, or 0 without a preset)
///   x_mm, y_mm, z_mm, t_ns (mean), sigma_x_mm, sigma_y_mm, sigma_z_mm,
///   sigma_t_ns (Gaussian widths)
/// The generators' own keys vertex_mm (gun) and beam_sigma_z_mm (ttbar,
/// overlay) set their region only when the sample has none; with one they
/// are an error.

#include "conftrack/core/ConfigTable.hpp"
#include "conftrack/simulation/LuminousRegion.hpp"
#include "conftrack/simulation/generators/EventGenerator.hpp"
#include "conftrack/simulation/generators/GammaGammaOverlay.hpp"
#include "conftrack/simulation/generators/HepMC3Generator.hpp"
#include "conftrack/simulation/generators/ParticleGun.hpp"
#include "conftrack/simulation/generators/TtbarGenerator.hpp"

#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace conftrack {

/// Reads a [luminous_region] table (keys in the file comment) and rejects
/// unknown keys.
LuminousRegion::Config readLuminousRegionConfig(const ConfigTable& table);

/// Refuses a generator's own region key `key` (vertex_mm, beam_sigma_z_mm)
/// when the sample's luminous region is set elsewhere (`regionSet`):
/// InputError at the key, naming `replacement`, the [luminous_region] key
/// to use instead.
void rejectRegionAlias(const ConfigTable& table, std::string_view key,
                       std::string_view replacement, bool regionSet);

/// Reads particle-gun keys (see the file comment).
ParticleGun::Config readParticleGunConfig(const ConfigTable& table);

/// Reads ttbar/bbbar keys on top of `defaults` (ttbar3TeV() or bb500()).
TtbarGenerator::Config readTtbarConfig(const ConfigTable& table,
                                       const TtbarGenerator::Config& defaults);

/// Reads HepMC keys; a relative `path` is taken relative to the folder of
/// the TOML file the table comes from.
HepMC3Generator::Config readHepMC3Config(const ConfigTable& table);

/// Reads gamma gamma overlay keys on top of `defaults`.
GammaGammaOverlay::Config readGammaGammaOverlayConfig(
    const ConfigTable& table, const GammaGammaOverlay::Config& defaults = {});

/// A generator for a named sample with default settings: "muons" or "gun"
/// (ParticleGun defaults), "ttbar3tev", "bb500", "hepmc:<path>", with the
/// luminous region `region` if set (else the generator's default). Throws
/// InputError for an unknown name.
std::unique_ptr<EventGenerator> makeGenerator(
    const std::string& sample,
    const std::optional<LuminousRegion::Config>& region = std::nullopt);

/// A generator from a table with key `sample` ("gun", "muons",
/// "ttbar3tev", "bb500", "hepmc") and that sample's keys, with the
/// luminous region `region` if set; rejects unknown keys, and the
/// generator's own region keys when `region` is set.
std::unique_ptr<EventGenerator> makeGenerator(
    const ConfigTable& table,
    const std::optional<LuminousRegion::Config>& region = std::nullopt);

/// The gamma gamma overlay from a table of overlay keys, with the luminous
/// region `region` if set; rejects unknown keys, and beam_sigma_z_mm when
/// `region` is set.
std::unique_ptr<GammaGammaOverlay> makeOverlay(
    const ConfigTable& table,
    const std::optional<LuminousRegion::Config>& region = std::nullopt);

}  // namespace conftrack
