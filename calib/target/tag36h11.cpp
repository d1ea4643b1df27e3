#include "calib/target/tag36h11.h"

#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

extern "C" {
#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>
}

#include "calib/target/aprilgrid.h"

namespace adugs::calib {
namespace {

// The family is created once; we copy out what we need so no C object outlives the call.
struct FamilyTable {
  std::vector<uint64_t> codes;
  std::vector<uint32_t> bit_x, bit_y;  // in the width_at_border grid, 0 = black border
  uint32_t nbits = 0;
};

const FamilyTable& table() {
  static const FamilyTable t = [] {
    FamilyTable out;
    apriltag_family_t* f = tag36h11_create();
    out.codes.assign(f->codes, f->codes + f->ncodes);
    out.bit_x.assign(f->bit_x, f->bit_x + f->nbits);
    out.bit_y.assign(f->bit_y, f->bit_y + f->nbits);
    out.nbits = f->nbits;
    tag36h11_destroy(f);
    return out;
  }();
  return t;
}

}  // namespace

Tag36h11Bits tag36h11Bits(int id) {
  const FamilyTable& t = table();
  if (id < 0 || id >= static_cast<int>(t.codes.size()))
    throw std::out_of_range("tag36h11 id " + std::to_string(id) + " outside 0.." +
                            std::to_string(t.codes.size() - 1));
  Tag36h11Bits bits{};
  const uint64_t code = t.codes[static_cast<size_t>(id)];
  // apriltag stores the first bit in the most significant position (see apriltag_to_image).
  for (uint32_t i = 0; i < t.nbits; ++i) {
    const bool white = (code >> (t.nbits - 1 - i)) & 1u;
    bits.at(t.bit_y[i] - 1).at(t.bit_x[i] - 1) = white;
  }
  return bits;
}

}  // namespace adugs::calib
