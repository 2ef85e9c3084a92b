// Shorthands shared by the family definitions: common parameter kinds and a
// platform-independent uniform random number.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

#include "generators.h"

namespace hrbench {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

// A length: > 0.
inline ParamSpec Length(const std::string &name, double value, const std::string &help) {
    return {name, value, "", 0, kInf, true, false, false, help};
}
// A length whose default is another parameter's value.
inline ParamSpec LengthLike(const std::string &name, const std::string &from,
                            const std::string &help) {
    return {name, 0, from, 0, kInf, true, false, false, help};
}
// A gap: >= 0.
inline ParamSpec Gap(const std::string &name, double value, const std::string &help) {
    return {name, value, "", 0, kInf, false, false, false, help};
}
// An offset: any finite value, default 0.
inline ParamSpec Offset(const std::string &name, const std::string &help) {
    return {name, 0, "", -kInf, kInf, false, false, false, help};
}
// An optional quantity > 0 without a default: absent unless given, and not to be given
// together with _excludes_, the parameter it replaces.
inline ParamSpec OptionalPositive(const std::string &name, const std::string &excludes,
                                  const std::string &help) {
    const double none = std::numeric_limits<double>::quiet_NaN();
    return {name, none, "", 0, kInf, true, false, false, help, excludes};
}
// A whole number in [low, high].
inline ParamSpec Count(const std::string &name, double value, double low, double high,
                       const std::string &help) {
    return {name, value, "", low, high, false, false, true, help};
}

// Uniform double in [0, 1) from the top 53 bits: the same on every platform,
// unlike std::uniform_real_distribution.
inline double Uniform(std::mt19937_64 &rng) { return double(rng() >> 11) * 0x1.0p-53; }

// Draws a random scene of _n_ shapes makes before it gives up (the box is too crowded):
// 1000 per shape up to n = 1111, then 100 per shape plus a million, so that a request
// that cannot be met fails in seconds (n = 100000: 1.1e7 draws).
inline int64_t MaxDraws(int n) { return std::min(1000 * int64_t(n), 100 * int64_t(n) + 1000000); }

// The shapes placed so far in a random scene, by the cells of a uniform grid their
// bounding boxes overlap, so that a candidate is tested against its neighbours only:
// generating n shapes costs O(n), not O(n^2), and the scene is the same as testing
// every shape (two shapes that meet share a point, whose cell both boxes overlap).
template <int D>
class PlacementGrid {
  public:
    using Point = std::array<double, D>;

    // _cell_: the side of a cell, at least the largest bounding-box side of a shape;
    // _extent_: the side of the region shapes lie in. Cells are widened so that there
    // are at most 2^20 per axis, which keeps cell indices small.
    PlacementGrid(double cell, double extent) : cell_(std::max(cell, extent * 0x1p-20)) {}

    // Calls _meets_(id) for every shape whose cells the box [lo, hi] overlaps, until it
    // returns true; returns whether one did. A shape may be offered more than once.
    template <typename Meets>
    bool AnyNear(const Point &lo, const Point &hi, Meets &&meets) const {
        bool found = false;
        ForEachCell(lo, hi, [&](uint64_t key) {
            auto it = cells_.find(key);
            if (it != cells_.end())
                for (uint32_t id : it->second)
                    if (!found && meets(id))
                        found = true;
        });
        return found;
    }

    // Registers shape _id_ with bounding box [lo, hi].
    void Insert(uint32_t id, const Point &lo, const Point &hi) {
        ForEachCell(lo, hi, [&](uint64_t key) { cells_[key].push_back(id); });
    }

  private:
    template <typename F>
    void ForEachCell(const Point &lo, const Point &hi, F &&f) const {
        std::array<int64_t, D> a, b, k;
        for (int d = 0; d < D; ++d)
            a[d] = Index(lo[d]), b[d] = Index(hi[d]), k[d] = a[d];
        while (true) {
            uint64_t key = 0;
            for (int d = 0; d < D; ++d)
                key = key << 21 | uint64_t(k[d] + (int64_t(1) << 20));  // 21 bits per axis
            f(key);
            int d = 0;
            while (d < D && k[d] == b[d])
                k[d] = a[d], ++d;
            if (d == D)
                return;
            ++k[d];
        }
    }

    // The cell of coordinate _x_, clamped to the 2^21 cells a key can hold.
    int64_t Index(double x) const {
        double i = std::floor(x / cell_);
        return int64_t(std::clamp(i, -double(int64_t(1) << 20), double((int64_t(1) << 20) - 1)));
    }

    double cell_;
    std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

}  // namespace hrbench
