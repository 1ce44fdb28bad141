#include "conftrack/core/Error.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

#include "Commands.hpp"
#include "EventLoop.hpp"
#include "OptionChecks.hpp"

namespace conftrack::cli {

namespace {

namespace fs = std::filesystem;

struct SlurmOptions {
  std::size_t shards = 0;
  std::string output;
  std::string partition;
  std::string account;
  std::string time;
  std::size_t cpusPerTask = 1;
  std::string memory;
  std::size_t maxRunning = 0;
  std::vector<std::string> sbatchOptions;
  bool resume = false;
  bool dryRun = false;
  bool noPlots = false;
  /// The conftrack command each shard runs: run or evaluate and its
  /// options (after --).
  std::vector<std::string> command;
};

/// `s` in single quotes for bash.
std::string quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  }
  return out + "'";
}

/// The absolute path of this program, which the jobs run (the same build on
/// the shared file system).
std::string selfPath() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) {
    throw InputError("slurm: cannot find the conftrack executable: " +
                     ec.message());
  }
  return self.string();
}

/// The options of the wrapped command that the shards set themselves.
void checkCommand(const std::vector<std::string>& command) {
  if (command.empty() || (command[0] != "run" && command[0] != "evaluate")) {
    throw InputError(
        "slurm: give the command of the shards after --: run ... or "
        "evaluate ... (e.g. conftrack slurm --shards 4 -o study -- run -n "
        "1000)");
  }
  for (const std::string& arg : command) {
    for (const char* own : {"-o", "--output", "--shard", "-j", "--threads"}) {
      const std::string o(own);
      if (arg == o || arg.rfind(o + "=", 0) == 0) {
        throw InputError("slurm: " + o +
                         " is set for each shard (-o from --output, -j from "
                         "--cpus-per-task): leave it out of the command");
      }
    }
  }
}

/// "0-3" or "1,3,5-7": the array indices of `shards`.
std::string arraySpec(const std::vector<std::size_t>& shards) {
  std::string spec;
  for (std::size_t i = 0; i < shards.size();) {
    std::size_t j = i;
    while (j + 1 < shards.size() && shards[j + 1] == shards[j] + 1) {
      ++j;
    }
    spec += (spec.empty() ? "" : ",") + std::to_string(shards[i]);
    if (j > i) {
      spec += "-" + std::to_string(shards[j]);
    }
    i = j + 1;
  }
  return spec;
}

/// The #SBATCH lines shared by both jobs.
std::string commonDirectives(const SlurmOptions& opt) {
  std::string s;
  if (!opt.partition.empty()) {
    s += "#SBATCH --partition=" + opt.partition + "\n";
  }
  if (!opt.account.empty()) {
    s += "#SBATCH --account=" + opt.account + "\n";
  }
  for (const std::string& o : opt.sbatchOptions) {
    s += "#SBATCH " + o + "\n";
  }
  return s;
}

void writeScript(const fs::path& file, const std::string& text) {
  std::ofstream out(file);
  out << text;
  out.close();
  if (!out) {
    throw InputError(file.string(), "cannot write the job script");
  }
  std::error_code ec;
  fs::permissions(file,
                  fs::perms::owner_all | fs::perms::group_read |
                      fs::perms::group_exec | fs::perms::others_read |
                      fs::perms::others_exec,
                  ec);
  if (ec) {
    throw InputError(file.string(),
                     "cannot make the job script executable: " + ec.message());
  }
}

/// Runs `sbatch --parsable ...` and returns the job id it prints.
std::string submit(const std::string& arguments) {
  const std::string command = "sbatch --parsable " + arguments + " 2>&1";
  std::FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) {
    throw InputError("slurm: cannot run sbatch");
  }
  std::string output;
  char buffer[256];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) {
    output += buffer;
  }
  const int status = ::pclose(pipe);
  while (!output.empty() && (output.back() == '\n' || output.back() == ' ')) {
    output.pop_back();
  }
  if (status != 0) {
    const bool missing = WIFEXITED(status) && WEXITSTATUS(status) == 127;
    throw InputError(
        "slurm: " +
        (missing ? std::string("sbatch not found: not a Slurm submit host? "
                               "(--dry-run writes the job scripts only)")
                 : "sbatch failed: " + output.substr(0, output.find('\n'))));
  }
  // --parsable prints "id" or "id;cluster".
  return output.substr(0, output.find(';'));
}

