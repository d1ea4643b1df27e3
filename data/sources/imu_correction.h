#pragma once
// Applies the IMU's scale, misalignment and g-sensitivity (ImuIntrinsics, from Kalibr's or
// OpenVINS' IMU file) to every IMU sample of a source, so the estimator sees the IMU frame's
// angular rate and specific force. Frames pass untouched.
#include <memory>

#include "data/calibration.h"
#include "data/sources/sequence_source.h"

namespace adugs::data {

// The source itself when the intrinsics are the identity.
std::unique_ptr<SequenceSource> correctImu(std::unique_ptr<SequenceSource> source, const ImuIntrinsics& intrinsics);

}  // namespace adugs::data
