// check-links: the counters it compares, and its output: the line of a passing check,
// the summary and the JSON.
#include <algorithm>
#include <optional>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "internal.h"
#include "util/format.h"

namespace hrbench {

// The counters that a dump and a check compare, by the counters line's names.
const std::vector<std::pair<std::string, uint64_t Counters::*>> &ComparedCounters(bool clusters) {
    static const std::vector<std::pair<std::string, uint64_t Counters::*>> counters = {
        {"links", &Counters::links},
        {"oracle_calls", &Counters::oracleCalls},
        {"nodes", &Counters::nodes},
        {"forced_links", &Counters::forcedLinks},
        {"max_depth", &Counters::maxDepth}};
    static const std::vector<std::pair<std::string, uint64_t Counters::*>> withClusters = [] {
        auto all = counters;
        all.insert(all.end(), {{"cluster_links", &Counters::clusterLinks},
                               {"element_links", &Counters::elementLinks},
                               {"cluster_oracle_calls", &Counters::clusterOracleCalls},
                               {"opened_clusters", &Counters::openedClusters},
                               {"root_pairs", &Counters::rootPairs}});
        return all;
    }();
    return clusters ? withClusters : counters;
}

// The value of counter _name_ that the record gives, if it gives one.
std::optional<uint64_t> FromRecord(const LinkCheck &check, const std::string &name) {
    if (name == "total_oracle_calls" &&
        (check.oracleCallsFromRecord || (check.treeComplete && check.oracleCallsKnown)))
        return check.totalOracleCalls;
    if (name == "total_oracle_calls")
        return std::nullopt;
    if (name == "passes")
        return check.passes;
    if (name == "links")
        return check.fromLinks.links;
    if (check.clusters && (name == "cluster_links" || name == "element_links"))
        return name == "cluster_links" ? check.fromLinks.clusterLinks
                                       : check.fromLinks.elementLinks;
    // The rest come from ProjectKernel's recursion down to the links, once it went through.
    if (name == "oracle_calls" && check.oracleCallsKnown && check.oracleCallsFromRecord)
        return check.fromLinks.oracleCalls;
    if (!check.treeComplete || (name == "oracle_calls" && !check.oracleCallsKnown) ||
        (name == "forced_links" && !check.forcedKnown))
        return std::nullopt;
    for (const auto &[key, field] : ComparedCounters(check.clusters))
        if (key == name)
            return check.fromLinks.*field;
    return std::nullopt;
}

void PrintLinkCheck(const LinkCheck &check, const LinkDump &dump, const RefineOptions &options,
                    std::ostream &out) {
    const Counters &c = check.fromLinks;
    uint64_t refined = check.rootPairs - check.culledPairs;
    if (check.clusters)
        out << dump.name << ": ok: " << c.links << " links (" << c.clusterLinks << " cluster link"
            << (c.clusterLinks == 1 ? "" : "s") << ") cover every root pair once, the " << refined
            << " refined root pair" << (refined == 1 ? "" : "s")
            << " the hierarchy reaches tiled exactly (" << check.culledPairs << " culled); ";
    else
        out << dump.name << ": ok: " << c.links << " links tile the " << refined
            << " refined root pair" << (refined == 1 ? "" : "s")
            << (check.conventions.directed ? ", each direction," : "") << " exactly ("
            << check.culledPairs << " culled); ";
    if (check.oracle == "own")
        out << "every decision is consistent with the links (the kernel's own oracle)";
    else
        out << "every link is where ProjectKernel links with " << check.oracle << " eps "
            << FormatDouble(options.eps);
    out << "; the counts agree\n";
    if (!check.conventions.IsHrbench()) {
        out << "conventions:";
        for (const auto &[key, value] : check.conventions.given)
            out << " " << key << "=" << value;
        out << "\n";
    }
    bool kernel = dump.countersLine != 0;
    char row[96];
    // total_oracle_calls, cluster_oracle_calls
    const int width = check.clusters ? 20 : dump.version >= 2 ? 18 : 14;
    std::snprintf(row, sizeof row, "%-*s %14s %14s%s\n", width, "", "dump", "hrbench",
                  kernel ? "         kernel" : "");
    out << row;
    std::vector<std::string> names;
    for (const auto &[name, field] : ComparedCounters(check.clusters))
        names.push_back(name);
    if (dump.version >= 2)
        names.insert(names.end(), {"total_oracle_calls", "passes"});
    for (const std::string &name : names) {
        std::string reported = "-", engine = "-", record = "-";
        for (const auto &[key, value] : dump.counters)
            if (key == name)
                reported = std::to_string(value);
        if (auto v = FromRecord(check, name))
            record = std::to_string(*v);
        for (const auto &[key, field] : ComparedCounters(check.clusters))
            if (key == name && check.engineCompared)
                engine = std::to_string(check.engine.*field);
        std::snprintf(row, sizeof row, "%-*s %14s %14s", width, name.c_str(), record.c_str(),
                      engine.c_str());
        out << row;
        if (kernel) {
            std::snprintf(row, sizeof row, " %14s", reported.c_str());
            out << row;
        }
        out << "\n";
    }
}

void PrintLinkSummary(const LinkSummary &summary, std::ostream &out) {
    out << summary.file << ": " << summary.total << " violation" << (summary.total == 1 ? "" : "s")
        << " in " << summary.categories.size() << " categor"
        << (summary.categories.size() == 1 ? "y" : "ies") << "\n";
    for (const auto &c : summary.categories) {
        out << c.id << " (" << c.label << "): " << c.count << "\n";
        for (const auto &item : c.first)
            out << "  " << item.message << "\n";
        if (c.count > c.first.size())
            out << "  ... " << c.count - c.first.size() << " more\n";
    }
    if (!summary.pairs.empty())
        out << "by root pair:\n";
    for (const auto &[pair, counts] : summary.pairs) {
        uint64_t total = 0;
        std::string list;
        for (const auto &[id, n] : counts) {
            total += n;
            list += (list.empty() ? "" : ", ") + id + " " + std::to_string(n);
        }
        out << "  " << pair.first << " " << pair.second << ": " << total << " (" << list << ")\n";
    }
    if (summary.pairsLeftOff)
        out << "  ... " << summary.pairsLeftOff << " more on further root pairs\n";
}

std::string LinkCheckJson(const LinkDump &dump, const LinkSummary *summary,
                          const LinkCheck *check) {
    nlohmann::ordered_json j;
    j["file"] = dump.name;
    j["ok"] = summary == nullptr;
    j["violations"] = summary ? summary->total : 0;
    nlohmann::ordered_json categories = nlohmann::ordered_json::array();
    nlohmann::ordered_json pairs = nlohmann::ordered_json::array();
    if (summary) {
        for (const auto &c : summary->categories) {
            nlohmann::ordered_json first = nlohmann::ordered_json::array();
            for (const auto &item : c.first) {
                nlohmann::ordered_json i;
                i["line"] = item.line ? nlohmann::ordered_json(item.line) : nullptr;
                i["pair"] = item.hasPair ? nlohmann::ordered_json({item.p, item.q}) : nullptr;
                i["message"] = item.message;
                first.push_back(i);
            }
            categories.push_back(
                {{"category", c.id}, {"label", c.label}, {"count", c.count}, {"first", first}});
        }
        for (const auto &[pair, counts] : summary->pairs) {
            uint64_t total = 0;
            nlohmann::ordered_json byCategory = nlohmann::ordered_json::object();
            for (const auto &[id, n] : counts) {
                total += n;
                byCategory[id] = n;
            }
            pairs.push_back({{"pair", {pair.first, pair.second}},
                             {"count", total},
                             {"categories", byCategory}});
        }
    }
    j["categories"] = categories;
    j["root_pairs"] = pairs;
    j["root_pairs_left_off"] = summary ? summary->pairsLeftOff : 0;
    if (check) {
        nlohmann::ordered_json conventions = nlohmann::ordered_json::object();
        for (const auto &[key, value] : check->conventions.given)
            conventions[key] = value;
        j["conventions"] = conventions;
        j["oracle"] = check->oracle;
        nlohmann::ordered_json record = nlohmann::ordered_json::object(),
                               kernel = nlohmann::ordered_json::object(),
                               engine = nlohmann::ordered_json::object();
        std::vector<std::string> names = DumpCounterNames(2);
        for (const auto &[name, field] : ComparedCounters(check->clusters))
            if (std::find(names.begin(), names.end(), name) == names.end())
                names.push_back(name);
        for (const std::string &name : names) {
            auto v = FromRecord(*check, name);
            record[name] = v ? nlohmann::ordered_json(*v) : nullptr;
        }
        for (const auto &[key, value] : dump.counters)
            kernel[key] = value;
        if (check->engineCompared)
            for (const auto &[name, field] : ComparedCounters(check->clusters))
                engine[name] = check->engine.*field;
        j["counters"] = {
            {"dump", record},
            {"kernel", dump.countersLine ? kernel : nlohmann::ordered_json(nullptr)},
            {"hrbench", check->engineCompared ? engine : nlohmann::ordered_json(nullptr)}};
    }
    return j.dump();
}

}  // namespace hrbench
