#include "hrbench/link_dump.h"

#include <algorithm>
#include <charconv>
#include <system_error>

#include "hrbench/probe.h"
#include "hrbench/util/error.h"

namespace hrbench {

namespace {

// Reads one dump line by line, with the position for messages.
class DumpReader {
  public:
    DumpReader(const std::string &name, int arity, size_t numPatches, LinkDump &dump)
        : name_(name), arity_(arity), numPatches_(numPatches), dump_(dump) {}

    // Subsequent messages name line _line_.
    void At(size_t line) { line_ = line; }

    void Line(const std::string &text) {
        fields_.clear();
        for (size_t end = 0;;) {
            size_t begin = text.find_first_not_of(" \t", end);
            if (begin == std::string::npos)
                break;
            end = std::min(text.find_first_of(" \t", begin), text.size());
            fields_.push_back(text.substr(begin, end - begin));
        }
        const std::vector<std::string> &fields = fields_;
        if (fields.empty() || fields[0][0] == '#')
            return;
        if (fields[0] == "counters")
            return Counters(fields);
        if (dump_.version >= 2 && Record(fields))
            return;
        if (fields.size() != 2)
            Fail("expected a link, two elements ROOT or ROOT/PATH, or a counters line; got " +
                 std::to_string(fields.size()) + " fields");
        if (IsClusterToken(fields[0]) || IsClusterToken(fields[1])) {
            dump_.clusterLinks.push_back({Node(fields[0]), Node(fields[1]), line_});
            records_ = true;
            return;
        }
        DumpLink link{Element(fields[0]), Element(fields[1]), line_};
        if (dump_.version == 1 && link.i.root > link.j.root)
            std::swap(link.i, link.j);
        dump_.links.push_back(link);
        records_ = true;
    }

    [[noreturn]] void Fail(const std::string &what) const {
        throw InputError(name_ + ":" + std::to_string(line_) + ": " + what);
    }

  private:
    // The records of version 2 other than links; false for a link line.
    bool Record(const std::vector<std::string> &f) {
        const std::string &kind = f[0];
        if (kind == "conventions") {
            if (dump_.conventionsLine != 0)
                Fail("a second conventions line (the first is line " +
                     std::to_string(dump_.conventionsLine) + ")");
            if (records_)
                Fail("the conventions line must come before every link, unlink, decide and "
                     "pass record");
            dump_.conventionsLine = line_;
            std::string text;
            for (size_t k = 1; k < f.size(); ++k)
                text += f[k] + " ";
            dump_.conventions = ParseConventionTokens(text);
            return true;
        }
        if (kind == "pass") {
            uint32_t expected = records_ ? dump_.passes + 1 : 1;
            if (f.size() != 2 || f[1] != std::to_string(expected))
                Fail("expected 'pass " + std::to_string(expected) +
                     "': passes are numbered 1, 2, ... in order, pass 1 before any record");
            dump_.passes = expected;
            records_ = true;
            return true;
        }
        if (kind == "unlink") {
            if (f.size() != 3)
                Fail("expected 'unlink X Y', two elements");
            dump_.unlinks.push_back({Element(f[1]), Element(f[2]), line_});
            records_ = true;
            return true;
        }
        if (kind != "decide")
            return false;
        const char *usage = "expected 'decide X Y ACTION', ACTION accept, split Z, forced "
                            "min_area, forced max_depth or cull";
        if (f.size() < 4)
            Fail(usage);
        DumpDecision d{Element(f[1]), Element(f[2]), DumpAction::Accept,
                       false,         dump_.passes,  line_};
        const std::string &a = f[3];
        size_t want = 4;
        if (a == "accept")
            d.action = DumpAction::Accept;
        else if (a == "cull")
            d.action = DumpAction::Cull;
        else if (a == "forced" && f.size() == 5 && (f[4] == "min_area" || f[4] == "max_depth")) {
            d.action = f[4] == "min_area" ? DumpAction::ForcedMinArea : DumpAction::ForcedMaxDepth;
            want = 5;
        } else if (a == "split" && f.size() == 5) {
            if (f[4] != f[1] && f[4] != f[2])
                Fail("decide: the split element '" + f[4] + "' is neither " + f[1] + " nor " +
                     f[2]);
            d.action = DumpAction::Split;
            d.splitI = f[4] == f[1];
            want = 5;
        } else {
            Fail(usage);
        }
        if (f.size() != want)
            Fail(usage);
        dump_.decisions.push_back(d);
        records_ = true;
        return true;
    }

