// check-links: reading a dump's conventions and the dump as it is checked.
#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "hrbench/oracles/registry.h"
#include "internal.h"
#include "util/format.h"

namespace hrbench {

namespace {

// Parses conventions tokens (KEY=VALUE, or the set name with an empty value) into
// _conv_, noting each key in _keys_; _where_ names the source for messages.
void ApplyConventions(const std::vector<std::pair<std::string, std::string>> &tokens,
                      const std::string &where, std::map<std::string, std::string> &keys) {
    static const std::map<std::string, std::vector<std::string>> values = {
        {"links", {"undirected", "directed"}},
        {"tie", {"first", "second", "receiver", "source"}},
        {"split", {"larger", "recorded"}},
        {"accept", {"le", "lt"}},
        {"min_area", {"lt", "le"}},
        {"max_depth", {"ge", "gt"}},
        {"cull", {"roots", "elements", "none"}},
        {"oracle", {}},
        {"ff_estimate", {}}};
    for (const auto &[key, value] : tokens) {
        if (value.empty() && key == "hrbench")
            continue;
        auto it = values.find(key);
        if (it == values.end())
            throw InputError(where + ": unknown convention '" + key +
                             "' (the named set hrbench, or links, tie, split, accept, min_area, "
                             "max_depth, cull, oracle, ff_estimate as KEY=VALUE)");
        if (!it->second.empty() &&
            std::find(it->second.begin(), it->second.end(), value) == it->second.end()) {
            std::string list;
            for (const auto &v : it->second)
                list += (list.empty() ? "" : ", ") + v;
            throw InputError(where + ": convention " + key + "=" + value + ": the values are " +
                             list);
        }
        if (value.empty())
            throw InputError(where + ": convention " + key + " needs a value, as " + key + "=...");
        if (keys.count(key))
            throw InputError(where + ": convention " + key + " is given twice");
        keys[key] = value;
    }
}

}  // namespace

// The conventions of a dump: its line and --conventions merged (a key given by both
// must agree), and the oracle options they name.
LinkConventions ResolveConventions(const LinkDump &dump, const CheckLinksOptions &extra,
                                   RefineOptions &options) {
    std::map<std::string, std::string> fromDump, fromLine;
    ApplyConventions(dump.conventions, dump.name + ":" + std::to_string(dump.conventionsLine),
                     fromDump);
    ApplyConventions(ParseConventionTokens(extra.conventions), "--conventions", fromLine);
    std::map<std::string, std::string> keys = fromDump;
    for (const auto &[key, value] : fromLine) {
        auto it = fromDump.find(key);
        if (it != fromDump.end() && it->second != value)
            throw InputError("--conventions " + key + "=" + value + " disagrees with the dump's " +
                             key + "=" + it->second + " (" + dump.name + ":" +
                             std::to_string(dump.conventionsLine) + ")");
        keys[key] = value;
    }
    LinkConventions c;
    auto is = [&](const char *key, const char *value) {
        auto it = keys.find(key);
        return it != keys.end() && it->second == value;
    };
    c.directed = is("links", "directed");
    if (c.directed && dump.version == 1)
        throw InputError(dump.name + ": links=directed needs a dump of version 2 (version 1 "
                                     "links stand for both directions)");
    c.tie = is("tie", "second")     ? LinkConventions::Tie::Second
            : is("tie", "receiver") ? LinkConventions::Tie::Receiver
            : is("tie", "source")   ? LinkConventions::Tie::Source
                                    : LinkConventions::Tie::First;
    if (!c.directed &&
        (c.tie == LinkConventions::Tie::Receiver || c.tie == LinkConventions::Tie::Source))
        throw InputError(dump.name + ": tie=" + keys["tie"] + " needs links=directed");
    c.splitRecorded = is("split", "recorded");
    c.acceptLt = is("accept", "lt");
    c.minAreaLe = is("min_area", "le");
    c.maxDepthGt = is("max_depth", "gt");
    c.cull = is("cull", "elements") ? LinkConventions::Cull::Elements
             : is("cull", "none")   ? LinkConventions::Cull::None
                                    : LinkConventions::Cull::Roots;
    c.ownOracle = is("oracle", "own");
    if (keys.count("oracle") && !c.ownOracle) {
        const std::string &name = keys["oracle"];
        bool known = false;
        for (const auto &info : OracleInfos())
            known = known || name == info.name;
        if (!known)
            throw InputError(dump.name + ": oracle=" + name +
                             " is no documented oracle (hrbench scenes lists them), nor own");
        if (extra.oracleGiven && options.oracle != name)
            throw InputError("--oracle " + options.oracle +
                             " disagrees with the dump's oracle=" + name);
        options.oracle = name;
    }
    // --ff-estimate is judged against the oracle in force: the dump's, else --oracle's.
    if (extra.ffEstimateGiven && !c.ownOracle && !FindOracle(options.oracle).Reads("ff_estimate"))
        throw InputError("--ff-estimate applies to the oracles " +
                         JoinedNames(OraclesReading("ff_estimate")) + " only, not to " +
                         options.oracle + (keys.count("oracle") ? ", the dump's oracle" : ""));
    if (keys.count("ff_estimate")) {
        const std::string &name = keys["ff_estimate"];
        FfEstimate estimate = ParseFfEstimate(name);
        if (extra.ffEstimateGiven && options.ffEstimate != estimate)
            throw InputError("--ff-estimate " + FfEstimateName(options.ffEstimate) +
                             " disagrees with the dump's ff_estimate=" + name);
        options.ffEstimate = estimate;
    }
    c.given.assign(keys.begin(), keys.end());
    return c;
}

// The dump as check-links checks it: undirected links (and decisions, unlinks) ordered
// by root, the unlinked links removed.
LinkDump Resolve(const LinkDump &dump, const LinkConventions &conv, Violations &violations) {
    LinkDump d = dump;
    if (!conv.directed) {
        for (DumpLink &l : d.links)
            if (l.i.root > l.j.root)
                std::swap(l.i, l.j);
        for (DumpLink &l : d.unlinks)
            if (l.i.root > l.j.root)
                std::swap(l.i, l.j);
        for (DumpDecision &x : d.decisions)
            if (x.i.root > x.j.root) {
                std::swap(x.i, x.j);
                x.splitI = !x.splitI;
            }
    }
    if (d.unlinks.empty())
        return d;
    std::unordered_map<std::string, std::vector<uint32_t>> live;
    std::vector<bool> removed(d.links.size(), false);
    size_t u = 0;
    auto unlink = [&](const DumpLink &l) {
        auto it = live.find(d.Name(l.i) + " " + d.Name(l.j));
        if (it == live.end() || it->second.empty())
            return violations.Add("bad-unlink", l.line, true, l.i.root, l.j.root, [&] {
                return "unlink " + d.Name(l.i) + " " + d.Name(l.j) + " removes no live link";
            });
        removed[it->second.back()] = true;
        it->second.pop_back();
    };
    for (uint32_t k = 0; k < d.links.size(); ++k) {
        for (; u < d.unlinks.size() && d.unlinks[u].line < d.links[k].line; ++u)
            unlink(d.unlinks[u]);
        live[d.Name(d.links[k].i) + " " + d.Name(d.links[k].j)].push_back(k);
    }
    for (; u < d.unlinks.size(); ++u)
        unlink(d.unlinks[u]);
    std::vector<DumpLink> kept;
    for (uint32_t k = 0; k < d.links.size(); ++k)
        if (!removed[k])
            kept.push_back(d.links[k]);
    d.links = std::move(kept);
    return d;
}

bool LinkConventions::IsHrbench() const {
    return !directed && tie == Tie::First && !splitRecorded && !acceptLt && !minAreaLe &&
           !maxDepthGt && cull == Cull::Roots && !ownOracle;
}

}  // namespace hrbench
