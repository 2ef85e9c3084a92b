#include "hrbench/geometry/segment.h"

#include <cmath>
#include <limits>

namespace hrbench {

void Segment::SamplePoints(int k, std::vector<Vec2> &out) const {
    for (int s = 0; s < k; ++s) {
        double t = (s + 0.5) / k;
        out.push_back((1 - t) * a + t * b);
    }
}

std::string Segment::Problem() const {
    if (!a.allFinite() || !b.allFinite())
        return "has a coordinate that is not finite";
    if (!std::isfinite(Length()))
        return "is too long for double precision (its length overflows)";
    if (a == b)
        return "is degenerate (its endpoints coincide)";
    // Below the smallest normal double, squared lengths and distances lose precision.
    if (!(SquaredLength() >= std::numeric_limits<double>::min()))
        return "is too short for double precision (its squared length underflows)";
    return "";
}

}  // namespace hrbench