    static bool IsClusterToken(const std::string &token) { return token[0] == 'C'; }

    // An end of a cluster link: C<index> (a cluster, index below 2^31) or a root patch,
    // written as its root token.
    uint32_t Node(const std::string &token) {
        if (!IsClusterToken(token)) {
            if (token.find('/') != std::string::npos)
                Fail("element '" + token + "' in a cluster link: a root patch paired with a " +
                     "cluster is written as its root, never subdivided against it");
            return Element(token).root;
        }
        std::string index = token.substr(1);
        if (index.find('/') != std::string::npos)
            Fail("bad cluster '" + token + "': a cluster has no path");
        if (index.empty() ||
            !std::all_of(index.begin(), index.end(), [](char c) { return c >= '0' && c <= '9'; }))
            Fail("bad cluster '" + token + "': expected C<index>, the index a whole number");
        uint64_t value = 0;
        if (index.size() > 10 ||
            std::from_chars(index.data(), index.data() + index.size(), value).ec != std::errc() ||
            value >= kClusterBit)
            Fail("bad cluster '" + token + "': the index is beyond 2^31 - 1");
        return ClusterNode(uint32_t(value));
    }

    DumpElement Element(const std::string &token) {
        size_t slash = token.find('/');
        std::string root = token.substr(0, slash);
        if (root.empty() || root.size() > 10 ||
            !std::all_of(root.begin(), root.end(), [](char c) { return c >= '0' && c <= '9'; }))
            Fail("bad element '" + token + "': expected ROOT or ROOT/PATH");
        uint64_t r = std::stoull(root);
        if (r >= numPatches_)
            Fail("element '" + token + "': the scene has no patch " + root + " (" +
                 std::to_string(numPatches_) + " patches)");
        std::string path = slash == std::string::npos ? "" : token.substr(slash + 1);
        if (slash != std::string::npos && path.empty())
            Fail("bad element '" + token + "': empty path after '/'");
        if (path.size() > size_t(kSafetyDepth))
            Fail("element '" + token + "' is deeper than the safety depth " +
                 std::to_string(kSafetyDepth));
        for (char c : path)
            if (c < '0' || c >= '0' + arity_)
                Fail("bad element '" + token + "': path digits must be 0 to " +
                     std::to_string(arity_ - 1) + " with " + std::to_string(arity_) +
                     " children per element");
        DumpElement e{uint32_t(r), uint8_t(path.size()), dump_.digits.size()};
        dump_.digits += path;
        return e;
    }

    void Counters(const std::vector<std::string> &fields) {
        if (dump_.countersLine != 0)
            Fail("a second counters line (the first is line " + std::to_string(dump_.countersLine) +
                 ")");
        dump_.countersLine = line_;
        const auto &names = DumpCounterNames(dump_.version);
        for (size_t k = 1; k < fields.size(); ++k) {
            size_t eq = fields[k].find('=');
            std::string key = fields[k].substr(0, eq), value;
            if (eq != std::string::npos)
                value = fields[k].substr(eq + 1);
            if (std::find(names.begin(), names.end(), key) == names.end()) {
                std::string list;
                for (const auto &n : names)
                    list += (list.empty() ? "" : ", ") + n;
                Fail("unknown counter '" + key + "' (the counters line takes " + list +
                     " as NAME=VALUE)");
            }
            // Digits only (std::from_chars alone would take a sign or leave a tail), then
            // any value a counter can hold, up to 2^64 - 1.
            uint64_t number = 0;
            if (value.empty() || !std::all_of(value.begin(), value.end(),
                                              [](char c) { return c >= '0' && c <= '9'; }))
                Fail("counter " + key + " needs a whole number, as " + key + "=12");
            if (std::from_chars(value.data(), value.data() + value.size(), number).ec !=
                std::errc())
                Fail("counter " + key + "=" + value.substr(0, 40) +
                     (value.size() > 40 ? "..." : "") +
                     " is beyond 2^64 - 1 = 18446744073709551615, the largest counter");
            for (const auto &kv : dump_.counters)
                if (kv.first == key)
                    Fail("counter " + key + " is given twice");
            dump_.counters.push_back({key, number});
        }
    }

