#include "conftrack/simulation/generators/GeneratorFactory.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/core/Units.hpp"

#include <filesystem>
#include <limits>
#include <optional>
#include <string_view>

namespace conftrack {

namespace {

using namespace conftrack::units;

/// Builds the generator from a config read from `table`; validation errors
/// of the constructor are reported at the table's location.
template <typename Generator>
std::unique_ptr<Generator> construct(const ConfigTable& table,
                                     const typename Generator::Config& cfg) {
  try {
    return std::make_unique<Generator>(cfg);
  } catch (const InputError& e) {
    table.fail("", e.what());
  }
}

/// Reads `key` (a double in the key's unit) into `target` if present.
void readIf(const ConfigTable& t, std::string_view key, double unit,
            double& target, Range range = {}) {
  if (t.has(key)) {
    target = t.getDouble(key, range) * unit;
  }
}

/// Range of a luminous-region width in mm.
Range sigmaRange() {
  return Range::closed(0.0, LuminousRegion::kMaxLength / mm);
}

}  // namespace

void rejectRegionAlias(const ConfigTable& t, std::string_view key,
                       std::string_view replacement, bool regionSet) {
  if (regionSet && t.has(key)) {
    t.fail(key,
           "the luminous region is already set ([luminous_region] or "
           "--luminous-region/--beam-sigma-z); give " +
               std::string(replacement) + " there instead");
  }
}

LuminousRegion::Config readLuminousRegionConfig(const ConfigTable& t) {
  LuminousRegion::Config c;
  if (t.has("preset")) {
    const std::string name = t.getString("preset");
    const LuminousRegion::Preset* preset = LuminousRegion::findPreset(name);
    if (preset == nullptr) {
      t.fail("preset", "unknown preset '" + name + "' (use " +
                           LuminousRegion::presetNames() + ")");
    }
    c = preset->config;
  }
  const Range position = Range::closed(-LuminousRegion::kMaxLength / mm,
                                       LuminousRegion::kMaxLength / mm);
  const Range time = Range::closed(-LuminousRegion::kMaxTime / ns,
                                   LuminousRegion::kMaxTime / ns);
  if (t.has("x_mm")) {
    c.position.x() = t.getDouble("x_mm", position) * mm;
  }
  if (t.has("y_mm")) {
    c.position.y() = t.getDouble("y_mm", position) * mm;
  }
  if (t.has("z_mm")) {
    c.position.z() = t.getDouble("z_mm", position) * mm;
  }
  readIf(t, "t_ns", ns, c.time, time);
  readIf(t, "sigma_x_mm", mm, c.sigmaX, sigmaRange());
  readIf(t, "sigma_y_mm", mm, c.sigmaY, sigmaRange());
  readIf(t, "sigma_z_mm", mm, c.sigmaZ, sigmaRange());
  readIf(t, "sigma_t_ns", ns, c.sigmaT,
         Range::closed(0.0, LuminousRegion::kMaxTime / ns));
  t.rejectUnknownKeys();
  return c;
}

ParticleGun::Config readParticleGunConfig(const ConfigTable& t) {
  ParticleGun::Config c;
  if (t.has("particle") && t.has("pdg")) {
    t.fail("pdg", "give either 'particle' or 'pdg', not both");
  }
  if (t.has("particle")) {
    const std::string name = t.getString("particle");
    const auto code = particleGunPdgFromName(name);
    if (!code) {
      t.fail("particle", "unknown particle '" + name +
                             "' (use mu-, mu+, e-, e+, pi-, pi+, K-, K+, p, "
                             "pbar)");
    }
    c.pdg = *code;
  }
  if (t.has("pdg")) {
    c.pdg =
        static_cast<std::int32_t>(t.getInt("pdg", Range::closed(-1e9, 1e9)));
  }
  c.randomCharge = t.getBool("random_charge", c.randomCharge);
  c.multiplicity = static_cast<std::size_t>(
      t.getInt("multiplicity", 1, Range::closed(1, 1e6)));

  // Momentum: exactly one of the four forms.
  const bool pFixed = t.has("p_GeV");
  const bool pRange = t.has("p_min_GeV") || t.has("p_max_GeV");
  const bool ptFixed = t.has("pt_GeV");
  const bool ptRange = t.has("pt_min_GeV") || t.has("pt_max_GeV");
  if (int(pFixed) + int(pRange) + int(ptFixed) + int(ptRange) > 1) {
    t.fail(pFixed ? "p_GeV" : (pRange ? "p_min_GeV" : "pt_GeV"),
           "give one of p_GeV, p_min_GeV/p_max_GeV, pt_GeV, "
           "pt_min_GeV/pt_max_GeV");
  }
  if (pFixed || ptFixed) {
    const char* key = pFixed ? "p_GeV" : "pt_GeV";
    c.momentumMin = c.momentumMax = t.getDouble(key, Range::positive()) * GeV;
    c.usePt = ptFixed;
  } else if (pRange || ptRange) {
    const char* lo = pRange ? "p_min_GeV" : "pt_min_GeV";
    const char* hi = pRange ? "p_max_GeV" : "pt_max_GeV";
    c.momentumMin = t.getDouble(lo, Range::positive()) * GeV;
    c.momentumMax =
        t.getDouble(hi, Range{c.momentumMin / GeV, Range{}.max}) * GeV;
    c.usePt = ptRange;
  }
  c.logMomentum = t.getBool("log_momentum", c.logMomentum);

  // Polar angle: fixed theta, theta range, or eta range.
  const bool thetaFixed = t.has("theta_deg");
  const bool thetaRange = t.has("theta_min_deg") || t.has("theta_max_deg");
  const bool etaRange = t.has("eta_min") || t.has("eta_max");
  if (int(thetaFixed) + int(thetaRange) + int(etaRange) > 1) {
    t.fail(thetaFixed ? "theta_deg" : "theta_min_deg",
           "give one of theta_deg, theta_min_deg/theta_max_deg, "
           "eta_min/eta_max");
  }
  const Range openTheta{0.0, 180.0, false, false};
  if (thetaFixed) {
    c.thetaMin = c.thetaMax = t.getDouble("theta_deg", openTheta) * degree;
    c.angleSampling = ParticleGun::AngleSampling::eUniformTheta;
  } else if (thetaRange) {
    c.thetaMin = t.getDouble("theta_min_deg", openTheta) * degree;
    c.thetaMax = t.getDouble("theta_max_deg",
                             Range{c.thetaMin / degree, 180.0, true, false}) *
                 degree;
  } else if (etaRange) {
    c.angleSampling = ParticleGun::AngleSampling::eUniformEta;
    c.etaMin = t.getDouble("eta_min", Range::closed(-20, 20));
    c.etaMax = t.getDouble("eta_max", Range::closed(c.etaMin, 20));
  }
  if (t.has("theta_sampling")) {
    if (!thetaRange) {
      t.fail("theta_sampling", "only with theta_min_deg/theta_max_deg");
    }
    const std::string s = t.getString("theta_sampling");
    if (s == "cos_theta") {
      c.angleSampling = ParticleGun::AngleSampling::eUniformCosTheta;
    } else if (s == "theta") {
      c.angleSampling = ParticleGun::AngleSampling::eUniformTheta;
    } else {
      t.fail("theta_sampling", "expected \"cos_theta\" or \"theta\"");
    }
  }
  c.phiMin =
      t.getDouble("phi_min_deg", -180.0, Range::closed(-360, 360)) * degree;
  c.phiMax =
      t.getDouble("phi_max_deg", 180.0, Range::closed(c.phiMin / degree, 360)) *
      degree;
  if (t.has("vertex_mm")) {
    // The position of the gun's luminous region (a point by default).
    const Range inside = Range::closed(-LuminousRegion::kMaxLength / mm,
                                       LuminousRegion::kMaxLength / mm);
    const auto v = t.getDoubleArray("vertex_mm", inside);
    if (v.size() != 3) {
      t.fail("vertex_mm", "expected [x, y, z]");
    }
    c.luminousRegion.position = Vector3(v[0], v[1], v[2]) * mm;
  }
  readIf(t, "r_min_mm", mm, c.rMin, Range::nonNegative());
  readIf(t, "r_max_mm", mm, c.rMax, Range{c.rMin / mm, Range{}.max});
  // Cross-field checks (e.g. the PDG code) at the table's location.
  construct<ParticleGun>(t, c);
  return c;
}

TtbarGenerator::Config readTtbarConfig(const ConfigTable& t,
                                       const TtbarGenerator::Config& defaults) {
  TtbarGenerator::Config c = defaults;
  const Range pos = Range::positive();
  const Range nonNeg = Range::nonNegative();
  const Range fraction = Range::closed(0, 1);
  readIf(t, "sqrt_s_GeV", GeV, c.sqrtS, pos);
  readIf(t, "top_mass_GeV", GeV, c.topMass, pos);
  readIf(t, "w_mass_GeV", GeV, c.wMass, pos);
  readIf(t, "b_mass_GeV", GeV, c.bMass, pos);
  readIf(t, "br_w_hadrons", 1.0, c.brWToHadrons, fraction);
  readIf(t, "br_w_enu", 1.0, c.brWToENu, fraction);
  readIf(t, "br_w_munu", 1.0, c.brWToMuNu, fraction);
  readIf(t, "br_w_taunu", 1.0, c.brWToTauNu, fraction);
  readIf(t, "nch_a", 1.0, c.nchA);
  readIf(t, "nch_b", 1.0, c.nchB);
  readIf(t, "nch_c", 1.0, c.nchC);
  readIf(t, "pi0_per_charged", 1.0, c.pi0PerCharged, nonNeg);
  readIf(t, "k0_per_charged", 1.0, c.k0PerCharged, nonNeg);
  readIf(t, "lambda_per_charged", 1.0, c.lambdaPerCharged, nonNeg);
  readIf(t, "kaon_fraction", 1.0, c.kaonFraction, fraction);
  readIf(t, "proton_fraction", 1.0, c.protonFraction, fraction);
  readIf(t, "frag_exponent", 1.0, c.fragmentationExponent, nonNeg);
  readIf(t, "frag_p_min_GeV", GeV, c.fragmentationPMin, pos);
  readIf(t, "kt_sigma_GeV", GeV, c.ktSigma, nonNeg);
  readIf(t, "b_frag_min", 1.0, c.bFragmentationMin, fraction);
  readIf(t, "b_frag_max", 1.0, c.bFragmentationMax, fraction);
  readIf(t, "b_ctau_mm", mm, c.bHadronCTau, nonNeg);
  readIf(t, "b_decay_charged_mean", 1.0, c.bDecayChargedMean, nonNeg);
  readIf(t, "b_decay_pi0_mean", 1.0, c.bDecayPi0Mean, nonNeg);
  readIf(t, "b_semileptonic_fraction", 1.0, c.bSemileptonicFraction, fraction);
  readIf(t, "b_decay_kaon_fraction", 1.0, c.bDecayKaonFraction, fraction);
  readIf(t, "beam_sigma_z_mm", mm, c.luminousRegion.sigmaZ, sigmaRange());
  construct<TtbarGenerator>(t, c);
  return c;
}

HepMC3Generator::Config readHepMC3Config(const ConfigTable& t) {
  HepMC3Generator::Config c;
  std::filesystem::path path = t.getString("path");
  if (path.empty()) {
    t.fail("path", "empty");
  }
  if (path.is_relative() && !t.file().empty()) {
    path = std::filesystem::path(t.file()).parent_path() / path;
  }
  c.path = path.string();
  readIf(t, "max_radius_mm", mm, c.maxProductionRadius, Range::positive());
  return c;
}

GammaGammaOverlay::Config readGammaGammaOverlayConfig(
    const ConfigTable& t, const GammaGammaOverlay::Config& defaults) {
  GammaGammaOverlay::Config c = defaults;
  c.numBunchCrossings = static_cast<std::size_t>(
      t.getInt("bunch_crossings", 30, Range::closed(1, 100000)));
  c.physicsBunchCrossing = static_cast<std::size_t>(
      t.getInt("physics_bx", 10,
               Range::closed(1, static_cast<double>(c.numBunchCrossings))));
  const Range nonNeg = Range::nonNegative();
  readIf(t, "bunch_spacing_ns", ns, c.bunchSpacing, nonNeg);
  readIf(t, "events_per_bx", 1.0, c.eventsPerBunchCrossing, nonNeg);
  readIf(t, "mean_charged", 1.0, c.meanCharged, nonNeg);
  readIf(t, "pt_mean_GeV", GeV, c.ptMean, Range::positive());
  readIf(t, "pt_min_GeV", GeV, c.ptMin, Range::positive());
  readIf(t, "pt_max_GeV", GeV, c.ptMax,
         Range{c.ptMin / GeV, Range{}.max, false, true});
  readIf(t, "eta_max", 1.0, c.etaMax, Range::closed(0, 20));
  readIf(t, "kaon_fraction", 1.0, c.kaonFraction, Range::closed(0, 1));
  readIf(t, "proton_fraction", 1.0, c.protonFraction, Range::closed(0, 1));
  readIf(t, "beam_sigma_z_mm", mm, c.luminousRegion.sigmaZ, sigmaRange());
  construct<GammaGammaOverlay>(t, c);
  return c;
}

std::unique_ptr<EventGenerator> makeGenerator(
    const std::string& sample,
    const std::optional<LuminousRegion::Config>& region) {
  if (sample == "muons" || sample == "gun") {
    ParticleGun::Config c;
    c.luminousRegion = region.value_or(c.luminousRegion);
    return std::make_unique<ParticleGun>(c);
  }
  if (sample == "ttbar3tev" || sample == "bb500") {
    TtbarGenerator::Config c = sample == "bb500"
                                   ? TtbarGenerator::Config::bb500()
                                   : TtbarGenerator::Config::ttbar3TeV();
    c.luminousRegion = region.value_or(c.luminousRegion);
    return std::make_unique<TtbarGenerator>(c);
  }
  constexpr std::string_view kHepMC = "hepmc:";
  if (sample.starts_with(kHepMC) && sample.size() > kHepMC.size()) {
    HepMC3Generator::Config c;
    c.path = sample.substr(kHepMC.size());
    c.luminousRegion = region;
    return std::make_unique<HepMC3Generator>(c);
  }
  throw InputError("unknown sample '" + sample +
                   "' (use muons, gun, ttbar3tev, bb500, hepmc:<path>)");
}

std::unique_ptr<EventGenerator> makeGenerator(
    const ConfigTable& table,
    const std::optional<LuminousRegion::Config>& region) {
  const std::string sample = table.getString("sample");
  std::unique_ptr<EventGenerator> gen;
  if (sample == "muons" || sample == "gun") {
    rejectRegionAlias(table, "vertex_mm", "x_mm, y_mm, z_mm",
                      region.has_value());
    auto cfg = readParticleGunConfig(table);
    cfg.luminousRegion = region.value_or(cfg.luminousRegion);
    table.rejectUnknownKeys();
    gen = std::make_unique<ParticleGun>(cfg);
  } else if (sample == "ttbar3tev" || sample == "bb500") {
    rejectRegionAlias(table, "beam_sigma_z_mm", "sigma_z_mm",
                      region.has_value());
    auto defaults = sample == "bb500" ? TtbarGenerator::Config::bb500()
                                      : TtbarGenerator::Config::ttbar3TeV();
    defaults.luminousRegion = region.value_or(defaults.luminousRegion);
    const auto cfg = readTtbarConfig(table, defaults);
    table.rejectUnknownKeys();
    gen = std::make_unique<TtbarGenerator>(cfg);
  } else if (sample == "hepmc") {
    auto cfg = readHepMC3Config(table);
    cfg.luminousRegion = region;
    table.rejectUnknownKeys();
    // File problems are reported at the file, not at the table.
    gen = std::make_unique<HepMC3Generator>(cfg);
  } else {
    table.fail("sample", "unknown sample '" + sample +
                             "' (use gun, muons, ttbar3tev, bb500, hepmc)");
  }
  return gen;
}

std::unique_ptr<GammaGammaOverlay> makeOverlay(
    const ConfigTable& table,
    const std::optional<LuminousRegion::Config>& region) {
  rejectRegionAlias(table, "beam_sigma_z_mm", "sigma_z_mm", region.has_value());
  GammaGammaOverlay::Config defaults;
  defaults.luminousRegion = region.value_or(defaults.luminousRegion);
  const auto cfg = readGammaGammaOverlayConfig(table, defaults);
  table.rejectUnknownKeys();
  return std::make_unique<GammaGammaOverlay>(cfg);
}

}  // namespace conftrack
