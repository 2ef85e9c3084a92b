// What the parts of check-links share: reading a dump and its conventions (read.cpp),
// the counters it compares (output.cpp), and the violations (violations.h).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hrbench/check_links.h"
#include "violations.h"

namespace hrbench {

// The conventions of a dump: its line and --conventions merged (a key given by both
// must agree), and the oracle options they name.
LinkConventions ResolveConventions(const LinkDump &dump, const CheckLinksOptions &extra,
                                   RefineOptions &options);

// The dump as check-links checks it: undirected links (and decisions, unlinks) ordered
// by root, the unlinked links removed.
LinkDump Resolve(const LinkDump &dump, const LinkConventions &conv, Violations &violations);

// The counters that a dump and a check compare, by the counters line's names; with
// _clusters_ the cluster counters of the walk besides (by the run record's names).
const std::vector<std::pair<std::string, uint64_t Counters::*>> &
ComparedCounters(bool clusters = false);

// The value of counter _name_ that the record gives, if it gives one.
std::optional<uint64_t> FromRecord(const LinkCheck &check, const std::string &name);

}  // namespace hrbench