    const std::string &name_;
    int arity_;
    size_t numPatches_;
    LinkDump &dump_;
    size_t line_ = 0;
    bool records_ = false;             // a link, unlink, decide or pass record came
    std::vector<std::string> fields_;  // of the current line, reused
};

// The path of element _e_ from its root, through the forest's parents.
template <typename Shape>
probe::ElementPath PathOf(const Forest<Shape> &forest, uint32_t e) {
    probe::ElementPath path = probe::ElementPath::Root(forest[e].root);
    for (; forest.Parent(e) != e; e = forest.Parent(e))
        path.digits += char('0' + (e - forest[forest.Parent(e)].firstChild));
    std::reverse(path.digits.begin(), path.digits.end());
    return path;
}

}  // namespace

std::string LinkDump::Name(const DumpElement &e) const {
    std::string root = std::to_string(e.root);
    return e.depth == 0 ? root : root + "/" + digits.substr(e.offset, e.depth);
}

std::string LinkDump::NodeName(uint32_t node) {
    return IsCluster(node) ? "C" + std::to_string(ClusterIndex(node)) : std::to_string(node);
}

const std::vector<std::string> &DumpCounterNames(int version) {
    static const std::vector<std::string> names1 = {"links", "oracle_calls", "nodes",
                                                    "forced_links", "max_depth"};
    static const std::vector<std::string> names2 = {
        "links",     "oracle_calls",       "nodes", "forced_links",
        "max_depth", "total_oracle_calls", "passes"};
    return version >= 2 ? names2 : names1;
}

std::vector<std::pair<std::string, std::string>> ParseConventionTokens(const std::string &text) {
    std::vector<std::pair<std::string, std::string>> tokens;
    auto separator = [](char c) { return c == ',' || c == ' ' || c == '\t'; };
    for (size_t begin = 0; begin < text.size();) {
        if (separator(text[begin])) {
            ++begin;
            continue;
        }
        size_t end = begin;
        while (end < text.size() && !separator(text[end]))
            ++end;
        std::string token = text.substr(begin, end - begin);
        size_t eq = token.find('=');
        tokens.push_back(
            {token.substr(0, eq), eq == std::string::npos ? "" : token.substr(eq + 1)});
        begin = end;
    }
    return tokens;
}

LinkDump ReadLinkDump(std::istream &in, const std::string &name, int arity, size_t numPatches) {
    LinkDump dump;
    dump.name = name;
    DumpReader reader(name, arity, numPatches, dump);
    std::string text;
    size_t line = 0;
    while (std::getline(in, text)) {
        reader.At(++line);
        if (!text.empty() && text.back() == '\r')
            text.pop_back();
        if (line == 1) {
            if (text.find_last_not_of(" \t") != std::string::npos)
                text.erase(text.find_last_not_of(" \t") + 1);
            if (text == probe::kDumpHeader2)
                dump.version = 2;
            else if (text != probe::kDumpHeader)
                reader.Fail(std::string("not a link dump: the first line must be '") +
                            probe::kDumpHeader + "' or '" + probe::kDumpHeader2 +
                            "' (the versions this engine reads)");
            continue;
        }
        reader.Line(text);
    }
    if (in.bad())
        throw InputError("cannot read link dump '" + name + "'");
    if (line == 0) {
        reader.At(1);
        reader.Fail(std::string("empty file; a link dump starts with '") + probe::kDumpHeader +
                    "' or '" + probe::kDumpHeader2 + "'");
    }
    return dump;
}

void WriteLinkDump(const AnyRefinement &refinement, std::ostream &out) {
    std::visit(
        [&](const auto &r) {
            out << probe::kDumpHeader << '\n';
            for (const Link &link : r.links)
                probe::WriteLinkLine(out, PathOf(r.forest, link.i), PathOf(r.forest, link.j));
            for (const ClusterLink &link : r.clusterLinks)
                out << LinkDump::NodeName(link.a) << ' ' << LinkDump::NodeName(link.b) << '\n';
            const Counters &c = r.record.counters;
            probe::WriteCountersLine(out,
                                     {c.oracleCalls, c.links, c.nodes, c.forcedLinks, c.maxDepth});
        },
        refinement);
}

}  // namespace hrbench
