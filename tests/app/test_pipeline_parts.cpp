// The pipeline's parts on their own (app/pipeline/): the entrance gate's two policies, the gyro
// bias feedback, the status line, the top view.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <string>
#include <thread>

#include "app/pipeline/estimator_feedback.h"
#include "app/pipeline/frame_gate.h"
#include "app/pipeline/live_window.h"
#include "app/pipeline/status_line.h"
#include "app/pipeline/stop_signal.h"
#include "app/pipeline/top_view.h"

namespace adugs::app {
namespace {

using Clock = std::chrono::steady_clock;

data::Frame frameAt(int64_t t_ns) {
  data::Frame f;
  f.t_ns = t_ns;
  return f;
}
data::ImuSample imuAt(int64_t t_ns) {
  data::ImuSample s;
  s.t_ns = t_ns;
  return s;
}

// 10 frames at 0, 100, ..., 900 with IMU every 10 between them.
void feed(FrameGate& gate, int frames) {
  for (int k = 0; k < frames; ++k) {
    for (int64_t t = k * 100 - 90; t <= k * 100; t += 10)
      if (t > (k - 1) * 100 && t >= 0) gate.addImu(imuAt(t));
    gate.addFrame(frameAt(k * 100), k * 0.1, Clock::now());
  }
}

TEST(FrameGate, LiveDropsTheOldestWaitingFrameAndPassesItsImuOn) {
  FrameGate gate(2, FrameGate::Policy::kDropOldest);
  feed(gate, 10);  // nobody takes frames out: 8 are dropped, never blocking
  gate.addImu(imuAt(905));
  gate.close();
  EXPECT_EQ(gate.framesDropped(), 8u);
  EXPECT_EQ(gate.imuPending(), 1u);
  PipelineFrame f;
  ASSERT_TRUE(gate.pop(&f));
  EXPECT_EQ(f.index, 0);
  EXPECT_EQ(f.frame.t_ns, 800);
  // Every IMU sample up to frame 800 rides with it, in time order, none lost.
  ASSERT_EQ(f.imu.size(), 81u);
  for (size_t i = 0; i < f.imu.size(); ++i) EXPECT_EQ(f.imu[i].t_ns, static_cast<int64_t>(10 * i));
  ASSERT_TRUE(gate.pop(&f));
  EXPECT_EQ(f.index, 1);
  EXPECT_EQ(f.frame.t_ns, 900);
  ASSERT_EQ(f.imu.size(), 10u);
  EXPECT_EQ(f.imu.front().t_ns, 810);
  EXPECT_FALSE(gate.pop(&f));
}

TEST(FrameGate, PlaybackWaitsAndLosesNothing) {
  FrameGate gate(2, FrameGate::Policy::kWait);
  std::thread producer([&] {
    feed(gate, 50);
    gate.close();
  });
  PipelineFrame f;
  int64_t last_imu = -10;  // samples come every 10 from 0
  int frames = 0;
  while (gate.pop(&f)) {
    EXPECT_EQ(f.index, frames);
    EXPECT_EQ(f.frame.t_ns, frames * 100);
    for (const data::ImuSample& s : f.imu) {
      EXPECT_EQ(s.t_ns, last_imu + 10);
      last_imu = s.t_ns;
    }
    ++frames;
    if (frames % 7 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));  // a slow consumer
  }
  producer.join();
  EXPECT_EQ(frames, 50);
  EXPECT_EQ(gate.framesDropped(), 0u);
  EXPECT_EQ(last_imu, 4900);
}

TEST(FrameGate, ClosedGateRefusesFramesAndReleasesAWaitingProducer) {
  FrameGate gate(1, FrameGate::Policy::kWait);
  ASSERT_TRUE(gate.addFrame(frameAt(0), 0, Clock::now()));
  bool refused = false;
  std::thread producer([&] { refused = !gate.addFrame(frameAt(1), 0, Clock::now()); });  // waits: full
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  gate.close();
  producer.join();
  EXPECT_TRUE(refused);
  PipelineFrame f;
  EXPECT_TRUE(gate.pop(&f));  // what was inside still comes out
  EXPECT_FALSE(gate.pop(&f));
}

TEST(EstimatorFeedback, WaitsForTheFrameAskedForAndStopsWhenClosed) {
  EstimatorFeedback feedback;
  Eigen::Vector3d b;
  ASSERT_TRUE(feedback.waitFor(-1, &b));
  EXPECT_EQ(b, Eigen::Vector3d::Zero());
  std::thread estimator([&] {
    for (int k = 0; k < 5; ++k) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      feedback.publish(Eigen::Vector3d::Constant(k));
    }
    feedback.close();
  });
  ASSERT_TRUE(feedback.waitFor(3, &b));
  EXPECT_EQ(b, Eigen::Vector3d::Constant(3));
  ASSERT_TRUE(feedback.waitFor(1, &b));  // earlier ones stay available
  EXPECT_EQ(b, Eigen::Vector3d::Constant(1));
  EXPECT_FALSE(feedback.waitFor(5, &b));  // never published: closed
  estimator.join();
}

