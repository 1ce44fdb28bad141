// The diagnose command end to end: on a reconstructed muon event its score
// is that of the score command, the causes add up to 1 - score, the JSON
// is the same for one and two threads; bad input is one line and exit 1
// (the rows in BadInputTests.cpp).

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "BadInputFixtures.hpp"

namespace {

using namespace clitest;
using Json = nlohmann::json;

/// Runs `conftrack -q args` with stdout to `out`; returns the exit code.
int runTo(const std::string& args, const fs::path& out) {
  const std::string cmd = std::string(CONFTRACK_BINARY) + " -q " + args +
                          " > " + out.string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// The mean score printed by `conftrack score`.
double printedScore(const std::string& text) {
  const auto pos = text.find("\n      mean ");
  EXPECT_NE(pos, std::string::npos) << text;
  return std::stod(text.substr(pos + 12));
}

double sumOfCauses(const Json& breakdown) {
  double sum = breakdown.at("found").get<double>();
  for (const char* key :
       {"never_found", "split", "partial", "impure", "left_off_same_layer",
        "left_off_new_layer", "other_tracks", "noise"}) {
    sum += breakdown.at(key).get<double>();
  }
  return sum;
}

TEST(DiagnoseCli, AgreesWithScoreAndAddsUpToOne) {
  const fs::path dir = processDir() / "diagnose";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string inputs = "-s " + (base() / "submission").string() + " -i " +
                             (base() / "ev").string();
  ASSERT_EQ(runTo("score " + inputs, dir / "score.txt"), 0);
  ASSERT_EQ(
      runTo("diagnose " + inputs + " -j 1 -o " + (dir / "d1.json").string(),
            dir / "diagnose.txt"),
      0)
      << slurp(dir / "diagnose.txt");
  ASSERT_EQ(runTo("diagnose " + inputs + " -j 2 --stray-hits 1 -o " +
                      (dir / "d2.json").string(),
                  dir / "diagnose2.txt"),
            0);
  EXPECT_EQ(slurp(dir / "d1.json"), slurp(dir / "d2.json"));
  EXPECT_EQ(slurp(dir / "diagnose.txt"), slurp(dir / "diagnose2.txt"));

  const Json j = Json::parse(slurp(dir / "d1.json"));
  EXPECT_EQ(j.at("max_stray_hits").get<int>(), 1);
  ASSERT_EQ(j.at("events").size(), 1u);
  const Json& event = j.at("events")[0];
  EXPECT_EQ(event.at("event").get<int>(), 1);
  const double score = event.at("score").get<double>();
  EXPECT_NEAR(score, printedScore(slurp(dir / "score.txt")), 0.5e-4);
  EXPECT_GT(score, 0.5);  // muons: most of the weight is found
  EXPECT_NEAR(sumOfCauses(event.at("breakdown")), 1.0, 1e-9);
  EXPECT_NEAR(event.at("breakdown").at("lost").get<double>(), 1.0 - score,
              1e-9);
  EXPECT_GT(event.at("tracks").get<double>(), 0.0);
  // The bins and the outside add up to the event, for each quantity.
  for (const char* quantity : {"pt", "abs_eta", "production_radius"}) {
    const Json& h = event.at(quantity);
    double weight = sumOfCauses(h.at("outside"));
    for (const Json& bin : h.at("bins")) {
      weight += bin.at("weight").get<double>();
    }
    EXPECT_NEAR(weight, 1.0, 1e-9) << quantity;
    EXPECT_TRUE(h.at("bins").back().at("max").is_null()) << quantity;
  }
  EXPECT_EQ(j.at("mean").at("score").get<double>(), score);
  // The places of the lost hits add up to their categories.
  const Json& places = event.at("lost_hit_places");
  const Json& causes = event.at("breakdown");
  EXPECT_NEAR(places.at("left_off_before").get<double>() +
                  places.at("left_off_between").get<double>() +
                  places.at("left_off_after").get<double>(),
              causes.at("left_off_same_layer").get<double>() +
                  causes.at("left_off_new_layer").get<double>(),
              1e-9);
  EXPECT_NEAR(places.at("other_at_holder_end").get<double>() +
                  places.at("other_inside_holder").get<double>(),
              causes.at("other_tracks").get<double>(), 1e-9);

  // The printed table: a header, the event and the mean.
  const std::string text = slurp(dir / "diagnose.txt");
  EXPECT_NE(text.find("TrackML weight by cause"), std::string::npos);
  EXPECT_NE(text.find("pT [GeV]"), std::string::npos);
  EXPECT_NE(text.find("r_prod [mm]"), std::string::npos);
  EXPECT_NE(text.find("Where found particles lose hits"), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
