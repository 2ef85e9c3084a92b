// Parametric scene families: each has named parameters with defaults and ranges.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "hrbench/scene.h"

namespace hrbench {

// One named parameter of a family, with its admissible range.
struct ParamSpec {
    std::string name;
    double defaultValue;      // used when the parameter is not given; NaN: none, the
                              // parameter is optional and absent unless given
    std::string defaultFrom;  // if not empty, the default is this other parameter's value
    double low, high;         // admissible range
    bool lowOpen = false;     // exclude _low_ itself (e.g. a length must be > 0)
    bool highOpen = false;    // exclude _high_ itself
    bool integer = false;     // the value must be a whole number
    std::string help;         // meaning and unit, for `hrbench scenes`
    std::string excludes{};   // if not empty, a parameter that must not also be given
};

// A scene family: a builder from complete, range-checked parameters.
struct Family {
    std::string name;
    std::string help;
    std::vector<ParamSpec> params;
    int dimension;                                      // 2 (segments) or 3 (polygons)
    std::function<AnyPatches(const ParamMap &)> build;  // the patches, in scene order
};

// Every family, in the order `hrbench scenes` lists them.
const std::vector<Family> &Families();

// Builds the scene of _family_ from _given_ parameters: rejects unknown names and
// out-of-range values with an InputError, fills in defaults, validates the result.
Scene MakeScene(const std::string &family, const ParamMap &given);

// Human-readable description of a parameter's range, e.g. "> 0" or "integer in [3, 100000]".
std::string DescribeRange(const ParamSpec &spec);

}  // namespace hrbench
