// What the hierarchical solve (solve.cpp, solve_output.cpp) and the dense reference
// (reference_solve.cpp) share: short numbers, timing a stage, describing a solved
// element the same way for both, and the unit of emission they solve in.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "hrbench/forest.h"
#include "hrbench/solve.h"
#include "util/stopwatch.h"

namespace hrbench {

// A number for a message or the table: 3 significant digits.
inline std::string Short(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", value);
    return text;
}

// The wall and CPU time of _watch_ so far, as a stage's time.
inline StageTime Elapsed(const Stopwatch &watch) {
    return {watch.WallSeconds(), watch.CpuSeconds()};
}

// Sums the stages' times over passes and solves.
inline void AddTime(StageTime &sum, const StageTime &t) { sum.wall += t.wall, sum.cpu += t.cpu; }

inline Vec3 AsVec3(const Vec2 &v) { return {v.x(), v.y(), 0}; }
inline Vec3 AsVec3(const Vec3 &v) { return v; }

// Element _e_ of _forest_ with its radiosity _b_ and irradiance _h_, and its outline.
template <typename Shape>
ElementRadiosity Describe(const Forest<Shape> &forest, uint32_t e, double b, double h) {
    ElementRadiosity r{e,
                       forest[e].root,
                       forest.Depth(e),
                       forest.Position(e),
                       AsVec3(forest[e].center),
                       forest[e].Size(),
                       b,
                       h};
    const Shape &shape = forest.ShapeOf(e);
    if constexpr (Shape::kDimension == 2) {
        r.corners[0] = AsVec3(shape.a), r.corners[1] = AsVec3(shape.b);
        r.numCorners = 2;
    } else {
        for (int k = 0; k < shape.n; ++k)
            r.corners[size_t(k)] = shape.v[size_t(k)];
        r.numCorners = shape.n;
    }
    return r;
}

// The equation is linear in E: both solvers solve it in units of the largest emission
// (materials after InEmissionUnits), so that no sum, square or norm of B under- or
// overflows at any scale of E, and the errors against the reference are the same at
// every scale; ToEmissionScale gives the solution back its scale (docs/solve.md, Scale).

// The largest emission of _materials_ (> 0: SolveMaterials refuses a scene where nothing
// emits), and _materials_ with every emission divided by it.
double EmissionUnit(const std::vector<Material> &materials);
std::vector<Material> InEmissionUnits(const std::vector<Material> &materials, double unit);

// Multiplies _elements_' radiosity and irradiance and the powers by _unit_; LimitError
// when one of them overflows (the solution lies beyond the largest double).
void ToEmissionScale(std::vector<ElementRadiosity> &elements, double &emittedPower,
                     double &absorbedPower, double unit);

}  // namespace hrbench
