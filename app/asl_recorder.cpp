#include "app/asl_recorder.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>

#include "app/pipeline/channel.h"
#include "app/pipeline/stop_signal.h"
#include "app/source_lost.h"
#include "calib/calibration_verdict.h"
#include "data/formats/asl_writer.h"
#include "data/formats/atomic_file.h"

namespace adugs::app {
namespace {
namespace fs = std::filesystem;

struct RecordCounts {
  std::atomic<size_t> frames_acquired{0}, imu_acquired{0}, frames_lost_queue{0};  // by the acquisition thread
  size_t csv_frames = 0, image_files = 0, csv_imu = 0;                              // the check at the end
};

}  // namespace

void recordToAsl(data::OpenedSequence& sequence, const AslRecordOptions& a) {
  data::SequenceSource& source = *sequence.source;
  StopSignal stop_signal;
  // A calibration adugs calib marked weak stays marked in the recording: `adugs run` on the folder
  // warns as it does with the original file.
  const std::vector<std::string> weak = calib::filesMarkedWeak(sequence.calibration_files);
  std::string weak_mark;
  for (const std::string& file : weak) {
    std::cerr << "WARNING: record: " << file
              << ": adugs calib marked this calibration WEAK; the recording's cam0/sensor.yaml carries the mark\n";
    weak_mark += "# verdict: weak (copied by adugs record from " + file + ", which adugs calib marked weak)\n";
  }
  data::AslWriter writer(a.out_dir, sequence.camera, sequence.has_imu ? &sequence.imu_noise : nullptr, false,
                         "recorded by adugs record; calibration: " + sequence.calibration_from,
                         weak_mark);

  // The writer thread: PNG encoding and disk off the acquisition thread.
  Channel<data::Measurement> queue;
  std::atomic<int> queued_frames{0};
  std::exception_ptr writer_error;
  std::thread writer_thread([&] {
    data::Measurement m;
    try {
      while (queue.pop(&m)) {
        if (m.isImu()) {
          writer.writeImu(m.imu);
        } else {
          writer.writeFrame(m.frame.t_ns, m.frame.colour.empty() ? m.frame.image : m.frame.colour);
          --queued_frames;
        }
      }
      writer.flush();
    } catch (...) {
      writer_error = std::current_exception();
      queue.close();
      source.stop();
    }
  });

  // The acquisition on its own thread, so that this one can watch Ctrl-C and print progress.
  RecordCounts c;
  std::exception_ptr source_error;
  std::atomic<bool> acquiring{true};
  std::thread acquisition([&] {
    data::Measurement m;
    try {
      while (source.next(m)) {
        if (m.isImu()) {
          ++c.imu_acquired;
        } else {
          ++c.frames_acquired;
          if (queued_frames >= a.max_queued_frames) {
            ++c.frames_lost_queue;  // the writer is that far behind: counted, reported, fails the recording
            continue;
          }
          ++queued_frames;
        }
        if (!queue.push(std::move(m))) break;
        m = data::Measurement{};
      }
    } catch (...) {
      source_error = std::current_exception();
    }
    queue.close();
    acquiring = false;
    stop_signal.wake();
  });
  auto last = std::chrono::steady_clock::now();
  std::string stopped;
  while (acquiring) {
    if (stop_signal.wait(std::chrono::milliseconds(1000))) {
      stopped = stop_signal.signalNumber() == SIGTERM ? "SIGTERM" : "SIGINT";
      source.stop();
    }
    if (!a.quiet && std::chrono::steady_clock::now() - last >= std::chrono::seconds(1) && acquiring) {
      last = std::chrono::steady_clock::now();
      std::cerr << "record: " << c.frames_acquired << " frames, " << c.imu_acquired << " IMU samples, "
                << queued_frames << " frames waiting to be written\n"
                << std::flush;
    }
  }
  acquisition.join();
  writer_thread.join();

  // The check: what is in the folder is what was acquired.
  const fs::path mav = writer.mavDir();
  const data::AslFolderCounts written = data::countAslFolder(mav.parent_path().string());
  c.csv_frames = written.camera_rows;
  c.image_files = written.image_files;
  c.csv_imu = sequence.has_imu ? written.imu_rows : 0;
  const size_t frames_kept = c.frames_acquired - c.frames_lost_queue;  // the acquisition has ended
  const bool complete = c.frames_lost_queue == 0 && c.csv_frames == frames_kept && c.image_files == frames_kept &&
                        c.csv_imu == (sequence.has_imu ? c.imu_acquired.load() : 0);
  std::ostringstream summary;
  summary << "source: \"" << source.description() << "\"\n"
          << "calibration: \"" << sequence.calibration_from << "\"\n"
          << calib::calibrationWeakYamlLine(weak) << "end: " << (source_error || writer_error ? "error" : stopped.empty() ? "end_of_source" : "stopped") << "\n";
  std::string why = stopped.empty() ? source.stopReason() : stopped;  // a camera unplugged, ...
  std::replace(why.begin(), why.end(), '"', '\'');
  if (!why.empty()) summary << "end_detail: \"" << why << "\"\n";
  summary << "frames_acquired: " << c.frames_acquired << "\n"
          << "frames_written: " << c.csv_frames << "\n"
          << "image_files: " << c.image_files << "\n"
          << "frames_lost_by_recorder: " << c.frames_lost_queue << "\n"
          << "frames_lost_by_source: " << source.counts().frames_lost << "\n"
          << "imu_samples_acquired: " << c.imu_acquired << "\n"
          << "imu_samples_written: " << c.csv_imu << "\n"
          << "complete: " << (complete ? "true" : "false") << "\n";
  data::writeTextFileAtomically((fs::path(a.out_dir) / "record.yaml").string(), summary.str());
  std::cout << "adugs record: " << c.csv_frames << " of " << c.frames_acquired << " frames and " << c.csv_imu << " of "
            << c.imu_acquired << " IMU samples written to " << mav.string() << "\n"
            << "  summary     " << (fs::path(a.out_dir) / "record.yaml").string() << "\n";
  if (!stopped.empty()) std::cout << "  stopped by " << stopped << "; everything acquired until then is written\n";
  else if (!why.empty()) std::cout << "  the source ended: " << why << "; everything acquired until then is written\n";
  if (source.counts().frames_lost > 0)
    std::cout << "  the source itself lost " << source.counts().frames_lost << " frames before they arrived\n";
  if (writer_error) std::rethrow_exception(writer_error);
  if (source_error) std::rethrow_exception(source_error);
  if (!complete)
    throw std::runtime_error("the recording is incomplete: " + std::to_string(c.frames_lost_queue.load()) +
                             " frames lost because the writer fell " + std::to_string(a.max_queued_frames) +
                             " frames behind (slow disk?), " + std::to_string(c.csv_frames) + " frames in cam0/data.csv, " +
                             std::to_string(c.image_files) + " images, of " + std::to_string(c.frames_acquired.load()) +
                             " acquired (see " + (fs::path(a.out_dir) / "record.yaml").string() + ")");
  if (stopped.empty() && !why.empty())
    throw SourceLost("the live source ended by itself: " + why + "; everything acquired until then is written in " +
                     mav.string());
}

}  // namespace adugs::app
