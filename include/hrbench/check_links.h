// `hrbench check-links`: validates a link dump (link_dump.h, docs/probe.md) against a
// scene and the oracle options: the links tile every refined root pair exactly, each is
// what ProjectKernel links under the oracle and the recursion limits, and the counts
// agree with the dump's counters line and with hrbench's own refinement.
#pragma once

#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "hrbench/link_dump.h"
#include "hrbench/record.h"
#include "hrbench/refine_options.h"
#include "hrbench/scene.h"
#include "hrbench/util/error.h"

namespace hrbench {

// Where a kernel's rules differ from hrbench's (docs/probe.md, "Conventions"); the
// defaults are hrbench's, the named set "hrbench".
struct LinkConventions {
    enum class Tie { First, Second, Receiver, Source };
    enum class Cull { Roots, Elements, None };
    bool directed = false;       // links=directed: one link per direction, receiver first
    Tie tie = Tie::First;        // tie=
    bool splitRecorded = false;  // split=recorded (else larger)
    bool acceptLt = false;       // accept=lt (else le)
    bool minAreaLe = false;      // min_area=le (else lt)
    bool maxDepthGt = false;     // max_depth=gt (else ge)
    Cull cull = Cull::Roots;     // cull=
    bool ownOracle = false;      // oracle=own
    std::vector<std::pair<std::string, std::string>> given;  // KEY=VALUE as resolved, for output

    // Whether these are hrbench's rules (the oracle aside).
    bool IsHrbench() const;
};

// What check-links takes besides the scene and the refinement options.
struct CheckLinksOptions {
    std::string conventions;  // --conventions: "hrbench" or "KEY=VALUE,..."
    bool oracleGiven = false, ffEstimateGiven = false;  // --oracle, --ff-estimate given
    std::ostream *every = nullptr;  // --all: each violation's message, a line, as found
};

// Every violation of one dump, by category and by root pair: counts and the first few
// messages (docs/probe.md, "The summary").
struct LinkSummary {
    struct Item {
        size_t line;  // 0: none
        bool hasPair;
        uint32_t p, q;
        std::string message;  // "FILE[:LINE]: label: what"
    };
    struct Category {
        std::string id, label;
        uint64_t count = 0;
        std::vector<Item> first;
    };
    std::string file;
    uint64_t total = 0;
    std::vector<Category> categories;  // in the order of their first violation
    std::map<std::pair<uint32_t, uint32_t>, std::map<std::string, uint64_t>> pairs;
    uint64_t pairsLeftOff = 0;  // violations of root pairs beyond the listed ones
    std::string firstMessage;
};

struct LinkCheck;

// A dump that breaks a rule: the message is the first violation, as one line
// "FILE:LINE: what: which link, why", with the count of all; exit code 4. _summary_
// holds all of them.
class LinkViolation : public Error {
  public:
    explicit LinkViolation(const std::string &message) : Error(message, kExitViolation) {}
    LinkViolation(const std::string &message, std::shared_ptr<const LinkSummary> summary,
                  std::shared_ptr<const LinkCheck> check)
        : Error(message, kExitViolation), summary(std::move(summary)), check(std::move(check)) {}
    std::shared_ptr<const LinkSummary> summary;
    std::shared_ptr<const LinkCheck> check;  // the counts recomputed, as far as they go
};

// What a dump amounts to.
struct LinkCheck {
    uint64_t rootPairs = 0, culledPairs = 0;
    Counters fromLinks;  // recomputed from the record: ProjectKernel's recursion down to it
    uint64_t totalOracleCalls = 0, passes = 1;         // from the decision records
    bool oracleCallsKnown = true, forcedKnown = true;  // whether the record gives them
    bool oracleCallsFromRecord = false;                // counted on the decision records
    bool treeComplete = true;  // the recursion down to the links went through: the
                               // counts it gives (nodes, max_depth, ...) are known
    bool clusters = false;     // --clusters: the dump's cluster links walked with the hierarchy
    bool engineCompared = false;
    Counters engine;  // hrbench's own refinement of the same scene and options
    LinkConventions conventions;
    std::string oracle;  // the oracle checked, "own" for none
};

// Checks _dump_ against _scene_ and _options_ (no visibility), in this order, and throws
// LinkViolation for the first violation: links within one patch or between a culled
// pair (dump order); the tiling of each refined root pair (scene order, depth first); the
// oracle, recursion limits and preferred subdivision (scene order, depth first); the
// counters line and hrbench's own counts. Throws InputError where Refine() does for the
// same scene and options (touching patches without a recursion limit) before any of
// these, and LimitError where Refine() does. Refine() runs last, once the dump has
// passed, so that the work and memory of a check grow with the dump, not the scene.
//
// With options.clusters (docs/probe.md, "Cluster links"), the root pairs checked are
// those the walk of the cluster hierarchy reaches past the dump's cluster links, each
// cluster link is checked with the cluster form of the oracle, and a pair covered twice
// is an overlap. A dump with cluster links needs it (InputError).
//
// Version 2 (docs/probe.md): under the dump's conventions (merged with _extra_'s), every
// check runs and every violation is collected; the LinkViolation thrown carries their
// summary. Throws InputError for conventions that are malformed or disagree.
LinkCheck CheckLinks(const Scene &scene, const RefineOptions &options, const LinkDump &dump,
                     const CheckLinksOptions &extra = {});

// The summary of the violations as text (one block per category, then per root pair).
void PrintLinkSummary(const LinkSummary &summary, std::ostream &out);

// The result as JSON (docs/probe.md, "The summary"): _summary_ null for a dump that passed.
std::string LinkCheckJson(const LinkDump &dump, const LinkSummary *summary, const LinkCheck *check);

// The summary of a passed check: one line, then the counters recomputed from the dump's
// links ("dump"), hrbench's ("hrbench") and, when the dump has a counters line, the
// kernel's own ("kernel"), side by side.
void PrintLinkCheck(const LinkCheck &check, const LinkDump &dump, const RefineOptions &options,
                    std::ostream &out);

}  // namespace hrbench
