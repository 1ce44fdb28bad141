// The CLD chain (chains/cld.toml) end to end, issue 15 item 5: CLD tt-bar +
// 30 BX with ideal layers and with sensors, and displaced muons, each
// against the numbers its CLICdet-style steps (seed caps, Displaced4,
// DisplacedHelix) reach. The samples are small (10 tt-bar events, 25 muons
// per momentum), so each bound leaves a stated tolerance beyond the value
// measured on this sample; the 50-event numbers are in the chain's comments.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "TempDir.hpp"

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

/// Runs `conftrack -q run --detector cld args -o dir`; returns summary.json
/// of `dir/sub` (sub empty: dir itself).
Json runCld(const std::string& args, const fs::path& dir,
            const std::string& sub = "") {
  fs::remove_all(dir);
  const std::string cmd = std::string(CONFTRACK_BINARY) +
                          " -q run --detector cld --no-plots -j 2 " + args +
                          " -o " + dir.string() + " > /dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << cmd;
  std::ifstream in(sub.empty() ? dir / "summary.json"
                               : dir / sub / "summary.json");
  std::stringstream s;
  s << in.rdbuf();
  return Json::parse(s.str());
}

double eff(const Json& j, const char* key) {
  return j.at("efficiency").at(key).get<double>();
}

// tt-bar + 30 BX at 3 TeV, 10 events, seed 1, ideal layers. Measured:
//   pT > 1 GeV 99.30 %, 0.1-1 GeV 97.81 %, fake rate 0.65 % (of 6,128
//   tracks; 99.12 %, 96.88 % and 1.31 % before the outliers left the
//   tracks, the 4-measurement minimum and LowPtHelix);
// the six-step chain before issue 15 item 5 on the same events: 97.72 %
// (557), 96.25 % (308), 1.37 % (83 / 6,064). Tolerance: 1 % on the
// efficiencies (6 particles above 1 GeV: the old chain fails the first
// bound), 0.5 % on the fake rate (about 30 tracks).
TEST(CldChain, TtbarIdealLayers) {
  conftrack::test::TempDir dir;
  const Json j = runCld("-n 10 --seed 1", dir.path() / "ideal");
  EXPECT_GE(eff(j, "pt_above_1GeV"), 0.9912 - 0.01);
  EXPECT_GE(eff(j, "pt_0p1_to_1GeV"), 0.9688 - 0.01);
  EXPECT_LE(j.at("fake_rate").get<double>(), 0.0131 + 0.005);
}

// The same events with CLD's sensors (--module-level). Measured:
//   pT > 1 GeV 99.30 %, 0.1-1 GeV 98.74 %, fake rate 0.61 % (of 6,041
//   tracks; 95.26 %, 96.86 % and 1.56 % at first)
// (the old chain: the same efficiencies, 1.57 %; on 50 events the new
// steps gain 0.7 % above 1 GeV, chains/cld.toml). Same tolerances.
TEST(CldChain, TtbarSensors) {
  conftrack::test::TempDir dir;
  const Json j = runCld("-n 10 --seed 1 --module-level", dir.path() / "mod");
  EXPECT_GE(eff(j, "pt_above_1GeV"), 0.9526 - 0.01);
  EXPECT_GE(eff(j, "pt_0p1_to_1GeV"), 0.9686 - 0.01);
  EXPECT_LE(j.at("fake_rate").get<double>(), 0.0156 + 0.005);
}

// Displaced muons (production radius 0-600 mm, --study displaced) at 1 and
// 10 GeV, 25 per momentum (-n 5). Measured: 25 / 25 and 25 / 25 (24 / 25
// at 1 GeV before the helix step took residuals at the hit), no fakes
// (on 250 per momentum: the old six-step chain 43.6 % and 69.6 %, this one
// 98.0 % and 100 %). Tolerance: two muons in 25.
TEST(CldChain, DisplacedMuons) {
  conftrack::test::TempDir dir;
  const fs::path out = dir.path() / "displaced";
  const Json p1 = runCld("--study displaced -n 5", out, "displaced_p1");
  EXPECT_GE(eff(p1, "all"), (24.0 - 2.0) / 25.0);
  EXPECT_EQ(p1.at("fake_rate").get<double>(), 0.0);
  std::ifstream in(out / "displaced_p10" / "summary.json");
  std::stringstream s;
  s << in.rdbuf();
  const Json p10 = Json::parse(s.str());
  EXPECT_GE(eff(p10, "all"), (25.0 - 2.0) / 25.0);
}

}  // namespace
