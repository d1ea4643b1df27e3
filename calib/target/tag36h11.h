#pragma once
// The tag36h11 code bits, read from the apriltag library's family table (no copied tables).
#include <array>

namespace adugs::calib {

// 6x6 data bits of code `id` (0..586) as the upright tag is printed: [row][col], row 0 at the
// top, true = white. Throws std::out_of_range for a bad id.
using Tag36h11Bits = std::array<std::array<bool, 6>, 6>;
Tag36h11Bits tag36h11Bits(int id);

}  // namespace adugs::calib
