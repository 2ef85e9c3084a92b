// The violations of a dump as check-links collects them (internal to check-links).
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "hrbench/check_links.h"

namespace hrbench {

// The name of an element given by its root and its path digits, as a dump writes it.
inline std::string ElementName(uint32_t root, const std::string &digits) {
    return digits.empty() ? std::to_string(root) : std::to_string(root) + "/" + digits;
}

// The categories of violations, in the order the summary lists them when tied: id (JSON)
// and the label that starts each message.
inline const std::vector<std::pair<std::string, std::string>> &Categories() {
    static const std::vector<std::pair<std::string, std::string>> categories = {
        {"link-within-patch", "link within one patch"},
        {"culled-pair-linked", "link between a culled pair"},
        {"bad-unlink", "unlink of no link"},
        {"missing-link", "missing link"},
        {"overlapping-link", "overlapping links"},
        {"off-subdivision", "link off the subdivision"},
        {"split-mismatch", "split inconsistent with its decision"},
        {"unacceptable-link", "unacceptable link"},
        {"oracle-mismatch", "decision against the oracle"},
        {"limit-mismatch", "recursion limit inconsistent"},
        {"cull-mismatch", "cull inconsistent"},
        {"missing-decision", "missing decision"},
        {"stray-decision", "stray decision"},
        {"bad-cluster", "cluster out of range"},
        {"link-within-cluster", "link within one cluster"},
        {"cluster-oracle", "unacceptable cluster link"},
        {"counter-mismatch", "counts"},
    };
    return categories;
}

// Collects violations with bounded memory: counts, the first few messages of each
// category and the counts of the first root pairs; and, given a stream, writes every
// message to it as it comes (check-links --all).
class Violations {
  public:
    static constexpr size_t kFirst = 3, kPairs = 100;

    explicit Violations(const std::string &file, std::ostream *every = nullptr) : every_(every) {
        summary_.file = file;
    }

    // A violation of _category_; _line_ 0 for none, _p_ and _q_ its root pair (or
    // direction) when _hasPair_; _what_ the message after the label (built only if kept).
    template <typename What>
    void Add(const std::string &category, size_t line, bool hasPair, uint32_t p, uint32_t q,
             const What &what) {
        LinkSummary::Category *c = nullptr;
        for (auto &k : summary_.categories)
            if (k.id == category)
                c = &k;
        if (!c) {
            std::string label;
            for (const auto &[id, l] : Categories())
                if (id == category)
                    label = l;
            summary_.categories.push_back({category, label, 0, {}});
            c = &summary_.categories.back();
        }
        if (c->first.size() < kFirst || summary_.total == 0 || every_) {
            std::string message = summary_.file + (line ? ":" + std::to_string(line) : "") + ": " +
                                  c->label + ": " + std::string(what());
            if (every_)
                *every_ << message << '\n';
            if (summary_.total == 0)
                summary_.firstMessage = message;
            if (c->first.size() < kFirst)
                c->first.push_back({line, hasPair, p, q, message});
        }
        ++c->count;
        ++summary_.total;
        if (hasPair) {
            auto key = std::make_pair(p, q);
            if (summary_.pairs.count(key) || summary_.pairs.size() < kPairs)
                ++summary_.pairs[key][category];
            else
                ++summary_.pairsLeftOff;
        }
    }

    uint64_t Total() const { return summary_.total; }
    LinkSummary Take() { return std::move(summary_); }

  private:
    LinkSummary summary_;
    std::ostream *every_;
};

}  // namespace hrbench
