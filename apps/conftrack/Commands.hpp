#pragma once

/// @file Commands.hpp
/// Registration of the `conftrack` subcommands. Each adds itself to the
/// CLI11 application and sets a callback that does the work; errors are
/// reported by exceptions (InputError: exit code 1, others: 2).

#include <CLI/CLI.hpp>

namespace conftrack::cli {

void addDetectorCommand(CLI::App& app);
void addSimulateCommand(CLI::App& app);
void addReconstructCommand(CLI::App& app);
void addRunCommand(CLI::App& app);
void addEvaluateCommand(CLI::App& app);
void addTrackmlCommands(CLI::App& app);
void addDiagnoseCommand(CLI::App& app);
void addDisplayCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addOverlayCommand(CLI::App& app);
void addMergeCommand(CLI::App& app);
void addSlurmCommand(CLI::App& app);

}  // namespace conftrack::cli
