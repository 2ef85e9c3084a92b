// `hrbench check-links`: validates a link dump (link_dump.h, docs/probe.md) against a
// scene and the oracle options: the links tile every refined root pair exactly, each is
// what ProjectKernel links under the oracle and the recursion limits, and the counts
// agree with the dump's counters line and with hrbench's own refinement.
#pragma once

#include <ostream>
#include <string>

#include "hrbench/link_dump.h"
#include "hrbench/record.h"
#include "hrbench/refine_options.h"
#include "hrbench/scene.h"
#include "hrbench/util/error.h"

namespace hrbench {

// The first rule a dump breaks, as one line "FILE:LINE: what: which link, why"; exit
// code 4.
class LinkViolation : public Error {
  public:
    explicit LinkViolation(const std::string &message) : Error(message, kExitViolation) {}
};

// What a dump that passes every check amounts to.
struct LinkCheck {
    uint64_t rootPairs = 0, culledPairs = 0;
    Counters fromLinks;  // recomputed from the links: ProjectKernel's recursion down to them
    Counters engine;     // hrbench's own refinement of the same scene and options
};

// Checks _dump_ against _scene_ and _options_ (no visibility), in this order, and throws
// LinkViolation for the first violation: links within one patch or between a culled
// pair (dump order); the tiling of each refined root pair (scene order, depth first); the
// oracle, recursion limits and preferred subdivision (scene order, depth first); the
// counters line and hrbench's own counts. Throws InputError where Refine() does for the
// same scene and options (touching patches without a recursion limit) before any of
// these, and LimitError where Refine() does. Refine() runs last, once the dump has
// passed, so that the work and memory of a check grow with the dump, not the scene.
LinkCheck CheckLinks(const Scene &scene, const RefineOptions &options, const LinkDump &dump);

// The summary of a passed check: one line, then the counters recomputed from the dump's
// links ("dump"), hrbench's ("hrbench") and, when the dump has a counters line, the
// kernel's own ("kernel"), side by side.
void PrintLinkCheck(const LinkCheck &check, const LinkDump &dump, const RefineOptions &options,
                    std::ostream &out);

}  // namespace hrbench
