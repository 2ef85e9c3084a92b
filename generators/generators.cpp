#include "generators.h"

#include <cmath>

#include "flatland.h"
#include "hrbench/util/error.h"
#include "space.h"
#include "util/format.h"

namespace hrbench {

const std::vector<Family> &Families() {
    static const std::vector<Family> families = [] {
        std::vector<Family> all = FlatlandFamilies();
        for (Family &f : SpaceFamilies())
            all.push_back(std::move(f));
        return all;
    }();
    return families;
}

std::string DescribeRange(const ParamSpec &s) {
    std::string kind = s.integer ? "integer " : "";
    bool noHigh = std::isinf(s.high), noLow = std::isinf(s.low);
    if (noLow && noHigh)
        return kind + "any finite value";
    if (noHigh)
        return kind + (s.lowOpen ? "> " : ">= ") + FormatDouble(s.low);
    return kind + "in " + (s.lowOpen ? "(" : "[") + FormatDouble(s.low) + ", " +
           FormatDouble(s.high) + (s.highOpen ? ")" : "]");
}

static const Family &FindFamily(const std::string &name) {
    std::string names;
    for (const Family &f : Families()) {
        if (f.name == name)
            return f;
        names += (names.empty() ? "" : ", ") + f.name;
    }
    throw InputError("unknown scene '" + name + "' (choose one of: " + names + ")");
}

Scene MakeScene(const std::string &familyName, const ParamMap &given) {
    const Family &family = FindFamily(familyName);

    // Reject parameters the family does not have.
    for (const auto &[key, value] : given) {
        bool known = false;
        for (const ParamSpec &spec : family.params)
            known |= spec.name == key;
        if (!known) {
            std::string names;
            for (const ParamSpec &spec : family.params)
                names += (names.empty() ? "" : ", ") + spec.name;
            throw InputError("scene " + family.name + " has no parameter '" + key +
                             "' (its parameters: " + names + ")");
        }
    }

    // Fill in defaults (an optional parameter without one stays absent), then check every
    // value against its range.
    ParamMap params;
    for (const ParamSpec &spec : family.params) {
        auto it = given.find(spec.name);
        if (it != given.end())
            params[spec.name] = it->second;
        else if (!spec.defaultFrom.empty())
            params[spec.name] = params.at(spec.defaultFrom);
        else if (!std::isnan(spec.defaultValue))
            params[spec.name] = spec.defaultValue;
    }
    // A given parameter that replaces another (its `excludes`) leaves that one out.
    for (const ParamSpec &spec : family.params) {
        if (spec.excludes.empty() || !given.count(spec.name))
            continue;
        if (given.count(spec.excludes))
            throw InputError("scene " + family.name + ": give " + spec.name + " or " +
                             spec.excludes + ", not both");
        params.erase(spec.excludes);
    }
    for (const ParamSpec &spec : family.params) {
        auto it = params.find(spec.name);
        if (it == params.end())
            continue;
        double v = it->second;
        bool ok = std::isfinite(v) && (spec.lowOpen ? v > spec.low : v >= spec.low) &&
                  (spec.highOpen ? v < spec.high : v <= spec.high) &&
                  (!spec.integer || v == std::floor(v));
        if (!ok)
            throw InputError("scene " + family.name + ": parameter " + spec.name + "=" +
                             FormatDouble(v) + " is out of range (" + DescribeRange(spec) + ")");
    }

    Scene scene;
    scene.family = family.name;
    scene.params = params;
    scene.patches = family.build(params);
    ValidateScene(scene);
    return scene;
}

}  // namespace hrbench
