// A probe for another project's ProjectKernel: counters as hrbench counts them and a
// link sink that writes a link dump, which `hrbench check-links` validates against the
// scene (tiling, oracle, counts; docs/probe.md). Header-only and standard C++17 only:
// copy it into a project, or use the target hrbench::probe of the installed package.
//
//   hrbench::probe::Probe probe(&dumpFile);          // or Probe() to count only
//   ... for each root patch r:       probe.ElementCreated(0);
//   ... for each child created:      probe.ElementCreated(depth);
//   ... in ProjectKernel(i, j):      probe.OracleCall();
//   ... on a link:                   probe.Link(pathOf(i), pathOf(j), forced);
//   probe.Finish();                                  // writes the counters line
#pragma once

#include <algorithm>
#include <cstdint>
#include <ostream>
#include <stdexcept>
#include <string>

namespace hrbench {
namespace probe {

// The first line of every link dump: the format's name and version (docs/probe.md).
constexpr const char *kDumpHeader = "hrbench-link-dump 1";
// Version 2: conventions, decision, pass and unlink records.
constexpr const char *kDumpHeader2 = "hrbench-link-dump 2";

// An element as hrbench names it: the index of its root patch in scene order and the
// path of child indices from that root, one digit per level ('0' is the first child;
// up to '1' with binary subdivision, '3' with the quadtree). Written "3" for root 3 and
// "3/0110" for the second child of the second child of ... of the first child of root 3.
struct ElementPath {
    uint32_t root = 0;
    std::string digits;

    static ElementPath Root(uint32_t root) { return {root, {}}; }
    // The child _c_ (0-based, in hrbench's subdivision order) of this element.
    ElementPath Child(int c) const { return {root, digits + char('0' + c)}; }
    int Depth() const { return int(digits.size()); }
    std::string ToString() const {
        return digits.empty() ? std::to_string(root) : std::to_string(root) + "/" + digits;
    }
};

// What a ProjectKernel counts, named as in `hrbench run`.
struct Counters {
    uint64_t oracleCalls = 0;       // ProjectKernel calls, one oracle evaluation each
    uint64_t links = 0;             // forced links included
    uint64_t nodes = 0;             // elements created, roots included
    uint64_t forcedLinks = 0;       // links made by a recursion limit, not the oracle
    uint64_t maxDepth = 0;          // depth of the deepest element; roots have depth 0
    uint64_t totalOracleCalls = 0;  // version 2: all passes; oracleCalls is the last pass's
    uint64_t passes = 1;            // version 2
};

// The recursion limit that forced a link (version 2 decisions).
enum class Limit { MinArea, MaxDepth };

// One link line of a dump: the elements of the pair, either order.
inline void WriteLinkLine(std::ostream &out, const ElementPath &i, const ElementPath &j) {
    out << i.ToString() << ' ' << j.ToString() << '\n';
}

// The counters line that ends a dump; check-links compares it with the links.
inline void WriteCountersLine(std::ostream &out, const Counters &c) {
    out << "counters links=" << c.links << " oracle_calls=" << c.oracleCalls << " nodes=" << c.nodes
        << " forced_links=" << c.forcedLinks << " max_depth=" << c.maxDepth << '\n';
}

// Counts what a kernel reports and, given a stream, writes the link dump.
//
// Thread safety: a Probe is not thread safe (its counters are plain integers and a
// record takes several stream operations), so two threads must never call one Probe at
// the same time: a kernel that refines on several threads guards every call with a mutex
// of its own. (The C probe, include/hrbench/probe_c.h, also offers a part per thread,
// merged at the end; docs/probe-c.md.)
class Probe {
  public:
    // _dump_ (may be null: count only) receives the header now, a line per link and
    // the counters line at Finish(). A version 1 dump: hrbench's conventions, no
    // decisions.
    explicit Probe(std::ostream *dump = nullptr) : dump_(dump) {
        if (dump_)
            *dump_ << kDumpHeader << '\n';
    }

