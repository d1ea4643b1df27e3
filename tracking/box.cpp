#include "tracking/box.h"

#include <algorithm>

namespace adugs::tracking {

double intersectionOverUnion(const Box& a, const Box& b) {
  const double iw = std::min(a.right(), b.right()) - std::max(a.left(), b.left());
  const double ih = std::min(a.bottom(), b.bottom()) - std::max(a.top(), b.top());
  if (iw <= 0 || ih <= 0) return 0.0;
  const double inter = iw * ih;
  const double uni = a.area() + b.area() - inter;
  return uni > 0 ? inter / uni : 0.0;
}

}  // namespace adugs::tracking
