// What a refinement will cost, estimated before it starts: elements, links and memory,
// from a pilot refinement at a coarser eps scaled by the laws hrbench checks
// (docs/limits.md#estimates). A run whose estimate exceeds its memory budget or its link
// cap stops at once with exit code 3, instead of filling the machine's memory or
// counting for days.
#pragma once

#include <cstdint>
#include <string>

#include "hrbench/refine_options.h"

namespace hrbench {

struct Scene;

// Default of --max-links: 1e11 links, an hour or more of counting on one core.
constexpr uint64_t kDefaultMaxLinks = 100'000'000'000;

// The estimate of one run, field by field.
struct RunEstimate {
    double elements = 0;  // elements of every tree (the counter nodes)
    double links = 0;     // links (the counter links)
    double bytes = 0;     // memory the run keeps: element trees, stored links (solve: its arrays)
    double pilotEps = 0;  // eps of the pilot refinement the estimate scales from; 0: none
    bool exact = false;   // the pilot was the run itself: elements and links are its counts
    std::string basis;    // how it was made, for messages: "scaled from a refinement at eps 0.016"
};

// Estimates a `run`, `links` or `solve` (_command_) with _options_ and --method _method_:
// count-only pilots at eps 4^k eps, from the coarsest whose scaled estimate could pass
// the caps down to the first that passes them (or eps itself, or the one whose 16 MiB
// pilot budget runs out), scaled by N ~ eps^-a and L ~ eps^-b with a and b the larger of
// the pilots' local exponents and the laws' 1 and 2 (N = Theta(g eps^-1), L = Theta(N
// eps^-1) in 2D, g^2 in 3D), the elements held to what a recursion limit allows; the
// translation method by its states instead (4/eps per level in 2D, 16/eps in 3D).
RunEstimate EstimateRun(const Scene &scene, const RefineOptions &options,
                        const std::string &command, const std::string &method, uint64_t maxLinks);

// Throws LimitError (exit code 3) when _estimate_ exceeds the memory budget of _options_
// or _maxLinks_ (0: no link cap), naming the estimate and the option that raises the cap.
void CheckEstimate(const RunEstimate &estimate, const RefineOptions &options,
                   const std::string &method, uint64_t maxLinks);

}  // namespace hrbench
