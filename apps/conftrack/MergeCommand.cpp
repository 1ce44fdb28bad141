#include "conftrack/core/Error.hpp"
#include "conftrack/core/Log.hpp"
#include "conftrack/evaluation/PerformanceCollector.hpp"
#include "conftrack/evaluation/ShardMerge.hpp"
#include "conftrack/frontend/ReportFiles.hpp"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <set>

#include "Commands.hpp"
#include "OptionChecks.hpp"

namespace conftrack::cli {

namespace {

namespace fs = std::filesystem;

struct MergeOptions {
  std::vector<std::string> inputs;
  std::string output = "merged";
  bool noPlots = false;
};

/// The report folders under `dir` that hold performance data, relative to
/// `dir` ("." for `dir` itself; a --study run has one per report).
std::set<fs::path> reportFolders(const fs::path& dir) {
  std::set<fs::path> folders;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end;
       it.increment(ec)) {
    if (it->is_regular_file(ec) &&
        it->path().filename() == kPerformanceDataFile) {
      folders.insert(fs::relative(it->path().parent_path(), dir));
    }
  }
  if (ec) {
    throw InputError("-i " + dir.string(), "cannot read: " + ec.message());
  }
  return folders;
}

/// `dir` / `folder`, `dir` itself for ".".
fs::path under(const fs::path& dir, const fs::path& folder) {
  return folder == "." ? dir : dir / folder;
}

void mergeReport(const MergeOptions& opt, const fs::path& folder) {
  std::vector<ShardInput> shards;
  for (const std::string& input : opt.inputs) {
    const fs::path file = under(input, folder) / kPerformanceDataFile;
    std::error_code ec;
    if (!fs::exists(file, ec)) {
      // An unfinished shard: its index is unknown, mergeShards names the
      // missing one.
      CONFTRACK_WARNING("merge: " << file.string()
                                  << " is missing (an unfinished shard?)");
      continue;
    }
    shards.push_back({readPerformanceData(file), file.string()});
  }
  SavedPerformance merged = mergeShards(std::move(shards));
  PerformanceSummary summary = summarizePerformance(merged.config, merged.data);
  summary.peakRssMb = merged.peakRssMb;
  const fs::path out = under(opt.output, folder);
  // The run's first event is the first shard's: its display is the run's.
  const fs::path display =
      under(opt.inputs.front(), folder) / "event_display.png";
  std::error_code ec;
  if (!opt.noPlots && fs::exists(display, ec)) {
    fs::copy_file(display, out / "event_display.png",
                  fs::copy_options::overwrite_existing, ec);
  }
  if (folder != ".") {
    std::cout << folder.string() << ":\n";
  }
  printSummaryTable(std::cout, merged.metadata, summary);
  writePerformanceReport(out, merged.metadata, summary, !opt.noPlots,
                         std::cerr);
  std::cout << "report: " << (out / "index.html").string() << '\n';
}

void runMerge(const MergeOptions& opt) {
  // Folders that exist but hold no results are unfinished shards (reported
  // by the merge); a folder that does not exist is a typo.
  std::set<fs::path> folders;
  for (const std::string& input : opt.inputs) {
    std::error_code ec;
    if (!fs::is_directory(input, ec)) {
      throw MissingFileError("-i " + input, "no such folder");
    }
    const std::set<fs::path> here = reportFolders(input);
    folders.insert(here.begin(), here.end());
  }
  if (folders.empty()) {
    throw InputError("-i: no " + std::string(kPerformanceDataFile) +
                     " in any input folder (reports of run or evaluate "
                     "with --shard)");
  }
  // Before any work, as every command does.
  prepareOutputFolder(opt.output, "-o");
  for (const fs::path& folder : folders) {
    mergeReport(opt, folder);
  }
}

}  // namespace

void addMergeCommand(CLI::App& app) {
  auto opt = std::make_shared<MergeOptions>();
  CLI::App* cmd = app.add_subcommand(
      "merge",
      "Merge the reports of the shards of a run (run or evaluate with "
      "--shard K/N) into the report of the whole run");
  cmd->add_option("-i,--input", opt->inputs,
                  "Shard report folders (e.g. out/shard-*), in any order")
      ->required();
  cmd->add_option("-o,--output", opt->output, "Folder of the merged report")
      ->capture_default_str();
  cmd->add_flag("--no-plots", opt->noPlots, "Skip the Python plots");
  cmd->callback([opt]() { runMerge(*opt); });
}

}  // namespace conftrack::cli
