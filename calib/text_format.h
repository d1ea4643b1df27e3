#pragma once
// Number formatting for the calibration outputs (YAML, reports).
#include <string>

namespace adugs::calib {

// Shortest decimal text that reads back to exactly the same double ("0.088", not
// "0.087999999999999995").
std::string formatDouble(double v);

// printf-style formatting into a std::string.
std::string strprintf(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

}  // namespace adugs::calib
