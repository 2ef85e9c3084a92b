// What an oracle is: the rule that decides whether one element pair may be linked.
//
// An oracle is a class template over the shape, a small value type that the kernel
// instantiates once per run, so that its test compiles into the recursion:
//
//   template <typename Shape>
//   class MyOracle {
//     public:
//       static constexpr OracleInfo kInfo = {"mine", kFlatland | kSpace, "eps", "doc line"};
//       // Built once per run from the threshold and the root patches.
//       MyOracle(double eps, const Patches<Shape> &roots);
//       // Optional: built from all of the run's options instead, for an oracle that
//       // reads more than eps (hanrahan reads RefineOptions::ffEstimate, bf that and
//       // RefineOptions::estimate; kInfo.parameters names the options). MakeOracle()
//       // (registry.h), the one way the engine builds an oracle, prefers it.
//       MyOracle(const RefineOptions &options, const Patches<Shape> &roots);
//       // True when the pair may be linked. Both tests are marked [[gnu::always_inline]]:
//       // the recursion is one function, and an out-of-line test cost 7% of the hanrahan
//       // kernel's time when measured.
//       bool Acceptable(const Element<D> &i, const Element<D> &j) const;
//       // The same with the error weighted by the pair's visible fraction V in (0, 1]
//       // (--visibility fraction); with V = 1 it must decide as Acceptable() does.
//       bool AcceptableVisible(const Element<D> &i, const Element<D> &j, double V) const;
//   };
//
// Every oracle is listed once, in oracles/registry.h; docs/engine.md says how to add one.
#pragma once

#include <string_view>

namespace hrbench {

// How an oracle presents itself to the command line, the help text, the JSON and the
// capability listing.
constexpr unsigned kFlatland = 1u << 2;  // 2D scenes (segments)
constexpr unsigned kSpace = 1u << 3;     // 3D scenes (polygons)

struct OracleInfo {
    const char *name;        // as on the command line and in JSON
    unsigned dimensions;     // the scene dimensions it supports: kFlatland | kSpace
    const char *parameters;  // the options it reads, separated by spaces: "eps ff_estimate"
    const char *doc;         // one line: what it accepts

    constexpr bool Supports(int dimension) const { return (dimensions >> dimension) & 1u; }

    // Whether _option_ (an option's name, "ff_estimate") is one of _parameters_.
    constexpr bool Reads(std::string_view option) const {
        std::string_view rest = parameters;
        while (!rest.empty()) {
            auto end = rest.find(' ');
            if (rest.substr(0, end) == option)
                return true;
            rest = end == std::string_view::npos ? "" : rest.substr(end + 1);
        }
        return false;
    }
};

}  // namespace hrbench