    // A version 2 dump, with the conventions line _conventions_ ("KEY=VALUE ...", as
    // docs/probe.md lists them; empty for hrbench's) and the decision records below.
    Probe(std::ostream *dump, const std::string &conventions) : dump_(dump), version2_(true) {
        if (dump_) {
            *dump_ << kDumpHeader2 << '\n';
            if (!conventions.empty())
                *dump_ << "conventions " << conventions << '\n';
        }
    }

    // Once per ProjectKernel call (each evaluates the oracle once). A version 2 probe
    // counts the calls through Accept, Split and Forced instead.
    void OracleCall() {
        ++counters_.oracleCalls;
        ++counters_.totalOracleCalls;
    }

    // Version 2 decisions, one per ProjectKernel call on the pair _i_ _j_ (receiver first
    // with directed links). Accept and Forced also write the link (Link() is not called
    // for them) unless _link_ is false: a later pass that keeps a live link. Split names
    // the element split, _i_ or _j_; Cull costs no oracle call.
    void Accept(const ElementPath &i, const ElementPath &j, bool link = true) {
        Decide(i, j, "accept");
        OracleCall();
        if (link)
            Link(i, j, false);
    }
    void Split(const ElementPath &i, const ElementPath &j, const ElementPath &split) {
        Decide(i, j, "split " + split.ToString());
        OracleCall();
    }
    void Forced(const ElementPath &i, const ElementPath &j, Limit limit, bool link = true) {
        Decide(i, j, limit == Limit::MinArea ? "forced min_area" : "forced max_depth");
        OracleCall();
        if (link)
            Link(i, j, true);
    }
    void Cull(const ElementPath &i, const ElementPath &j) { Decide(i, j, "cull"); }

    // Version 2: starts the next pass; oracleCalls counts that pass's calls from now.
    void Pass() {
        RequireVersion2();
        ++counters_.passes;
        counters_.oracleCalls = 0;
        if (dump_)
            *dump_ << "pass " << counters_.passes << '\n';
    }

    // Version 2: removes the live link _i_ _j_ (_forced_ as it was made).
    void Unlink(const ElementPath &i, const ElementPath &j, bool forced = false) {
        RequireVersion2();
        --counters_.links;
        counters_.forcedLinks -= forced;
        if (dump_)
            *dump_ << "unlink " << i.ToString() << ' ' << j.ToString() << '\n';
    }

    // Once per element when it is created: every root (depth 0), every child.
    void ElementCreated(int depth) {
        ++counters_.nodes;
        counters_.maxDepth = std::max<uint64_t>(counters_.maxDepth, uint64_t(depth));
    }

    // A link of elements _i_ and _j_; _forced_ when a recursion limit made it.
    void Link(const ElementPath &i, const ElementPath &j, bool forced = false) {
        ++counters_.links;
        counters_.forcedLinks += forced;
        if (dump_)
            WriteLinkLine(*dump_, i, j);
    }

    // Ends the dump with the counters line.
    void Finish() {
        if (!dump_)
            return;
        if (!version2_)
            return WriteCountersLine(*dump_, counters_);
        const Counters &c = counters_;
        *dump_ << "counters links=" << c.links << " oracle_calls=" << c.oracleCalls
               << " total_oracle_calls=" << c.totalOracleCalls << " passes=" << c.passes
               << " nodes=" << c.nodes << " forced_links=" << c.forcedLinks
               << " max_depth=" << c.maxDepth << '\n';
    }

    const Counters &Counts() const { return counters_; }

  private:
    void RequireVersion2() const {
        if (!version2_)
            throw std::logic_error("hrbench probe: decisions, passes and unlinks need a "
                                   "version 2 probe, Probe(dump, conventions)");
    }
    void Decide(const ElementPath &i, const ElementPath &j, const std::string &action) {
        RequireVersion2();
        if (dump_)
            *dump_ << "decide " << i.ToString() << ' ' << j.ToString() << ' ' << action << '\n';
    }

    std::ostream *dump_;
    bool version2_ = false;
    Counters counters_;
};

}  // namespace probe
}  // namespace hrbench
