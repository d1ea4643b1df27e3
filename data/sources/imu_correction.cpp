#include "data/sources/imu_correction.h"

namespace adugs::data {
namespace {

class ImuCorrection : public SequenceSource {
 public:
  ImuCorrection(std::unique_ptr<SequenceSource> source, const ImuIntrinsics& intrinsics)
      : source_(std::move(source)), intrinsics_(intrinsics) {}
  bool next(Measurement& m) override {
    if (!source_->next(m)) return false;
    if (m.isImu()) intrinsics_.correct(m.imu.gyro, m.imu.accel);
    return true;
  }
  SourceCounts counts() const override { return source_->counts(); }
  std::string description() const override { return source_->description() + " (IMU intrinsics applied)"; }
  bool isLive() const override { return source_->isLive(); }
  void stop() override { source_->stop(); }
  std::string stopReason() const override { return source_->stopReason(); }

 private:
  std::unique_ptr<SequenceSource> source_;
  ImuIntrinsics intrinsics_;
};

}  // namespace

std::unique_ptr<SequenceSource> correctImu(std::unique_ptr<SequenceSource> source, const ImuIntrinsics& intrinsics) {
  if (intrinsics.isIdentity()) return source;
  return std::make_unique<ImuCorrection>(std::move(source), intrinsics);
}

}  // namespace adugs::data
