// Every class of bad input of the conftrack program (docs/bad-input.md):
// exit code 1 and exactly one line on stderr, "conftrack: error: ...",
// naming the file and line, the key or the option. One row per class; the
// rows are the table of docs/bad-input.md.

#include "conftrack/core/TextFile.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unistd.h>
#include <vector>

#include "BadInputFixtures.hpp"

namespace {

using namespace clitest;

/// A hits file whose first data row is `row`.
std::function<void(const fs::path&)> hitsRow(const std::string& row) {
  return [row](const fs::path& dir) {
    writeHits(dir, kHeader + row + "\n2,33.215,0.5,10.5,1,4,0\n");
  };
}

/// The gzip bytes of a valid hits file.
std::string gzipHits() {
  const fs::path tmp = processDir() / "gz" / "hits.csv.gz";
  fs::create_directories(tmp.parent_path());
  std::string text = kHeader;
  for (int i = 1; i <= 200; ++i) {
    text +=
        std::to_string(i) + ",31.165,0," + std::to_string(i * 0.1) + ",1,2,0\n";
  }
  conftrack::writeTextFile(tmp, text, true);
  return slurp(tmp);
}

/// A detector file: the shipped CLICdet with `from` replaced by `to`.
std::function<void(const fs::path&)> detector(const std::string& from,
                                              const std::string& to) {
  return [from, to](const fs::path& dir) {
    std::string text =
        slurp(fs::path(CONFTRACK_TEST_DATA_DIR) / "../detectors/clicdet.toml");
    const auto pos = text.find(from);
    ASSERT_NE(pos, std::string::npos) << from;
    writeFile(dir / "det.toml", text.replace(pos, from.size(), to));
  };
}

/// A chain file: one build step over `collections` with `extra` keys.
std::function<void(const fs::path&)> chain(const std::string& collections,
                                           const std::string& cut,
                                           const std::string& extra = "") {
  return [=](const fs::path& dir) {
    writeFile(dir / "chain.toml",
              "[[step]]\nname = \"S0\"\ncollections = [" + collections +
                  "]\nactions = [\"build\"]\nmax_cell_angle = 0.005\n"
                  "max_cell_angle_rz = 0.005\n" +
                  cut +
                  "\nmin_hits = 4\nmax_distance = 0.02\n"
                  "slope_z_range = 10.0\nhigh_pt_cut_GeV = 10.0\n" +
                  extra);
  };
}

void nothing(const fs::path&) {}

void fileNamedOut(const fs::path& dir) { writeFile(dir / "out", "a file\n"); }

/// Shard 0 of a 3-shard run in {dir}/s0, the others missing.
void firstOfThreeShards(const fs::path& dir) {
  const Outcome r =
      runConftrack("run --sample muons -n 3 --no-plots --shard 0/3 -o " +
                   (dir / "s0").string());
  if (r.code != 0) {
    throw std::runtime_error("shard 0 failed: " + r.err);
  }
}

/// One class of bad input.
struct BadInput {
  std::string name;  ///< test name
  std::function<void(const fs::path&)> prepare;
  /// conftrack arguments; "{dir}" is the case's folder.
  std::string args;
  /// ECMAScript regex the message after "conftrack: error: " must match.
  std::string message;
};

void PrintTo(const BadInput& c, std::ostream* os) { *os << c.name; }

const std::string kRecoIn = "reconstruct -i {dir}/ev -o {dir}/tracks";

/// Bad files: gzip, CSV, detector and chain TOML (one list per kind of
/// input keeps each initializer small enough for clang-format).
std::vector<BadInput> fileCases() {
  return {
      // ---------------------------------------------------------- gzip
      {"TruncatedGzip",
       [](const fs::path& d) {
         const std::string gz = gzipHits();
         writeFile(d / "ev" / (kHitsName + ".gz"), gz.substr(0, gz.size() / 2));
       },
       kRecoIn,
       R"(^\S+/event000000001-hits\.csv\.gz: unexpected end of file: truncated gzip data$)"},
      {"GarbledGzip",
       [](const fs::path& d) {
         std::string gz = gzipHits();
         for (std::size_t i = 20; i < 40; ++i) {
           gz[i] = static_cast<char>(gz[i] ^ 0x5a);
         }
         writeFile(d / "ev" / (kHitsName + ".gz"), gz);
       },
       kRecoIn, R"(^\S+-hits\.csv\.gz: corrupt gzip data: .+$)"},
      {"GzipWithTrailingGarbage",
       [](const fs::path& d) {
         writeFile(d / "ev" / (kHitsName + ".gz"), gzipHits() + "garbage");
       },
       kRecoIn,
       R"(^\S+-hits\.csv\.gz: trailing garbage after the gzip data at byte \d+$)"},
      // ------------------------------------------------------ CSV shape
      {"EmptyFile", [](const fs::path& d) { writeHits(d, ""); }, kRecoIn,
       R"(^\S+-hits\.csv:1: no header line \(empty file or empty first line\)$)"},
      {"MissingColumn",
       [](const fs::path& d) {
         writeHits(
             d, "hit_id,x,y,volume_id,layer_id,module_id\n1,31.165,0,1,2,0\n");
       },
       kRecoIn,
       R"(^\S+-hits\.csv:1: missing required column 'z' \(header: .*\)$)"},
      {"MissingField", hitsRow("1,31.165,0,1,2,0"), kRecoIn,
       R"(^\S+-hits\.csv:2: expected 7 fields as in the header, found 6$)"},
      {"ExtraField", hitsRow("1,31.165,0,10,1,2,0,7"), kRecoIn,
       R"(^\S+-hits\.csv:2: expected 7 fields as in the header, found 8$)"},
      {"DuplicateHeaderColumn",
       [](const fs::path& d) {
         writeHits(d, "hit_id,x,y,z,x,volume_id,layer_id,module_id\n");
       },
       kRecoIn, R"(^\S+-hits\.csv:1: duplicate column 'x' in the header$)"},
      {"CrOnlyLineEnds",
       [](const fs::path& d) {
         writeHits(d,
                   "hit_id,x,y,z,volume_id,layer_id,module_id\r"
                   "1,31.165,0,10,1,2,0\r2,33.215,0.5,10.5,1,4,0\r");
       },
       kRecoIn,
       R"(^\S+-hits\.csv:1: line ends are CR only \(classic Mac OS\); expected LF or CRLF line ends$)"},
      {"NonUtf8Bytes", hitsRow("1,\xff\xfe,0,10,1,2,0"), kRecoIn,
       R"(^\S+-hits\.csv:2: column 'x': '\?\?' is not a number$)"},
      {"NulByte", hitsRow(std::string("1,31.165,0,10,1,2,0\0", 20)), kRecoIn,
       R"(^\S+-hits\.csv: binary data \(NUL byte\) in a CSV file$)"},
      {"PlainAndGzipBothPresent",
       [](const fs::path& d) {
         writeHits(d, kHeader + kRows);
         writeFile(d / "ev" / (kHitsName + ".gz"), gzipHits());
       },
       kRecoIn,
       R"(^\S+-hits\.csv: both \S+ and \S+ exist: remove one of them$)"},
      {"InputIsNotAFolder", nothing, "reconstruct -i {dir}/nothing -o {dir}/t",
       R"(^\S+/nothing: not a folder$)"},
      {"InputWithoutEvents",
       [](const fs::path& d) { fs::create_directories(d / "ev"); }, kRecoIn,
       R"(^\S+/ev: no event files \(eventNNNNNNNNN-hits\.csv\)$)"},
      // ---------------------------------------------------- hit values
      {"NaNCoordinate", hitsRow("1,nan,0,10,1,2,0"), kRecoIn,
       R"(^\S+-hits\.csv:2: column 'x': 'nan' is not finite$)"},
      {"InfCoordinate", hitsRow("1,31.165,-inf,10,1,2,0"), kRecoIn,
       R"(^\S+-hits\.csv:2: column 'y': '-inf' is not finite$)"},
      {"CoordinateBeyondDouble", hitsRow("1,31.165,0,1e309,1,2,0"), kRecoIn,
       R"(^\S+-hits\.csv:2: column 'z': '1e309' is out of the range of a double$)"},
      {"HitFarOutsideTheDetector", hitsRow("1,1e308,1e308,1e308,1,2,0"),
       kRecoIn,
       R"(^\S+-hits\.csv:2: hit_id 1 at r = 1\.41421e\+308 mm, z = 1e\+308 mm lies outside the tracker of detector 'CLICdet' \(r <= 1500 mm, \|z\| <= 2306 mm\)$)"},
      {"HitAwayFromItsLayer", hitsRow("1,800,0,10,1,2,0"), kRecoIn,
       R"(^\S+-hits\.csv:2: hit_id 1 at r = 800 mm, z = 10 mm is not on the layer its volume_id/layer_id name \(VXD_B_L0: r = 31\.165 mm, \|z\| <= 130 mm, tolerance 25 mm\)$)"},
      {"HitOnTheBeamLine", hitsRow("1,0,0,10,1,2,0"), kRecoIn,
       R"(^\S+-hits\.csv:2: hit_id 1 lies on the beam line \(sqrt\(x\^2 \+ y\^2\) < 1 um\): no tracking layer is there and conformal coordinates are undefined$)"},
      {"DuplicateHitId",
       [](const fs::path& d) {
         writeHits(d,
                   kHeader + "1,31.165,0,10,1,2,0\n1,33.215,0.5,10.5,1,4,0\n");
       },
       kRecoIn, R"(^\S+-hits\.csv:3: duplicate hit_id 1$)"},
      {"NegativeHitId", hitsRow("-1,31.165,0,10,1,2,0"), kRecoIn,
       R"(^\S+-hits\.csv:2: column 'hit_id': '-1' is not an integer in \[0, 18446744073709551615\]$)"},
      {"UnknownLayer", hitsRow("1,31.165,0,10,99,2,0"), kRecoIn,
       R"(^\S+-hits\.csv:2: \(volume_id, layer_id\) = \(99, 2\) is not a layer of detector 'CLICdet'$)"},
      {"ModuleOutOfRange", hitsRow("1,31.165,0,10,1,2,16"), kRecoIn,
       R"(^\S+-hits\.csv:2: column 'module_id': '16' exceeds the 16 modules of layer VXD_B_L0$)"},
      {"NegativeResolution",
       [](const fs::path& d) {
         writeHits(d,
                   "hit_id,x,y,z,volume_id,layer_id,module_id,sigma_u\n"
                   "1,31.165,0,10,1,2,0,-0.003\n");
       },
       kRecoIn,
       R"(^\S+-hits\.csv:2: column 'sigma_u': '-0\.003' is negative$)"},
      // ------------------------------------------- truth, tracks, scores
      {"TruthRowMissing",
       [](const fs::path& d) {
         copyBase("ev", d / "ev");
         copyBase("tracks", d / "tracks");
         std::string truth = slurp(d / "ev" / "event000000001-truth.csv");
         truth.erase(truth.find('\n') + 1,
                     truth.find('\n', truth.find('\n') + 1) - truth.find('\n'));
         writeFile(d / "ev" / "event000000001-truth.csv", truth);
       },
       "evaluate -i {dir}/ev -t {dir}/tracks -o {dir}/report --no-plots",
       R"(^\S+-truth\.csv: no truth row for hit_id 1 \(1 hits without truth; every hit needs one row\)$)"},
      {"NegativeTruthWeight",
       [](const fs::path& d) {
         copyBase("ev", d / "ev");
         copyBase("submission", d / "submission");
         setField(d / "ev" / "event000000001-truth.csv", 2, "weight", "-1");
       },
       "score -s {dir}/submission -i {dir}/ev",
       R"(^\S+-truth\.csv:3: column 'weight': '-1' is negative$)"},
      {"DiagnoseWithoutTruth",
       [](const fs::path& d) {
         copyBase("ev", d / "ev");
         copyBase("submission", d / "submission");
         fs::remove(d / "ev" / "event000000001-truth.csv");
       },
       "diagnose -s {dir}/submission -i {dir}/ev",
       R"(^\S+-truth\.csv: no such file \(nor with \.gz\): scoring needs the truth$)"},
      {"DiagnoseStrayHitsNegative", nothing,
       "diagnose -s {dir} -i {dir} --stray-hits -1",
       R"(^--stray-hits: '-1' is not a whole number in \[0, 1000\])"},
      {"FittedTrackWithOmegaZero",
       [](const fs::path& d) {
         copyBase("ev", d / "ev");
         copyBase("tracks", d / "tracks");
         setField(d / "tracks" / "event000000001-tracks.csv", 1, "omega", "0");
       },
       "evaluate -i {dir}/ev -t {dir}/tracks -o {dir}/report --no-plots",
       R"(^\S+-tracks\.csv:2: column 'omega': '0' is 0 on a fitted track \(a straight track, infinite pT: not a fit in a magnetic field\)$)"},
      {"TrackHitNotInTheEvent",
       [](const fs::path& d) {
         copyBase("ev", d / "ev");
         copyBase("tracks", d / "tracks");
         setField(d / "tracks" / "event000000001-track-hits.csv", 1, "hit_id",
                  "999999");
       },
       "evaluate -i {dir}/ev -t {dir}/tracks -o {dir}/report --no-plots",
       R"(^\S+-track-hits\.csv:2: hit_id 999999 is not a hit of the event$)"},
      // ------------------------------------------------- output folders
      {"OutputFolderIsAFileReconstruct",
       [](const fs::path& d) {
         writeHits(d, kHeader + kRows);
         fileNamedOut(d);
       },
       "reconstruct -i {dir}/ev -o {dir}/out",
       R"(^-o \S+/out: is a file, not a folder$)"},
      {"OutputFolderUnderAFileSimulate", fileNamedOut,
       "simulate --sample muons -n 1 -o {dir}/out/events",
       R"(^-o \S+/out/events: cannot create the folder: Not a directory$)"},
      {"OutputFolderCannotBeCreatedRun", nothing,
       "run --sample muons -n 1 --no-plots -o /proc/conftrack-no-such/run",
       R"(^-o /proc/conftrack-no-such/run: cannot create the folder: No such file or directory$)"},
      {"OutputFolderIsAFileRun", fileNamedOut,
       "run --sample muons -n 1 --no-plots -o {dir}/out",
       R"(^-o \S+/out: is a file, not a folder$)"},
      {"OutputFolderIsAFileEvaluate",
       [](const fs::path& d) {
         copyBase("ev", d / "ev");
         copyBase("tracks", d / "tracks");
         fileNamedOut(d);
       },
       "evaluate -i {dir}/ev -t {dir}/tracks -o {dir}/out --no-plots",
       R"(^-o \S+/out: is a file, not a folder$)"},
      {"OutputFolderIsAFileSimulateTrackml", fileNamedOut,
       "simulate-trackml -i " CONFTRACK_TEST_DATA_DIR
       "/trackml/train_100_events_no_truth -o {dir}/out",
       R"(^-o \S+/out: is a file, not a folder$)"},
      {"OutputFileInAFileDisplay",
       [](const fs::path& d) {
         writeHits(d, kHeader + kRows);
         fileNamedOut(d);
       },
       "display -i {dir}/ev -o {dir}/out/display.png",
       R"(^-o \S+/out/display\.png: '\S+/out' is a file, not a folder$)"},
      {"OutputFileIsAFolderDisplay",
       [](const fs::path& d) { writeHits(d, kHeader + kRows); },
       "display -i {dir}/ev -o {dir}/ev",
       R"(^-o \S+/ev: is a folder, expected a file name$)"},
      {"OutputFileIsAFolderDiagnose",
       [](const fs::path& d) {
         copyBase("ev", d / "ev");
         copyBase("submission", d / "submission");
       },
       "diagnose -s {dir}/submission -i {dir}/ev -o {dir}/ev",
       R"(^-o \S+/ev: is a folder, expected a file name$)"},
      // ------------------------------------------------ detector TOML
      {"DetectorUnknownKey", detector("bz_T = 4.0", "bz_T = 4.0\ncolour = 3"),
       "detector show {dir}/det.toml",
       R"(^\S+/det\.toml:\d+: key 'detector\.colour': unknown key$)"},
      {"DetectorNegativeValue", detector("r_mm = 31.165", "r_mm = -31.165"),
       "detector show {dir}/det.toml",
       R"(^\S+/det\.toml:\d+: key 'subdetector\[0\]\.layer\[0\]\.r_mm': value -31\.165 out of range \(0, inf\]$)"},
      {"DetectorNaNValue", detector("r_mm = 31.165", "r_mm = nan"),
       "detector show {dir}/det.toml",
       R"(^\S+/det\.toml:\d+: key 'subdetector\[0\]\.layer\[0\]\.r_mm': must be finite$)"},
      {"DetectorSharedTrackmlVolume",
       detector("trackml_volume = 4", "trackml_volume = 1"),
       "detector show {dir}/det.toml",
       R"(^\S+/det\.toml:\d+: key 'subdetector\[2\]\.trackml_volume': TrackML volume 1 is already that of VertexBarrel \(line 21\): each subdetector \(endcap side\) needs its own$)"},
      {"DetectorTomlSyntax", detector("bz_T = 4.0", "bz_T = = 4"),
       "detector show {dir}/det.toml",
       R"(^\S+/det\.toml:\d+: TOML syntax: .+$)"},
      {"DetectorNonUtf8", detector("name = \"CLICdet\"", "name = \"CLI\xe9\""),
       "detector show {dir}/det.toml",
       R"(^\S+/det\.toml:\d+: non-ASCII byte 0xe9 \(conftrack config files are ASCII\)$)"},
      {"UnknownDetectorName", nothing, "detector show no-such-detector",
       R"(no-such-detector)"},
      // --------------------------------------------------- chain TOML
      {"ChainUnknownKey",
       chain("\"VertexBarrel\"", "chi2_cut = 100", "speed = 3"),
       kRecoIn + " --chain {dir}/chain.toml",
       R"(^\S+/chain\.toml:\d+: key 'step\[0\]\.speed': unknown key$)"},
      {"ChainNegativeCut", chain("\"VertexBarrel\"", "chi2_cut = -1"),
       kRecoIn + " --chain {dir}/chain.toml",
       R"(^\S+/chain\.toml:7: key 'step\[0\]\.chi2_cut': value -1 out of range \(0, inf\)$)"},
      {"ChainNaNCut", chain("\"VertexBarrel\"", "chi2_cut = nan"),
       kRecoIn + " --chain {dir}/chain.toml",
       R"(^\S+/chain\.toml:7: key 'step\[0\]\.chi2_cut': must be finite$)"},
      {"ChainMinHitsZero",
       [](const fs::path& d) {
         chain("\"VertexBarrel\"", "chi2_cut = 100")(d);
         std::string text = slurp(d / "chain.toml");
         text.replace(text.find("min_hits = 4"), 12, "min_hits = 0");
         writeFile(d / "chain.toml", text);
       },
       kRecoIn + " --chain {dir}/chain.toml",
       R"(^\S+/chain\.toml:8: key 'step\[0\]\.min_hits': value 0 out of range \[3, 100\]$)"},
      {"ChainUnknownCollection", chain("\"Calorimeter\"", "chi2_cut = 100"),
       kRecoIn + " --chain {dir}/chain.toml",
       R"(^\S+/chain\.toml:3: key 'step\[0\]\.collections': detector 'CLICdet' has no subdetector 'Calorimeter' \(it has: .*\)$)"},
      {"ChainFirstStepWithoutCollections", chain("", "chi2_cut = 100"),
       kRecoIn + " --chain {dir}/chain.toml",
       R"(^\S+/chain\.toml:3: key 'step\[0\]\.collections': the first step must name its collections)"},
      {"ChainSecondPassUnknownStep",
       chain("\"VertexBarrel\"", "chi2_cut = 100",
             "[second_pass]\nsteps = [\"Helix\"]\n"),
       kRecoIn + " --chain {dir}/chain.toml",
       R"(^\S+/chain\.toml:\d+: key 'second_pass\.steps': no step named 'Helix'$)"},
  };
}

/// Bad command lines and output folders.
std::vector<BadInput> commandLineCases() {
  return {
      // ------------------------------------------------- command line
      {"EventsZero", nothing, "simulate --sample muons --events 0 -o {dir}/o",
       R"(^--events: 0 is out of range \[1, 100000000\] \(run with --help for usage\)$)"},
      {"EventsInExponentNotation", nothing,
       "simulate --sample muons --events 1e8 -o {dir}/o",
       R"(^--events: '1e8' is not a whole number in \[1, 100000000\] \(digits only\))"},
      {"EventsNegative", nothing, "run --sample muons -n -1 -o {dir}/o",
       R"(^--events: '-1' is not a whole number in \[1, 100000000\])"},
      {"ThreadsNegative", nothing, kRecoIn + " -j -1",
       R"(^--threads: '-1' is not a whole number in \[0, 1024\])"},
      {"ThreadsAbsurd", nothing, kRecoIn + " -j 100000",
       R"(^--threads: 100000 is out of range \[0, 1024\])"},
      {"FitPdgZero", nothing, kRecoIn + " --fit-pdg 0",
       R"(^--fit-pdg: unknown PDG code '0' \(known: 11, 13, 211, 321, 2212 and their negatives\))"},
      {"FitPdgIntMin", nothing, kRecoIn + " --fit-pdg -2147483648",
       R"(^--fit-pdg: unknown PDG code '-2147483648')"},
      {"BeamSpotOneValue", nothing, kRecoIn + " --beam-spot 0.5",
       R"(^--beam-spot: At least 2 required but received 1)"},
      {"BeamSpotFarOff", nothing, kRecoIn + " --beam-spot 0,-11",
       R"(^--beam-spot: -11 is out of range \[-10, 10\])"},
      {"BeamSpotNaN", nothing, kRecoIn + " --beam-spot nan,0",
       R"(^--beam-spot: 'nan' is not a finite number in \[-10, 10\])"},
      {"FirstEventOverflow", nothing,
       "simulate --sample muons --first-event 18446744073709551615 -n 2 -o "
       "{dir}/o",
       R"(^--first-event 18446744073709551615 with --events 2: the last event number would exceed 18446744073709551615$)"},
      {"OverlayNegative", nothing, "simulate --overlay-bx -1 -n 1 -o {dir}/o",
       R"(^--overlay-bx: '-1' is not a whole number in \[0, 100000\])"},
      {"BeamLineFarOff", nothing,
       "simulate-trackml -i {dir} -o {dir}/o --beam-line 12,0",
       R"(^--beam-line: 12 is out of range \[-10, 10\])"},
      {"NoiseNaN", nothing, "simulate-trackml -i {dir} -o {dir}/o --noise nan",
       R"(^--noise: 'nan' is not a finite number in \[0, 0\.99\])"},
      {"TwoNoiseModels", nothing,
       "simulate-trackml -i {dir} -o {dir}/o --noise 0.1 "
       "--noise-per-sensor 1",
       R"(^--noise-per-sensor: not with --noise or --ideal-layers \(a rate per sensor needs the sensors; give one noise model\)$)"},
      {"MinPtNegative", nothing,
       "simulate-trackml -i {dir} -o {dir}/o --min-pt -1",
       R"(^--min-pt: -1 is out of range \[0, 1e\+06\])"},
      {"GeneratorValue", nothing,
       "simulate --sample muons --gen p_GeV=-3 -n 1 -o {dir}/o",
       R"(^--gen options:2: key 'generator\.p_GeV': value -3 out of range \(0, inf\]$)"},
      // ------------------------------------------------ luminous region
      {"LuminousRegionUnknownPreset", nothing,
       "simulate --luminous-region lep -n 1 -o {dir}/o",
       R"(^--luminous-region: unknown luminous region 'lep' \(presets: clic3tev, fccee-z, fccee-ttbar, hllhc, trackml-kaggle, point\) \(run with --help for usage\)$)"},
      {"BeamSigmaZNegative", nothing,
       "simulate --beam-sigma-z -1 -n 1 -o {dir}/o",
       R"(^--beam-sigma-z: -1 is out of range \[0, 1000\])"},
      {"BeamSigmaZNaNTrackml", nothing,
       "simulate-trackml -i {dir} -o {dir}/o --beam-sigma-z nan",
       R"(^--beam-sigma-z: 'nan' is not a finite number in \[0, 1000\])"},
      {"LuminousRegionNegativeWidth",
       [](const fs::path& d) {
         writeFile(d / "gen.toml", "[luminous_region]\nsigma_z_mm = -0.1\n");
       },
       "simulate --config {dir}/gen.toml -n 1 -o {dir}/o",
       R"(^\S+/gen\.toml:2: key 'luminous_region\.sigma_z_mm': value -0\.1 out of range \[0, 1000\]$)"},
      {"LuminousRegionNaNPosition",
       [](const fs::path& d) {
         writeFile(d / "gen.toml", "[luminous_region]\nz_mm = nan\n");
       },
       "simulate --config {dir}/gen.toml -n 1 -o {dir}/o",
       R"(^\S+/gen\.toml:2: key 'luminous_region\.z_mm': must be finite$)"},
      {"LuminousRegionUnknownPresetInFile",
       [](const fs::path& d) {
         writeFile(d / "gen.toml", "[luminous_region]\npreset = \"lep\"\n");
       },
       "simulate --config {dir}/gen.toml -n 1 -o {dir}/o",
       R"(^\S+/gen\.toml:2: key 'luminous_region\.preset': unknown preset 'lep' \(use clic3tev, .*, point\)$)"},
      {"LuminousRegionUnknownKey",
       [](const fs::path& d) {
         writeFile(d / "gen.toml", "[luminous_region]\nsigma_z = 0.05\n");
       },
       "simulate --config {dir}/gen.toml -n 1 -o {dir}/o",
       R"(^\S+/gen\.toml:2: key 'luminous_region\.sigma_z': unknown key$)"},
      {"LuminousRegionInFileAndOption",
       [](const fs::path& d) {
         writeFile(d / "gen.toml", "[luminous_region]\npreset = \"hllhc\"\n");
       },
       "simulate --config {dir}/gen.toml --luminous-region hllhc -n 1 -o "
       "{dir}/o",
       R"(^\S+/gen\.toml:1: table 'luminous_region': the luminous region is also set on the command line \(--luminous-region/--beam-sigma-z\): give it in one place$)"},
      {"BeamSigmaZKeyWithRegion", nothing,
       "simulate --gen beam_sigma_z_mm=0.05 --luminous-region hllhc -n 1 "
       "-o "
       "{dir}/o",
       R"(^--gen options:2: key 'generator\.beam_sigma_z_mm': the luminous region is already set \(\[luminous_region\] or --luminous-region/--beam-sigma-z\); give sigma_z_mm there instead$)"},
      {"TrackmlIdsWithoutVertexId",
       [](const fs::path& d) { copyBase("ev", d / "ev"); },
       "simulate-trackml -i {dir}/ev -o {dir}/o --luminous-region hllhc",
       R"(^\S+/ev/event000000001-particles\.csv: particle_id 1: no TrackML vertex id \(bits 52-63 are 0\); moving the interactions needs the particle ids of TrackML particle files$)"},
      {"DisplayEventNegative",
       [](const fs::path& d) { writeHits(d, kHeader + kRows); },
       "display -i {dir}/ev --event -3 -o {dir}/d.png",
       R"(^--event: '-3' is not a whole number)"},
      {"BenchRepeatZero", nothing, "bench --repeat 0",
       R"(^--repeat: 0 is out of range \[1, 1000\])"},
      {"ModuleLevelWithoutLayout", nothing,
       "simulate --detector trackml --module-level -n 1 -o {dir}/o",
       R"(^--module-level: detector TrackML has no layout file \S+/trackml_layout\.json\.gz \(CLICdet and CLD have one\)$)"},
      {"ShardOutOfRange", nothing, "run --sample muons -n 2 --shard 4/4",
       R"(^--shard: '4/4' is not K/N with 0 <= K < N <= 1000000)"},
      {"ShardNotAFraction", nothing, "simulate -n 2 --shard 1 -o {dir}/o",
       R"(^--shard: '1' is not K/N with 0 <= K < N <= 1000000)"},
      {"MergeFolderMissing", nothing, "merge -i {dir}/nothing -o {dir}/m",
       R"(^-i \S+/nothing: no such folder$)"},
      {"MergeFolderWithoutResults",
       [](const fs::path& d) { fs::create_directories(d / "s0"); },
       "merge -i {dir}/s0 -o {dir}/m",
       R"(^-i: no performance_data\.json in any input folder \(reports of run or evaluate with --shard\)$)"},
      {"MergeGarbledResults",
       [](const fs::path& d) {
         writeFile(d / "s0" / "performance_data.json", "{\"format\": ");
       },
       "merge -i {dir}/s0 -o {dir}/m",
       R"(^\S+/s0/performance_data\.json: invalid JSON: .+$)"},
      {"MergeShardMissing", firstOfThreeShards, "merge -i {dir}/s0 -o {dir}/m",
       R"(^merge: shard 1 of 3 of the run of \S+/s0/performance_data\.json is missing \(run it, then merge again\)$)"},
      {"SlurmWithoutCommand", nothing, "slurm --shards 2 -o {dir}/s",
       R"(^slurm: give the command of the shards after --: run \.\.\. or evaluate \.\.\. .*$)"},
      {"SlurmOutputInCommand", nothing,
       "slurm --dry-run --shards 2 -o {dir}/s -- run -o x",
       R"(^slurm: -o is set for each shard \(-o from --output, -j from --cpus-per-task\): leave it out of the command$)"},
      {"UnknownSubcommand", nothing, "frobnicate",
       R"(^unknown subcommand 'frobnicate' of conftrack \(subcommands: detector, simulate, .*\)$)"},
      {"UnknownNestedSubcommand", nothing, "detector frobnicate",
       R"(^unknown subcommand 'frobnicate' of conftrack detector \(subcommands: show, import-trackml\)$)"},
      {"UnknownOption", nothing, "run --frobnicate",
       R"(^The following argument was not expected: --frobnicate \(run with --help for usage\)$)"},
      {"MissingRequiredOption", nothing, "reconstruct",
       R"(^--input is required \(run with --help for usage\)$)"},
  };
}

const std::vector<BadInput>& cases() {
  static const std::vector<BadInput> all = [] {
    std::vector<BadInput> v = fileCases();
    std::vector<BadInput> more = commandLineCases();
    v.insert(v.end(), more.begin(), more.end());
    return v;
  }();
  return all;
}

class BadInputTest : public ::testing::TestWithParam<BadInput> {};

TEST_P(BadInputTest, OneLineAndExitCodeOne) {
  const BadInput& c = GetParam();
  const fs::path dir = processDir() / c.name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  c.prepare(dir);
  std::string args = c.args;
  for (std::size_t p; (p = args.find("{dir}")) != std::string::npos;) {
    args.replace(p, 5, dir.string());
  }
  const Outcome r = runConftrack(args);
  EXPECT_EQ(r.code, 1) << r.err;
  // Exactly one line, ending in a newline.
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  ASSERT_FALSE(r.err.empty());
  EXPECT_EQ(r.err.back(), '\n');
  const std::string prefix = "conftrack: error: ";
  ASSERT_EQ(r.err.rfind(prefix, 0), 0u) << r.err;
  const std::string message =
      r.err.substr(prefix.size(), r.err.size() - prefix.size() - 1);
  // In --gtest_output=xml reports: the messages quoted in bad-input.md.
  RecordProperty("message", message);
  EXPECT_TRUE(std::regex_search(message, std::regex(c.message)))
      << "message: " << message << "\nexpected: " << c.message;
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Classes, BadInputTest, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<BadInput>& info) {
                           return info.param.name;
                         });

}  // namespace
