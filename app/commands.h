#pragma once
// Each subcommand lives in its own app/cmd_NAME.cpp and registers itself on the root CLI::App.
// The callback it installs runs after parsing and may throw; main() turns errors into exit codes.
#include <CLI/CLI.hpp>

namespace adugs::app {

void registerBagCommand(CLI::App& root);
void registerCalibCommand(CLI::App& root);
// adugs calib show | convert (app/cmd_calib_files.cpp), registered by registerCalibCommand.
void registerCalibFileCommands(CLI::App* calib);
void registerD435iCommand(CLI::App& root);
void registerEvalCommand(CLI::App& root);
void registerEvalMotCommand(CLI::App& root);
void registerLiveCommand(CLI::App& root);
void registerRecordCommand(CLI::App& root);
void registerRunCommand(CLI::App& root);
void registerSimCommand(CLI::App& root);
void registerTrackCommand(CLI::App& root);

}  // namespace adugs::app
