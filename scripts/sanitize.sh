#!/usr/bin/env bash
# Builds the unit tests with AddressSanitizer + UndefinedBehaviorSanitizer into build-asan/ and
# runs them. Any sanitizer report fails the run.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
# -g1: line tables only, enough for file:line in sanitizer reports; full -g debug info of the
# Eigen/Ceres-heavy code made this build much slower.
# ccache keys on paths relative to the checkout, so a fresh clone elsewhere reuses objects.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$root}"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DADUGS_SANITIZE=ON \
  -DADUGS_BUILD_BENCHMARKS=OFF -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG"
cmake --build build-asan -j"${ADUGS_JOBS:-2}"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# Leaks inside third-party libraries (OpenCV's and ViSP's static singletons) are not ours.
export LSAN_OPTIONS="suppressions=$root/scripts/lsan.supp:print_suppressions=0"
cd build-asan
# The longest accuracy and end-to-end runs (13-80 s each in Release, 4-10x that under ASan) run in
# the Release stage only; under the sanitizers their code paths run through shorter siblings kept
# here: the estimator (SlidingWindowEstimator.StaticStreet..., InitialisesOnItsOwnWindow...), the
# pipeline with signals (CmdLive.SigintMidRunFlushesEveryOutput, CmdRunVioSim.*), the detector
# chain (CmdRunVioSim.DetectorMasksRunTheWholeDynamicObjectStage), bag playback
# (RosbagPlayback.*), the camera-IMU calibration (CameraImuCalibrator.Synthetic..., and
# CameraImuVerdict.FirstThreeSecondsOfEurocFail: the CLI test of the same run is left out), the
# intrinsics' verdicts (IntrinsicsVerdict.*, CalibCli.IntrinsicsFromEurocCornerCsvs).
# SANITIZE_ALL=1 runs every test.
release_only=(
  CameraImuCalibrator.EurocImuAprilMatchesPublishedExtrinsics
  SlidingWindowEstimator.RejectsLandmarksThatSlideOffTheirPoint
  SlidingWindowEstimator.OnlineTimeOffsetRecoversAFiveMillisecondShift
  SlidingWindowEstimator.OnlineExtrinsicCorrectsAWrongCalibrationRotation
  SlidingWindowEstimator.TimeOffsetBeyondItsBoundResetsTheWindow
  SlidingWindowEstimator.BlackoutResetsCleanlyAndReinitialises
  CmdPlayback.OpenLorisBagWithSplitImuTracksAsWellAsTheFolder
  CmdPlayback.TumViFolderWithPartialMocapAndSixteenBitImages
  CmdPlayback.ViodeBagGivesTheTrajectoryOfTheAslFolder
  CmdPlayback.ConfigPlaybackMapSetsTopicsAndTheCommandLineWins
  CmdPlayback.ACalibrationMarkedWeakIsUsedWithAWarningAndNamedInTheSummary
  CmdPlayback.StartAndDurationPlayPartOfTheSequence
  CmdPlayback.BadBagInputIsAnErrorNamingTheProblem
  CmdPlaybackTumVi.FisheyeSequenceRunsWithThePresetCalibration
  CmdLive.RecordedReplayRunsLikeTheOriginal
  CmdLive.ReplayGivesTheAccuracyOfRunAndEveryImuSample
  CmdLive.SlowEstimatorDropsFramesByThePolicyAndKeepsEveryImuSample
  CmdLive.SigtermStopsAPlaybackWithItsOutputs
  CmdLive.ARecordingKeepsTheWeakMarkOfItsCalibration
  CmdLive.SigintWhileRecordingKeepsACompleteShorterRecording
  CmdRunVioSim.TorchScriptDetectorAndMobileSamRunTheDynamicStage
  SimWalkers.ARealDetectorRecognisesThemAndNotTheOldBoxes
  CmdTrack.DetectorOnARealVideo
  RunConfigChoice.AdugsRunPrintsAndRecordsTheChosenConfig
  CalibCli.UndeterminedFocalFailsWithExitThreeAndWritesNothing
  CameraImuCli.FirstThreeSecondsOfEurocFailWithExitThree
  CameraImuCli.SyntheticRunWritesKalibrFilesReportAndPlots
  IntrinsicsCalibrator.NearStillViewsAreNeverOk
)
exclude="^($(IFS='|'; echo "${release_only[*]}"))\$"
if [ "${SANITIZE_ALL:-0}" = 1 ]; then exclude='^$'; fi
ctest --output-on-failure -j"${ADUGS_JOBS:-2}" -E "$exclude"
