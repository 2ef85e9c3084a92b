// The replay of ProjectKernel that check-links runs on each root pair whose links tile:
// Checker::Guide and Checker::Descend (internal to check-links, included by checker.h).
#pragma once

#include <array>
#include <string>

#include "checker.h"

namespace hrbench {

template <typename Shape, typename Oracle>
void Checker<Shape, Oracle>::Guide(size_t lo, size_t hi, uint32_t p, uint32_t q, uint32_t ex,
                                   uint32_t ey, std::string &x, std::string &y) {
    const auto ei = forest_[ex], ej = forest_[ey];
    auto pair = [&] { return ElementName(p, x) + " " + ElementName(q, y); };
    auto oracle = [&] {
        return std::string("the oracle ") + Oracle::kInfo.name + " (eps " +
               FormatDouble(options_.eps) + ")";
    };
    // The element the rule splits, and the limits on an element.
    const bool tieX = conv_.tie == LinkConventions::Tie::Receiver ||
                      (conv_.tie == LinkConventions::Tie::First && p < q) ||
                      (conv_.tie == LinkConventions::Tie::Second && p > q);
    const bool ruleX =
        ei.sizeSquared > ej.sizeSquared || (ei.sizeSquared == ej.sizeSquared && tieX);
    auto belowMinArea = [&](bool sideX) { return (sideX ? ei : ej).sizeSquared < minAreaBound_; };
    auto atMaxDepth = [&](bool sideX) {
        int depth = int(sideX ? x.size() : y.size());
        return options_.maxDepth >= 0 &&
               (conv_.maxDepthGt ? depth > depthLimit_ : depth >= depthLimit_);
    };
    auto limited = [&](bool sideX) { return belowMinArea(sideX) || atMaxDepth(sideX); };
    auto limitName = [&](bool sideX) {
        return belowMinArea(sideX) ? "--min-area " + FormatDouble(options_.minArea)
                                   : "--max-depth " + std::to_string(options_.maxDepth);
    };
    const bool exact = hi - lo == 1 && Side(order_[lo], true).depth == x.size() &&
                       Side(order_[lo], false).depth == y.size();
    const bool culled = ElementCulled(ex, ey);
    const bool judged = !conv_.ownOracle;

    if (!decided_) {
        if (culled) {  // no call: the region holds no link
            for (size_t k = lo; k < hi; ++k)
                v_.Add("culled-pair-linked", Line(order_[k]), true, p, q, [&] {
                    return LinkName(order_[k]) + " lies in the element pair " + pair() +
                           ", culled (cull=elements)";
                });
            return;
        }
        ++calls_;
        if (lo == hi)
            return v_.Add("missing-link", 0, true, p, q, [&] {
                return "nothing covers the element pair " + pair() + " of patches " +
                       std::to_string(p) + " and " + std::to_string(q);
            });
        const Judgement j = judged ? Judge(ei, ej) : Judgement::Either;
        // The element split: the rule's, or with split=recorded the side every link
        // inside is finer on (the first where both are).
        bool splitX = ruleX;
        if (conv_.splitRecorded && !exact) {
            splitX = true;
            for (size_t k = lo; k < hi && splitX; ++k)
                splitX = Side(order_[k], true).depth > x.size();
        }
        const bool limitHolds = limited(splitX);
        if (exact) {
            if (j == Judgement::Refuse && !limitHolds)
                return v_.Add("unacceptable-link", Line(order_[lo]), true, p, q, [&] {
                    return pair() + " is refused by " + oracle() +
                           " and no recursion limit forces it";
                });
            ++links_;
            forced_ += j == Judgement::Refuse;
            return;
        }
        if (j == Judgement::Accept)
            return v_.Add("unacceptable-link", Line(order_[lo]), true, p, q, [&] {
                return LinkName(order_[lo]) + " lies below the pair " + pair() + ", which " +
                       oracle() + " accepts";
            });
        if (limitHolds && j != Judgement::Either)
            return v_.Add("unacceptable-link", Line(order_[lo]), true, p, q, [&] {
                return LinkName(order_[lo]) + " lies below the pair " + pair() + ", where " +
                       limitName(splitX) + " forces a link";
            });
        if (limitHolds)
            return v_.Add("limit-mismatch", Line(order_[lo]), true, p, q, [&] {
                return LinkName(order_[lo]) + " lies below the pair " + pair() + ", where " +
                       limitName(splitX) + " forces a link";
            });
        std::string &side = splitX ? x : y;
        for (size_t k = lo; k < hi; ++k)
            if (Side(order_[k], splitX).depth <= side.size())
                return v_.Add("off-subdivision", Line(order_[k]), true, p, q, [&] {
                    return LinkName(order_[k]) + " keeps element " +
                           ElementName(splitX ? p : q, side) +
                           " whole, but ProjectKernel splits it in the refused pair " + pair() +
                           " (the larger element, ties the " + TieName() + ")";
                });
        return Descend(lo, hi, p, q, ex, ey, x, y, splitX);
    }

    // The recorded decision on this pair.
    auto found = decisionOf_.find(pair());
    if (found == decisionOf_.end())
        return v_.Add("missing-decision", lo < hi ? Line(order_[lo]) : 0, true, p, q, [&] {
            return "no decision is recorded for the pair " + pair() +
                   ", which ProjectKernel reaches through the recorded decisions";
        });
    const DumpDecision &d = dump_.decisions[found->second];
    reached_[found->second] = true;
    auto decided = [&] { return " (decide, line " + std::to_string(d.line) + ")"; };
    if (d.action == DumpAction::Cull) {
        if (!culled)
            v_.Add("cull-mismatch", d.line, true, p, q, [&] {
                return "the pair " + pair() + " is culled, but " +
                       (conv_.cull == LinkConventions::Cull::Elements
                            ? std::string("its centres do not face away (cull=elements)")
                            : "the conventions cull no element pair (cull=elements does)");
            });
        for (size_t k = lo; k < hi; ++k)
            v_.Add("culled-pair-linked", Line(order_[k]), true, p, q, [&] {
                return LinkName(order_[k]) + " lies in the element pair " + pair() +
                       ", which the kernel culls" + decided();
            });
        return;
    }
    ++calls_;
    if (culled)
        v_.Add("cull-mismatch", d.line, true, p, q, [&] {
            return "the pair " + pair() + " faces away (cull=elements), but the kernel " +
                   "calls the oracle on it" + decided();
        });
    const Judgement j = judged ? Judge(ei, ej) : Judgement::Either;
    if (d.action != DumpAction::Split) {
        const bool forced = d.action != DumpAction::Accept;
        if (lo == hi)
            return v_.Add("missing-link", d.line, true, p, q, [&] {
                return "nothing covers the element pair " + pair() + ", which the kernel links" +
                       decided();
            });
        if (!exact)
            return v_.Add("split-mismatch", Line(order_[lo]), true, p, q, [&] {
                return LinkName(order_[lo]) + " lies below the pair " + pair() +
                       ", which the kernel links whole" + decided();
            });
        ++links_;
        forced_ += forced;
        if (!forced && j == Judgement::Refuse)
            v_.Add("unacceptable-link", Line(order_[lo]), true, p, q, [&] {
                return pair() + " is accepted by the kernel but refused by " + oracle() + decided();
            });
        if (forced && j == Judgement::Accept)
            v_.Add("oracle-mismatch", d.line, true, p, q, [&] {
                return "the kernel forces a link on " + pair() + ", which " + oracle() + " accepts";
            });
        if (forced) {
            bool minArea = d.action == DumpAction::ForcedMinArea;
            auto holds = [&](bool sideX) {
                return minArea ? options_.minArea > 0 && belowMinArea(sideX) : atMaxDepth(sideX);
            };
            bool ok = conv_.splitRecorded ? holds(true) || holds(false) : holds(ruleX);
            if (!ok)
                v_.Add("limit-mismatch", d.line, true, p, q, [&] {
                    return "the kernel forces " + pair() + " by " +
                           (minArea ? "min_area" : "max_depth") + ", but " +
                           (minArea ? (options_.minArea > 0
                                           ? "--min-area " + FormatDouble(options_.minArea) +
                                                 " does not hold"
                                           : std::string("no --min-area is given"))
                                    : (options_.maxDepth >= 0
                                           ? "--max-depth " + std::to_string(options_.maxDepth) +
                                                 " does not hold"
                                           : std::string("no --max-depth is given"))) +
                           " for the limited element";
                });
        }
        return;
    }
    const bool splitX = d.splitI;
    std::string &side = splitX ? x : y;
    if (exact)
        return v_.Add("split-mismatch", Line(order_[lo]), true, p, q, [&] {
            return pair() + " is linked whole, but the kernel splits " +
                   ElementName(splitX ? p : q, side) + decided();
        });
    for (size_t k = lo; k < hi; ++k)
        if (Side(order_[k], splitX).depth <= side.size())
            return v_.Add("split-mismatch", Line(order_[k]), true, p, q, [&] {
                return LinkName(order_[k]) + " keeps element " + ElementName(splitX ? p : q, side) +
                       " whole, but the kernel splits it "
                       "in the pair " +
                       pair() + decided();
            });
    if (j == Judgement::Accept)
        v_.Add("oracle-mismatch", d.line, true, p, q, [&] {
            return "the kernel splits the pair " + pair() + ", which " + oracle() + " accepts";
        });
    if (!conv_.splitRecorded && splitX != ruleX)
        v_.Add("off-subdivision", d.line, true, p, q, [&] {
            return "the kernel splits " + ElementName(splitX ? p : q, side) + " in the pair " +
                   pair() + ", but the rule splits the larger element, ties the " + TieName() +
                   " (split=larger)";
        });
    if (limited(conv_.splitRecorded ? splitX : ruleX))
        v_.Add("limit-mismatch", d.line, true, p, q, [&] {
            return "the kernel splits the pair " + pair() + ", where " +
                   limitName(conv_.splitRecorded ? splitX : ruleX) + " forces a link";
        });
    if (int(side.size()) >= kSafetyDepth)
        return v_.Add("limit-mismatch", d.line, true, p, q, [&] {
            return "the kernel splits " + ElementName(splitX ? p : q, side) +
                   " beyond the safety depth " + std::to_string(kSafetyDepth);
        });
    Descend(lo, hi, p, q, ex, ey, x, y, splitX);
}

template <typename Shape, typename Oracle>
void Checker<Shape, Oracle>::Descend(size_t lo, size_t hi, uint32_t p, uint32_t q, uint32_t ex,
                                     uint32_t ey, std::string &x, std::string &y, bool splitX) {
    std::string &side = splitX ? x : y;
    uint32_t child = forest_.Children(splitX ? ex : ey);
    std::array<size_t, 5> begin = Partition(lo, hi, splitX, int(side.size()));
    for (int c = 0; c < arity_; ++c) {
        side.push_back(char('0' + c));
        if (splitX)
            Guide(begin[c], begin[c + 1], p, q, child + c, ey, x, y);
        else
            Guide(begin[c], begin[c + 1], p, q, ex, child + c, x, y);
        side.pop_back();
    }
}

}  // namespace hrbench
