// `adugs record`: a live source (app/live_sources.h: --replay, --video, --v4l2, --d435i)
// into an EuRoC ASL folder (app/asl_recorder.h) that `adugs run`, `adugs calib ...` and `adugs
// track` read back.
#include <filesystem>
#include <memory>
#include <string>

#include "app/asl_recorder.h"
#include "app/commands.h"
#include "app/live_sources.h"
#include "data/input_error.h"

namespace adugs::app {
namespace {

struct RecordArgs {
  LiveSourceArgs source;
  std::string config_path;
  AslRecordOptions record;
};

void record(const RecordArgs& a) {
  if (std::filesystem::exists(std::filesystem::path(a.record.out_dir) / "mav0"))
    throw data::InputError(a.record.out_dir, 0, "--out", "already holds a recording (mav0/): choose a new folder");
  data::OpenedSequence sequence = openLiveSource(a.source, a.config_path, a.record.out_dir);
  recordToAsl(sequence, a.record);
}

}  // namespace

void registerRecordCommand(CLI::App& root) {
  auto args = std::make_shared<RecordArgs>();
  CLI::App* cmd = root.add_subcommand(
      "record", "Record a live source (--replay SEQ | --video FILE | --v4l2 DEV | --d435i) into an EuRoC ASL folder");
  addLiveSourceOptions(cmd, args->source);
  cmd->add_option("--config", args->config_path,
                  "run config YAML: its d435i: map for --d435i (e.g. data/config/d435i.yaml), its playback: map for --replay")
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", args->record.out_dir, "output folder (gets mav0/cam0, mav0/imu0, record.yaml)")->required();
  cmd->add_option("--max-queued-frames", args->record.max_queued_frames,
                  "frames that may wait to be written before frames are lost (and the recording fails)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", args->record.quiet, "no progress on stderr");
  cmd->callback([args] { record(*args); });
}

}  // namespace adugs::app
