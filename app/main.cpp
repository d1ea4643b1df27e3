// adugs: the ADUGS-VINS command line. Subcommands are registered from app/cmd_*.cpp.
#include <exception>
#include <iostream>

#include <CLI/CLI.hpp>

#include "app/commands.h"
#include "app/source_lost.h"
#include "calib/calibration_verdict.h"
#include "calib/solver_outcome.h"
#include "data/input_error.h"

int main(int argc, char** argv) {
  adugs::calib::silenceSolverLogging();
  CLI::App root{"ADUGS-VINS: visual-inertial odometry robust to dynamic objects"};
  root.require_subcommand(1);
  root.set_version_flag("--version", "adugs 0.1");
  adugs::app::registerRunCommand(root);
  adugs::app::registerLiveCommand(root);
  adugs::app::registerRecordCommand(root);
  adugs::app::registerEvalCommand(root);
  adugs::app::registerEvalMotCommand(root);
  adugs::app::registerCalibCommand(root);
  adugs::app::registerBagCommand(root);
  adugs::app::registerSimCommand(root);
  adugs::app::registerTrackCommand(root);
  adugs::app::registerD435iCommand(root);

  try {
    root.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return root.exit(e);
  } catch (const adugs::data::InputError& e) {
    std::cerr << "adugs: error: " << e.what() << "\n";
    return 2;
  } catch (const adugs::calib::CalibrationFailed& e) {
    std::cerr << "adugs: calibration failed: " << e.what() << "\n";
    return adugs::calib::kExitCalibrationFailed;
  } catch (const adugs::app::SourceLost& e) {
    std::cerr << "adugs: " << e.what() << "\n";
    return adugs::app::kExitSourceLost;
  } catch (const std::exception& e) {
    std::cerr << "adugs: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
