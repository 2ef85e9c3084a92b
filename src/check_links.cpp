#include "hrbench/check_links.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <map>

#include "hrbench/culling.h"
#include "hrbench/forest.h"
#include "hrbench/oracles/registry.h"
#include "hrbench/refine.h"
#include "hrbench/util/format.h"

namespace hrbench {

namespace {

// The name of an element given by its root and its path digits, as a dump writes it.
std::string ElementName(uint32_t root, const std::string &digits) {
    return digits.empty() ? std::to_string(root) : std::to_string(root) + "/" + digits;
}

// The checks of one dump for one shape and one oracle. Every element pair is a region
// of its root pair's parameter domain: element x stands for the part of its root that
// its descendants cover, so pairs of tree elements tile exactly when their paths do,
// and the tiling is checked on paths alone, with no arithmetic.
template <typename Shape, typename Oracle>
class Checker {
  public:
    Checker(const Patches<Shape> &patches, const Oracle &oracle, const RefineOptions &options,
            const LinkDump &dump)
        : patches_(patches), oracle_(oracle), options_(options), dump_(dump),
          forest_(patches, SIZE_MAX, options.subdivision), arity_(forest_.Arity()),
          minAreaBound_(SquaredSizeBound(options.minArea)),
          depthLimit_(options.maxDepth >= 0 ? options.maxDepth : kSafetyDepth) {}

    LinkCheck Run() {
        LinkCheck check;
        // The refined root pairs in scene order, classified as Refine() does (touching
        // patches without a recursion limit refused first, as it refuses them). Each
        // needs a link of its own, so a dump of L links tiles at most L of them: L + 1
        // suffice to find the first it misses, and keep this check's memory, like its
        // work, within the dump's size however large the scene's refinement.
        std::vector<std::pair<uint32_t, uint32_t>> refined;
        const uint32_t n = uint32_t(patches_.size());
        for (uint32_t p = 0; p < n; ++p)
            for (uint32_t q = p + 1; q < n; ++q) {
                ++check.rootPairs;
                PairRelation relation = ClassifyPair(patches_[p].shape, patches_[q].shape);
                if (!RefinesRootPair(relation, p, q, options_))
                    ++check.culledPairs;
                else if (refined.size() <= dump_.links.size())
                    refined.push_back({p, q});
            }
        CheckPatches();
        SortByPair();
        for (auto [p, q] : refined) {
            auto [lo, hi] = Range(p, q);
            std::string x, y;
            Tile(lo, hi, p, q, x, y);
        }
        SortByPair();  // dump order again within each pair: violations name the first line
        for (auto [p, q] : refined) {
            auto [lo, hi] = Range(p, q);
            std::string x, y;
            Guide(lo, hi, p, q, x, y);
        }
        Counters &c = check.fromLinks;
        c.links = links_, c.oracleCalls = calls_, c.forcedLinks = forced_;
        c.nodes = forest_.Size();
        c.leaves = forest_.NumLeaves();
        c.nodesPerDepth = forest_.NodesPerDepth();
        c.maxDepth = c.nodesPerDepth.size() - 1;
        c.rootPairs = check.rootPairs, c.culledPairs = check.culledPairs;
        return check;
    }

  private:
    const DumpElement &Side(uint32_t link, bool first) const {
        const DumpLink &l = dump_.links[link];
        return first ? l.i : l.j;
    }
    std::string LinkName(uint32_t link) const {
        const DumpLink &l = dump_.links[link];
        return dump_.Name(l.i) + " " + dump_.Name(l.j);
    }
    [[noreturn]] void Fail(uint32_t link, const std::string &what) const {
        throw LinkViolation(dump_.name + ":" + std::to_string(dump_.links[link].line) + ": " +
                            what);
    }
    // Two links overlap: name the later line, and the earlier one.
    [[noreturn]] void Overlap(uint32_t a, uint32_t b) const {
        if (dump_.links[a].line < dump_.links[b].line)
            std::swap(a, b);
        Fail(a, "overlapping links: " + LinkName(a) + " overlaps " + LinkName(b) + " of line " +
                    std::to_string(dump_.links[b].line));
    }