void runSlurm(const SlurmOptions& opt) {
  checkCommand(opt.command);
  for (const std::string& value : opt.sbatchOptions) {
    if (value.find_first_of("\n\r") != std::string::npos) {
      throw InputError("--sbatch-option: a line break in '" + value + "'");
    }
  }
  const fs::path out = fs::absolute(opt.output).lexically_normal();
  prepareOutputFolder(out / "slurm", "-o");
  const std::string program = selfPath();
  const std::string n = std::to_string(opt.shards);
  const std::string shardDir = (out / "shard-").string();

  std::string args;
  for (const std::string& a : opt.command) {
    args += " " + quote(a);
  }
  const std::string shardScript =
      "#!/bin/bash\n"
      "# Written by conftrack slurm: one shard of the run per array task.\n"
      "#SBATCH --job-name=conftrack-shards\n"
      "#SBATCH --output=" +
      (out / "slurm" / "shard-%a.log").string() +
      "\n"
      "#SBATCH --cpus-per-task=" +
      std::to_string(opt.cpusPerTask) + "\n" +
      (opt.memory.empty() ? "" : "#SBATCH --mem=" + opt.memory + "\n") +
      (opt.time.empty() ? "" : "#SBATCH --time=" + opt.time + "\n") +
      commonDirectives(opt) +
      "set -euo pipefail\n"
      "k=${SLURM_ARRAY_TASK_ID:?run as a Slurm array task}\n"
      "rm -f " +
      quote(shardDir) + "\"$k/COMPLETE\"\n" + quote(program) + args +
      " --shard \"$k/" + n + "\" -j " + std::to_string(opt.cpusPerTask) +
      " -o " + quote(shardDir) + "\"$k\"" + " --no-plots" +
      "\n"
      "# The mark of a finished shard, for --resume.\n"
      "touch " +
      quote(shardDir) + "\"$k/COMPLETE\"\n";
  const std::string mergeScript =
      "#!/bin/bash\n"
      "# Written by conftrack slurm: merges the shards into one report.\n"
      "#SBATCH --job-name=conftrack-merge\n"
      "#SBATCH --output=" +
      (out / "slurm" / "merge.log").string() +
      "\n"
      "#SBATCH --cpus-per-task=1\n" +
      commonDirectives(opt) +
      "set -euo pipefail\n"
      "inputs=()\n"
      "for ((k = 0; k < " +
      n + "; ++k)); do inputs+=(" + quote(shardDir) +
      "\"$k\"); done\n"
      "exec " +
      quote(program) + " merge -i \"${inputs[@]}\" -o " +
      quote((out / "merged").string()) + (opt.noPlots ? " --no-plots" : "") +
      "\n";
  const fs::path shardFile = out / "slurm" / "shard.sh";
  const fs::path mergeFile = out / "slurm" / "merge.sh";
  writeScript(shardFile, shardScript);
  writeScript(mergeFile, mergeScript);

  std::vector<std::size_t> todo;
  for (std::size_t k = 0; k < opt.shards; ++k) {
    std::error_code ec;
    if (!opt.resume ||
        !fs::exists(shardDir + std::to_string(k) + "/COMPLETE", ec)) {
      todo.push_back(k);
    }
  }
  const std::string spec = arraySpec(todo);
  const std::string shardArgs =
      "--array=" + spec +
      (opt.maxRunning > 0 ? "%" + std::to_string(opt.maxRunning) : "") + " " +
      quote(shardFile.string());
  if (opt.dryRun) {
    std::cout << "job scripts: " << shardFile.string() << ", "
              << mergeFile.string() << "\n";
    if (!todo.empty()) {
      std::cout << "sbatch --parsable " << shardArgs << "\n"
                << "sbatch --parsable --dependency=afterok:<shard job> "
                << quote(mergeFile.string()) << "\n";
    } else {
      std::cout << "sbatch --parsable " << quote(mergeFile.string()) << "\n";
    }
    return;
  }
  std::string dependency;
  if (todo.empty()) {
    std::cout << "all " << n << " shards are complete\n";
  } else {
    const std::string shardJob = submit(shardArgs);
    dependency = "--dependency=afterok:" + shardJob + " ";
    std::cout << "shards: job " << shardJob << " (array " << spec << " of " << n
              << ", logs " << (out / "slurm").string() << "/shard-<k>.log)\n";
  }
  const std::string mergeJob = submit(dependency + quote(mergeFile.string()));
  std::cout << "merge: job " << mergeJob
            << (todo.empty() ? "" : ", starts when every shard succeeded")
            << " (log " << (out / "slurm" / "merge.log").string() << ")\n"
            << "report: " << (out / "merged").string() << "/"
            << (opt.command[0] == "run" &&
                        std::find(opt.command.begin(), opt.command.end(),
                                  "--study") != opt.command.end()
                    ? "<report>/"
                    : "")
            << "index.html\n"
            << "if a shard fails, the merge never starts: fix the cause, "
               "then resume with the same command and --resume\n";
}

}  // namespace

void addSlurmCommand(CLI::App& app) {
  auto opt = std::make_shared<SlurmOptions>();
  CLI::App* cmd = app.add_subcommand(
      "slurm",
      "Run a study as a Slurm array job, one shard per task, and merge the "
      "shards in a job that waits for them: conftrack slurm --shards N -o "
      "DIR -- run <run options>");
  cmd->add_option("--shards", opt->shards, "Number of shards (array tasks)")
      ->required()
      ->check(wholeNumber(1, kMaxShards));
  cmd->add_option("-o,--output", opt->output,
                  "Study folder on a file system the nodes share: "
                  "shard-<k>/, merged/, slurm/ (scripts, logs)")
      ->required();
  cmd->add_option("--partition", opt->partition, "sbatch --partition");
  cmd->add_option("--account", opt->account, "sbatch --account");
  cmd->add_option("--time", opt->time, "Time limit per shard (sbatch --time)");
  cmd->add_option("--cpus-per-task", opt->cpusPerTask,
                  "Cores per shard, used as its threads")
      ->capture_default_str()
      ->check(wholeNumber(1, kMaxThreads));
  cmd->add_option("--mem", opt->memory, "Memory per shard (sbatch --mem)");
  cmd->add_option("--max-running", opt->maxRunning,
                  "Most shards running at once (0: no limit)")
      ->check(wholeNumber(0, kMaxShards));
  cmd->add_option("--sbatch-option", opt->sbatchOptions,
                  "Further #SBATCH option of both jobs, e.g. --qos=short");
  cmd->add_flag("--resume", opt->resume,
                "Submit only the shards without a COMPLETE mark, then the "
                "merge");
  cmd->add_flag("--dry-run", opt->dryRun,
                "Write the job scripts and print the sbatch commands only");
  cmd->add_flag("--no-plots", opt->noPlots,
                "Skip the plots of the merged report");
  cmd->add_option("command", opt->command,
                  "After --: the command of each shard (run ... or "
                  "evaluate ...) without -o, -j and --shard");
  cmd->callback([opt]() { runSlurm(*opt); });
}

}  // namespace conftrack::cli
