#include "geometry/segment.h"

#include <cmath>

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
    if (a == b || !(Length() > 0))
        return "is degenerate (its endpoints coincide)";
    return "";
}

}  // namespace hrbench