    // Dump order: no link within one patch, none between a culled pair.
    void CheckPatches() {
        for (uint32_t k = 0; k < dump_.links.size(); ++k) {
            const DumpLink &l = dump_.links[k];
            if (l.i.root == l.j.root)
                Fail(k, "link within one patch: " + LinkName(k) + " (both elements of patch " +
                            std::to_string(l.i.root) + ")");
            if (Culled(l.i.root, l.j.root))
                Fail(k, "link between a culled pair: " + LinkName(k) + " (patches " +
                            std::to_string(l.i.root) + " and " + std::to_string(l.j.root) +
                            " cannot exchange light; hrbench never refines them)");
        }
    }

    // Whether the root pair of a dump link is culled, cached by pair: the dump's pairs
    // only, so that the cache stays within the dump's size.
    bool Culled(uint32_t p, uint32_t q) {
        auto key = std::make_pair(p, q);
        auto it = culled_.find(key);
        if (it == culled_.end())
            it = culled_
                     .emplace(key, ClassifyPair(patches_[p].shape, patches_[q].shape) ==
                                       PairRelation::Culled)
                     .first;
        return it->second;
    }

    // The links in order of root pair, each pair's in dump order.
    void SortByPair() {
        order_.resize(dump_.links.size());
        for (uint32_t k = 0; k < order_.size(); ++k)
            order_[k] = k;
        std::stable_sort(order_.begin(), order_.end(), [&](uint32_t a, uint32_t b) {
            const DumpLink &la = dump_.links[a], &lb = dump_.links[b];
            return std::make_pair(la.i.root, la.j.root) < std::make_pair(lb.i.root, lb.j.root);
        });
    }

    std::pair<size_t, size_t> Range(uint32_t p, uint32_t q) const {
        auto key = [&](uint32_t k) {
            return std::make_pair(dump_.links[k].i.root, dump_.links[k].j.root);
        };
        auto lo = std::partition_point(order_.begin(), order_.end(),
                                       [&](uint32_t k) { return key(k) < std::make_pair(p, q); });
        auto hi = std::partition_point(lo, order_.end(),
                                       [&](uint32_t k) { return key(k) == std::make_pair(p, q); });
        return {size_t(lo - order_.begin()), size_t(hi - order_.begin())};
    }

    // Reorders order_[lo, hi) stably by the path digit at _level_ of side _first_;
    // returns where each child's links begin (and the end).
    std::array<size_t, 5> Partition(size_t lo, size_t hi, bool first, int level) {
        scratch_.assign(order_.begin() + lo, order_.begin() + hi);
        std::array<size_t, 5> begin{};
        for (uint32_t k : scratch_)
            ++begin[dump_.Digit(Side(k, first), level) + 1];
        begin[0] = lo;
        for (int c = 1; c <= arity_; ++c)
            begin[c] += begin[c - 1];
        std::array<size_t, 5> next = begin;
        for (uint32_t k : scratch_)
            order_[next[dump_.Digit(Side(k, first), level)]++] = k;
        return begin;
    }

    // Tiling: the links order_[lo, hi) (those inside the region x * y of root pair p, q)
    // must cover it without overlap. Where no link covers the region whole, one side of
    // it has every link finer than the region: split that side (x first). If neither
    // side has, a link whole in x and one whole in y cross, so they overlap.
    void Tile(size_t lo, size_t hi, uint32_t p, uint32_t q, std::string &x, std::string &y) {
        if (lo == hi)
            throw LinkViolation(dump_.name + ": missing link: nothing covers the element pair " +
                                ElementName(p, x) + " " + ElementName(q, y) + " of patches " +
                                std::to_string(p) + " and " + std::to_string(q));
        const size_t dx = x.size(), dy = y.size();
        size_t wholeX = hi, wholeY = hi;
        for (size_t k = lo; k < hi; ++k) {
            bool coarseX = Side(order_[k], true).depth <= dx;
            bool coarseY = Side(order_[k], false).depth <= dy;
            if (coarseX && coarseY) {
                if (hi - lo > 1)
                    Overlap(order_[k], order_[k == lo ? lo + 1 : lo]);
                return;
            }
            if (coarseX && wholeX == hi)
                wholeX = k;
            if (coarseY && wholeY == hi)
                wholeY = k;
        }
        if (wholeX != hi && wholeY != hi)
            Overlap(order_[wholeX], order_[wholeY]);
        bool splitX = wholeX == hi;
        std::string &side = splitX ? x : y;
        std::array<size_t, 5> begin = Partition(lo, hi, splitX, int(side.size()));
        for (int c = 0; c < arity_; ++c) {
            side.push_back(char('0' + c));
            Tile(begin[c], begin[c + 1], p, q, x, y);
            side.pop_back();
        }
    }

