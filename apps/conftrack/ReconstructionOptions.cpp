#include "ReconstructionOptions.hpp"

#include "conftrack/core/Units.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"

#include "OptionChecks.hpp"

namespace conftrack::cli {

void addReconstructionOptions(CLI::App& cmd, ReconstructionOptions& o) {
  cmd.add_option("--detector", o.detector, "Detector name or TOML file")
      ->capture_default_str();
  cmd.add_option("--chain", o.chain,
                 "Finding chain name or TOML file (default: the detector's)");
  cmd.add_flag("--no-fit", o.noFit, "Finding only, no Kalman fit");
  cmd.add_option(
         "--fit-pdg", o.fitPdg,
         "Mass hypothesis of the fit (PDG code: 211, 13, 11, 321, 2212)")
      ->capture_default_str()
      ->check(pdgCode());
  addBeamLineOption(cmd, "--beam-spot", o.beamSpot,
                    "Transverse position X,Y of the beam line [mm], about "
                    "which the finder maps hits to the conformal plane "
                    "(default: the chain's beam_spot_x_mm, beam_spot_y_mm, "
                    "else 0,0)");
}

Reconstruction::Config makeReconstructionConfig(const ReconstructionOptions& o,
                                                const Detector& detector) {
  ReconstructionChoice choice;
  choice.detector = o.detector;
  choice.chain = o.chain;
  choice.fit = !o.noFit;
  choice.fitPdg = o.fitPdg;
  if (o.beamSpot.size() == 2) {
    choice.beamSpot = Vector2(o.beamSpot[0], o.beamSpot[1]);
  }
  return conftrack::makeReconstructionConfig(choice, detector);
}

}  // namespace conftrack::cli