TEST(EstimatorFeedback, CarriesTheStateOnceThereIsOne) {
  EstimatorFeedback feedback;
  feedback.publish(Eigen::Vector3d(0.1, 0, 0), std::nullopt, 100);  // not initialised yet
  vio::NavState state;
  state.t_ns = 205;  // the camera stamp 200 + a 5 ns time offset
  state.v_W = Eigen::Vector3d(1, 2, 3);
  feedback.publish(Eigen::Vector3d(0.2, 0, 0), state, 200);
  EstimatorFeedback::AfterFrame after;
  ASSERT_TRUE(feedback.waitFor(0, &after));
  EXPECT_FALSE(after.state.has_value());
  EXPECT_EQ(after.frame_t_ns, 100);
  ASSERT_TRUE(feedback.waitFor(1, &after));
  EXPECT_EQ(after.gyro_bias, Eigen::Vector3d(0.2, 0, 0));
  ASSERT_TRUE(after.state.has_value());
  EXPECT_EQ(after.state->v_W, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(after.state->t_ns, 205);
  EXPECT_EQ(after.frame_t_ns, 200);
  ASSERT_TRUE(feedback.waitFor(-3, &after));  // before any estimate
  EXPECT_FALSE(after.state.has_value());
  EXPECT_EQ(after.gyro_bias, Eigen::Vector3d::Zero());
}

TEST(EstimatorFeedback, KeepsTheNewestFramesOnly) {
  // A long run's feedback stays bounded: the newest 1024 frames are kept, an older one asked for
  // is a logic error (the stages ask for 2 or 3 frames back).
  EstimatorFeedback feedback;
  for (int k = 0; k < 5000; ++k) feedback.publish(Eigen::Vector3d::Constant(k));
  Eigen::Vector3d b;
  ASSERT_TRUE(feedback.waitFor(4997, &b));
  EXPECT_EQ(b, Eigen::Vector3d::Constant(4997));
  ASSERT_TRUE(feedback.waitFor(5000 - 1024, &b));
  EXPECT_EQ(b, Eigen::Vector3d::Constant(5000 - 1024));
  EXPECT_THROW(feedback.waitFor(100, &b), std::logic_error);
}

volatile std::sig_atomic_t g_previous_handler_calls = 0;
void previousHandler(int) { ++g_previous_handler_calls; }

// While a StopSignal exists, SIGINT and SIGTERM become a stop request (reported once, by wait());
// afterwards the previous handlers are back.
TEST(StopSignal, TurnsSigintIntoAStopRequestAndRestoresTheHandler) {
  std::signal(SIGINT, previousHandler);
  {
    StopSignal stop;
    EXPECT_FALSE(stop.wait(std::chrono::milliseconds(1)));
    std::thread waker([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      stop.wake();
    });
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_FALSE(stop.wait(std::chrono::seconds(10)));  // woken, no signal
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
    waker.join();
    std::raise(SIGINT);  // the process goes on
    EXPECT_TRUE(stop.wait(std::chrono::milliseconds(100)));
    EXPECT_EQ(stop.signalNumber(), SIGINT);
    EXPECT_FALSE(stop.wait(std::chrono::milliseconds(1)));  // reported once
    EXPECT_EQ(g_previous_handler_calls, 0);
  }
  std::raise(SIGINT);
  EXPECT_EQ(g_previous_handler_calls, 1);
  std::signal(SIGINT, SIG_DFL);
}

// No window without an X server to show it: the live command then runs headless and says why.
TEST(LiveWindow, IsNotAvailableWithoutAnXServerAndSaysWhy) {
  const char* saved = std::getenv("DISPLAY");
  const std::string previous = saved ? saved : "";
  std::string why;
  unsetenv("DISPLAY");
  EXPECT_FALSE(LiveWindow::available(&why));
  EXPECT_NE(why.find("DISPLAY"), std::string::npos) << why;
  setenv("DISPLAY", ":4711", 1);  // no server there
  EXPECT_FALSE(LiveWindow::available(&why));
  EXPECT_NE(why.find(":4711"), std::string::npos) << why;
  if (saved)
    setenv("DISPLAY", previous.c_str(), 1);
  else
    unsetenv("DISPLAY");
}

TEST(StatusLine, SaysRatesDropsFeaturesAndState) {
  StatusFigures s;
  s.sequence_s = 12.34;
  s.fps_in = 30;
  s.fps_out = 29.44;
  s.dropped = 3;
  s.features = 148;
  s.estimating = true;
  s.initialized = true;
  EXPECT_EQ(formatStatusLine("live", s),
            "live: 12.3 s | 30.0 fps in, 29.4 fps out, 3 dropped | 148 features | tracking, 0 resets");
  s.initialized = false;
  EXPECT_NE(formatStatusLine("live", s).find("initialising"), std::string::npos);
  s.estimating = false;
  EXPECT_NE(formatStatusLine("live", s).find("vision only"), std::string::npos);
}

TEST(TopView, GridStepIsOneTwoOrFiveTimesAPowerOfTen) {
  EXPECT_DOUBLE_EQ(topViewGridStep(8.0, 8), 1.0);
  EXPECT_DOUBLE_EQ(topViewGridStep(9.0, 8), 2.0);
  EXPECT_DOUBLE_EQ(topViewGridStep(30.0, 8), 5.0);
  EXPECT_DOUBLE_EQ(topViewGridStep(0.5, 8), 0.1);
  EXPECT_DOUBLE_EQ(topViewGridStep(120.0, 8), 20.0);
}

// A trajectory along +x drawn from left to right through the panel's middle row, heading arrow
// and current position in green at its right end.
TEST(TopView, DrawsTheTrajectoryFromAboveScaledToFit) {
  std::vector<data::StampedPose> trail;
  for (int i = 0; i <= 40; ++i) {
    data::StampedPose p;
    p.t_ns = i;
    p.p_W_B = Eigen::Vector3d(0.1 * i, 2.0, 1.0);
    trail.push_back(p);
  }
  const cv::Mat panel = drawTopView(trail, {200, 200}, "tracking");
  ASSERT_EQ(panel.type(), CV_8UC3);
  const auto isTrail = [&](int u, int v) {
    const cv::Vec3b c = panel.at<cv::Vec3b>(v, u);
    return c[2] > 200 && c[1] > 150 && c[0] < 80;  // orange-yellow (BGR 0, 200, 255)
  };
  EXPECT_TRUE(isTrail(100, 100));
  EXPECT_TRUE(isTrail(40, 100));
  EXPECT_FALSE(isTrail(100, 60));
  EXPECT_FALSE(isTrail(100, 140));
  // The 4 m are scaled to the usable width: the left end at the margin, the current position
  // (green) at the right margin.
  const cv::Vec3b end = panel.at<cv::Vec3b>(100, 200 - 24);
  EXPECT_GT(end[1], 200);
  EXPECT_LT(end[2], 100);
  // Nothing yet: a plain panel with its labels, no crash.
  const cv::Mat empty = drawTopView({}, {120, 80}, "initialising");
  EXPECT_EQ(empty.size(), cv::Size(120, 80));
}

}  // namespace
}  // namespace adugs::app