    // ProjectKernel, guided by the links of the region (which tile it): the call on the
    // pair of elements ex (path x) and ey (path y) either links them, and then the
    // region is one link, or splits the larger element, and then every link lies in one
    // of its children.
    void Guide(size_t lo, size_t hi, uint32_t ex, uint32_t ey, std::string &x, std::string &y) {
        ++calls_;
        const auto ei = forest_[ex], ej = forest_[ey];
        const bool accept = oracle_.Acceptable(ei, ej);
        const bool splitX = ei.sizeSquared >= ej.sizeSquared;
        const double preferredSquared = splitX ? ei.sizeSquared : ej.sizeSquared;
        const int preferredDepth = int(splitX ? x.size() : y.size());
        const bool belowMinArea = preferredSquared < minAreaBound_;
        const bool atMaxDepth = options_.maxDepth >= 0 && preferredDepth >= depthLimit_;
        const bool forced = !accept && (belowMinArea || atMaxDepth);
        const uint32_t first = order_[lo];
        // The names for messages, built only for a violation.
        auto pair = [&] { return ElementName(ei.root, x) + " " + ElementName(ej.root, y); };
        auto oracle = [&] {
            return std::string("the oracle ") + Oracle::kInfo.name + " (eps " +
                   FormatDouble(options_.eps) + ")";
        };
        if (hi - lo == 1 && Side(first, true).depth == x.size() &&
            Side(first, false).depth == y.size()) {
            if (!accept && !forced)
                Fail(first, "unacceptable link: " + pair() + " is refused by " + oracle() +
                                " and no recursion limit forces it");
            ++links_;
            forced_ += forced;
            return;
        }
        if (accept)
            Fail(first, "unacceptable link: " + LinkName(first) + " lies below the pair " + pair() +
                            ", which " + oracle() + " accepts");
        if (forced)
            Fail(first, "unacceptable link: " + LinkName(first) + " lies below the pair " + pair() +
                            ", where " +
                            (belowMinArea ? "--min-area " + FormatDouble(options_.minArea)
                                          : "--max-depth " + std::to_string(options_.maxDepth)) +
                            " forces a link");
        std::string &side = splitX ? x : y;
        for (size_t k = lo; k < hi; ++k)
            if (Side(order_[k], splitX).depth <= side.size())
                Fail(order_[k], "link off the subdivision: " + LinkName(order_[k]) +
                                    " keeps element " +
                                    ElementName(splitX ? ei.root : ej.root, side) +
                                    " whole, but ProjectKernel splits it in the refused pair " +
                                    pair() + " (the larger element, ties the first)");
        uint32_t child = forest_.Children(splitX ? ex : ey);
        std::array<size_t, 5> begin = Partition(lo, hi, splitX, int(side.size()));
        for (int c = 0; c < arity_; ++c) {
            side.push_back(char('0' + c));
            if (splitX)
                Guide(begin[c], begin[c + 1], child + c, ey, x, y);
            else
                Guide(begin[c], begin[c + 1], ex, child + c, x, y);
            side.pop_back();
        }
    }

