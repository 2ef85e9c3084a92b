#include "geometry/segment.h"

#include <cmath>

namespace hrbench {

int Segment::Subdivide(Subdivision, std::array<Segment, 4> &out) const {
    Vec2 m = Midpoint();
    out[0] = {a, m};
    out[1] = {m, b};
    return 2;
}

void Segment::SamplePoints(int k, std::vector<Vec2> &out) const {
    for (int s = 0; s < k; ++s) {
        double t = (s + 0.5) / k;
        out.push_back((1 - t) * a + t * b);
    }
}

std::string Segment::Problem() const {
    if (!a.allFinite() || !b.allFinite())
        return "has a coordinate that is not finite";
    if (a == b || !(Length() > 0) || !std::isfinite(Length()))
        return "is degenerate (its endpoints coincide)";
    return "";
}

bool Segment::Resolves(double measure, const std::array<double, 4> &children, int n) {
    double half = 0.5 * measure;
    for (int c = 0; c < n; ++c)
        if (!(std::abs(children[c] - half) <= 1e-6 * half))
            return false;
    return true;
}

}  // namespace hrbench
