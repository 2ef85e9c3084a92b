// Shorthands shared by the family definitions: common parameter kinds and a
// platform-independent uniform random number.
#pragma once

#include <limits>
#include <random>
#include <string>

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
// A whole number in [low, high].
inline ParamSpec Count(const std::string &name, double value, double low, double high,
                       const std::string &help) {
    return {name, value, "", low, high, false, false, true, help};
}

// Uniform double in [0, 1) from the top 53 bits: the same on every platform,
// unlike std::uniform_real_distribution.
inline double Uniform(std::mt19937_64 &rng) { return double(rng() >> 11) * 0x1.0p-53; }

}  // namespace hrbench