    const Patches<Shape> &patches_;
    const Oracle &oracle_;
    const RefineOptions &options_;
    const LinkDump &dump_;
    Forest<Shape> forest_;  // the elements ProjectKernel creates, in its order
    const int arity_;
    const double minAreaBound_;
    const int depthLimit_;
    std::map<std::pair<uint32_t, uint32_t>, bool> culled_;
    std::vector<uint32_t> order_, scratch_;
    uint64_t calls_ = 0, links_ = 0, forced_ = 0;
};

template <typename Shape>
LinkCheck CheckShape(const Scene &scene, const RefineOptions &options, const LinkDump &dump) {
    const Patches<Shape> &patches = scene.Get<Shape>();
    LinkCheck check;
    AllOracles::ForEach([&](auto tag) {
        using Oracle = typename decltype(tag)::template Type<Shape>;
        if constexpr (Oracle::kInfo.Supports(Shape::kDimension)) {
            if (options.oracle == Oracle::kInfo.name) {
                Oracle oracle = MakeOracle<Oracle>(options, patches);
                check = Checker<Shape, Oracle>(patches, oracle, options, dump).Run();
            }
        }
    });
    return check;
}

// The counters that a dump and a check compare, by the counters line's names.
const std::vector<std::pair<std::string, uint64_t Counters::*>> &ComparedCounters() {
    static const std::vector<std::pair<std::string, uint64_t Counters::*>> counters = {
        {"links", &Counters::links},
        {"oracle_calls", &Counters::oracleCalls},
        {"nodes", &Counters::nodes},
        {"forced_links", &Counters::forcedLinks},
        {"max_depth", &Counters::maxDepth}};
    return counters;
}

}  // namespace

LinkCheck CheckLinks(const Scene &scene, const RefineOptions &options, const LinkDump &dump) {
    if (options.visibility != VisibilityMode::None)
        throw InputError("check-links checks refinement without visibility: the links of a "
                         "root pair tile it only when no pair is occluded");
    RefineOptions counting = options;
    counting.storeLinks = false;
    counting.threads = 1;
    ValidateScene(scene);
    ValidateOptions(counting, scene.Dimension());
    // The dump first: that check's work and memory grow with the dump (Checker::Run). A
    // dump that passes it is ProjectKernel's refinement link for link, so hrbench's own
    // refinement, run after it, makes as many links as the dump holds: a tiny dump
    // before a refinement too large to finish fails quickly instead of waiting on it.
    LinkCheck check = scene.Dimension() == 2 ? CheckShape<Segment>(scene, options, dump)
                                             : CheckShape<Polygon>(scene, options, dump);
    check.engine =
        std::visit([&](auto &&r) { return std::move(r.record.counters); }, Refine(scene, counting));
    for (const auto &[name, field] : ComparedCounters()) {
        uint64_t fromLinks = check.fromLinks.*field;
        for (const auto &[key, value] : dump.counters)
            if (key == name && value != fromLinks)
                throw LinkViolation(dump.name + ":" + std::to_string(dump.countersLine) +
                                    ": counts: the counters line says " + name + "=" +
                                    std::to_string(value) + ", the links give " +
                                    std::to_string(fromLinks));
        if (check.engine.*field != fromLinks)
            throw LinkViolation(dump.name + ": counts: the links give " + name + " " +
                                std::to_string(fromLinks) + ", hrbench's refinement " +
                                std::to_string(check.engine.*field));
    }
    return check;
}

void PrintLinkCheck(const LinkCheck &check, const LinkDump &dump, const RefineOptions &options,
                    std::ostream &out) {
    const Counters &c = check.fromLinks;
    uint64_t refined = check.rootPairs - check.culledPairs;
    out << dump.name << ": ok: " << c.links << " links tile the " << refined << " refined root pair"
        << (refined == 1 ? "" : "s") << " exactly (" << check.culledPairs
        << " culled); every link is where ProjectKernel links with " << options.oracle << " eps "
        << FormatDouble(options.eps) << "; the counts agree\n";
    bool kernel = dump.countersLine != 0;
    char row[96];
    std::snprintf(row, sizeof row, "%-14s %14s %14s%s\n", "", "dump", "hrbench",
                  kernel ? "         kernel" : "");
    out << row;
    for (const auto &[name, field] : ComparedCounters()) {
        std::string reported = "-";
        for (const auto &[key, value] : dump.counters)
            if (key == name)
                reported = std::to_string(value);
        std::snprintf(row, sizeof row, "%-14s %14llu %14llu", name.c_str(),
                      (unsigned long long)(c.*field), (unsigned long long)(check.engine.*field));
        out << row;
        if (kernel) {
            std::snprintf(row, sizeof row, " %14s", reported.c_str());
            out << row;
        }
        out << "\n";
    }
}

}  // namespace hrbench
