// DirectionTable: a fixed grid of unit directions, and the interpolation of a function
// of direction from its values there. A cluster's projected measure toward u is tabled
// on it once (cluster_transfer.cpp), so that each cluster link reads it in O(1).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

#include "hrbench/geometry/shape.h"

namespace hrbench {

// 3D: the grid points of a cube's six faces, (N + 1)^2 a face at face coordinates
// -1 + 2i/N (edges and corners repeated on each face that has them), each direction the
// point made unit; a direction u is looked up on the face of its largest |u_a| (the
// first axis on ties) and interpolated bilinearly in that face's coordinates
// u_b / |u_a|, u_c / |u_a|. 2D: kDirections2D directions around the circle, linear in
// angle. Both are exact where the function is constant or, per face cell or arc, linear
// in the face coordinates or the angle; elsewhere within a fraction of its variation
// across one cell.
template <int D>
class DirectionTable;

template <>
class DirectionTable<3> {
  public:
    static constexpr int kCells = 4;  // N: cells per face side
    static constexpr size_t kSize = 6 * (kCells + 1) * (kCells + 1);
    struct Weights {
        std::array<size_t, 4> index;
        std::array<double, 4> weight;
    };

    static Vector<3> Direction(size_t m) {
        size_t face = m / ((kCells + 1) * (kCells + 1)), rest = m % ((kCells + 1) * (kCells + 1));
        int axis = int(face / 2);
        Vector<3> v;
        v[axis] = face % 2 == 0 ? 1.0 : -1.0;
        v[(axis + 1) % 3] = -1 + 2 * double(rest / (kCells + 1)) / kCells;
        v[(axis + 2) % 3] = -1 + 2 * double(rest % (kCells + 1)) / kCells;
        return v.normalized();
    }

    // The table entries whose weighted sum gives the value toward the unit vector _u_.
    static Weights Lookup(const Vector<3> &u) {
        int axis = 0;
        for (int a = 1; a < 3; ++a)
            if (std::abs(u[a]) > std::abs(u[axis]))
                axis = a;
        size_t face = size_t(2 * axis + (u[axis] < 0));
        double scale = 1 / std::abs(u[axis]);
        auto cell = [](double x, size_t &i, double &f) {
            double g = std::clamp((x + 1) * kCells / 2, 0.0, double(kCells));
            i = std::min(size_t(g), size_t(kCells - 1));
            f = g - double(i);
        };
        size_t i, j;
        double fi, fj;
        cell(u[(axis + 1) % 3] * scale, i, fi);
        cell(u[(axis + 2) % 3] * scale, j, fj);
        size_t base = face * (kCells + 1) * (kCells + 1) + i * (kCells + 1) + j;
        return {{base, base + 1, base + kCells + 1, base + kCells + 2},
                {(1 - fi) * (1 - fj), (1 - fi) * fj, fi * (1 - fj), fi * fj}};
    }
};

template <>
class DirectionTable<2> {
  public:
    static constexpr size_t kSize = 64;
    struct Weights {
        std::array<size_t, 2> index;
        std::array<double, 2> weight;
    };

    static Vector<2> Direction(size_t m) {
        double angle = 2 * M_PI * double(m) / double(kSize);
        return {std::cos(angle), std::sin(angle)};
    }

    static Weights Lookup(const Vector<2> &u) {
        double g = std::atan2(u.y(), u.x()) / (2 * M_PI) * double(kSize);
        if (g < 0)
            g += double(kSize);
        size_t i = std::min(size_t(g), kSize - 1);
        double f = g - double(i);
        return {{i, (i + 1) % kSize}, {1 - f, f}};
    }
};

}  // namespace hrbench
