// Every oracle of the engine, listed once. The command line, the help text, the JSON,
// the capability listing and the refinement dispatch all read this list.
// To add an oracle: write oracles/<name>.h (see oracles/oracle.h) and add it here.
#pragma once

#include <string>
#include <type_traits>
#include <vector>

#include "hrbench/oracles/bf.h"
#include "hrbench/oracles/garmann.h"
#include "hrbench/oracles/hanrahan.h"
#include "hrbench/refine_options.h"
#include "hrbench/scene.h"

namespace hrbench {

// A list of oracle class templates.
template <template <typename> class... Oracles>
struct OracleList {
    // Calls _f_ with a default-constructed tag OracleTag<Oracle> for each oracle in order.
    template <typename F>
    static void ForEach(F &&f) {
        (f(OracleTag<Oracles>{}), ...);
    }

    template <template <typename> class Oracle>
    struct OracleTag {
        template <typename Shape>
        using Type = Oracle<Shape>;
        static constexpr const OracleInfo &Info() { return Oracle<Segment>::kInfo; }
    };
};

using AllOracles = OracleList<GarmannOracle, HanrahanOracle, BFOracle>;

// Builds _Oracle_ for a run on _roots_: from the run's options where it reads more than
// the threshold (hanrahan and bf read RefineOptions::ffEstimate, bf also
// RefineOptions::estimate), else from options.eps. The one way
// refinement and check-links construct an oracle.
template <typename Oracle, typename Shape>
Oracle MakeOracle(const RefineOptions &options, const Patches<Shape> &roots) {
    if constexpr (std::is_constructible_v<Oracle, const RefineOptions &, const Patches<Shape> &>)
        return Oracle(options, roots);
    else
        return Oracle(options.eps, roots);
}

// The name, dimensions, parameters and doc line of every oracle, in registry order.
std::vector<OracleInfo> OracleInfos();

// The registry entry named _name_; throws InputError listing the names otherwise.
const OracleInfo &FindOracle(const std::string &name);

// The names of the oracles that read the option _option_ ("ff_estimate"), in registry order.
std::vector<std::string> OraclesReading(const std::string &option);

}  // namespace hrbench
