// The link dump of include/hrbench/probe.h (docs/probe.md): every link as the paths of
// its two elements from their roots. Written by `hrbench links --format probe` and by
// other kernels through the probe, read by `hrbench check-links`.
#pragma once

#include <cstdint>
#include <istream>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "hrbench/refine.h"

namespace hrbench {

// An element of a dump: root patch and child path, whose digits (0 .. arity-1, one per
// level) lie in LinkDump::digits from _offset_ on.
struct DumpElement {
    uint32_t root;
    uint8_t depth;
    size_t offset;
};

// One link line of a dump (or an unlink record), its elements as written; check-links
// orders them so that i.root < j.root for undirected links (a kernel may write either
// order) and keeps receiver, source for directed ones.
struct DumpLink {
    DumpElement i, j;
    size_t line;  // 1-based line number in the dump
};

// A cluster link of a dump (--clusters): a line with a cluster token C<index> at one end
// at least, its other end a cluster or a root patch. Its ends are nodes as in clusters.h
// (kClusterBit set for a cluster, else the patch index), in the order written.
struct DumpClusterLink {
    uint32_t a, b;
    size_t line;
};

// What a kernel did in one ProjectKernel call (version 2, "decide X Y ACTION").
enum class DumpAction : uint8_t { Accept, Split, ForcedMinArea, ForcedMaxDepth, Cull };

struct DumpDecision {
    DumpElement i, j;
    DumpAction action;
    bool splitI;    // with Split: the element split is i (else j)
    uint32_t pass;  // 1-based
    size_t line;
};

// The tokens of a conventions text: KEY=VALUE (or a set name, value "") separated by
// spaces, commas or both, alike in a dump's conventions line, Probe(dump, conventions)
// and `check-links --conventions` (docs/probe.md#conventions).
std::vector<std::pair<std::string, std::string>> ParseConventionTokens(const std::string &text);

struct LinkDump {
    std::string name;  // the file, for messages
    int version = 1;
    std::string digits;                         // child digits of every element, back to back
    std::vector<DumpLink> links;                // every link line between elements, in dump order
    std::vector<DumpClusterLink> clusterLinks;  // every cluster link line, in dump order
    std::vector<DumpLink> unlinks;              // every unlink record, in dump order
    std::vector<DumpDecision> decisions;
    uint32_t passes = 1;
    // The conventions line's tokens (KEY=VALUE, or a set name with an empty value).
    std::vector<std::pair<std::string, std::string>> conventions;
    size_t conventionsLine = 0;
    // The kernel's own counters from the counters line, by name, in the line's order.
    std::vector<std::pair<std::string, uint64_t>> counters;
    size_t countersLine = 0;  // its line number, 0 when the dump has none

    int Digit(const DumpElement &e, int level) const { return digits[e.offset + level] - '0'; }
    // "3" or "3/0110", as the dump writes it.
    std::string Name(const DumpElement &e) const;
    // A node of a cluster link as the dump writes it: "C2" or "3".
    static std::string NodeName(uint32_t node);
};

// The names the counters line of a dump of _version_ may use.
const std::vector<std::string> &DumpCounterNames(int version = 1);

// Reads a dump for a scene of _numPatches_ patches and a subdivision of _arity_ children.
// Throws InputError "NAME:LINE: ..." for the first malformed line (bad header, token,
// digit or root, a path deeper than the safety depth, a repeated counters line).
LinkDump ReadLinkDump(std::istream &in, const std::string &name, int arity, size_t numPatches);

// Writes the stored links of _refinement_ as a dump: its element links, then its cluster
// links (--clusters) in traversal order, ending with its counters.
void WriteLinkDump(const AnyRefinement &refinement, std::ostream &out);

}  // namespace hrbench
