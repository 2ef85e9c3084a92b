#include "cmd/options.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

#include "generators.h"
#include "hrbench/count.h"
#include "hrbench/oracles/registry.h"
#include "hrbench/refine.h"
#include "hrbench/util/error.h"
#include "util/args.h"
#include "util/format.h"

namespace hrbench {

namespace {

// `--sweep`'s argument, "eps=V,V,..." or "min_area=V,V,..." (InputError otherwise).
SweepValues ParseSweep(const std::string &text) {
    size_t equals = text.find('=');
    SweepValues sweep{text.substr(0, equals), {}};
    if (equals == std::string::npos || (sweep.param != "eps" && sweep.param != "min_area"))
        throw InputError("--sweep needs eps=V,V,... or min_area=V,V,..., not '" + text + "'");
    std::string list = text.substr(equals + 1);
    std::istringstream words(list);
    for (std::string word; std::getline(words, word, ',');)
        sweep.values.push_back(ParseDouble(word, "--sweep " + sweep.param));
    if (sweep.values.empty() || list.back() == ',')
        throw InputError("--sweep needs numbers separated by commas after " + sweep.param +
                         "=, not '" + list + "'");
    return sweep;
}

// --max-links: a whole number of links, 0 to 2^63, in any notation ParseDouble reads
// (1e12).
uint64_t ParseMaxLinks(const std::string &text) {
    double links = ParseDouble(text, "--max-links");
    if (!(links >= 0 && links <= 9.2e18 && links == std::floor(links)))
        throw InputError("--max-links must be a whole number of links from 0 (no cap) to "
                         "9.2e18, not " +
                         text);
    return uint64_t(links);
}

int ClampedInt(const std::string &text, const std::string &flag) {
    return int(std::min<int64_t>(ParseInt(text, flag), 1 << 20));
}

// A size in MiB, 1 to 2^30 (1 PiB), in bytes.
size_t ParseMib(const std::string &text, const std::string &flag) {
    int64_t mib = ParseInt(text, flag);
    if (mib < 1 || mib > (int64_t(1) << 30))
        throw InputError(flag + " must be between 1 and 1073741824 MiB, not " + text);
    return size_t(mib) << 20;
}

// The names in a table of choices (oracles, methods, solvers), for the option's choices.
template <typename Table>
std::vector<std::string> ChoiceNames(const Table &table) {
    std::vector<std::string> names;
    for (const auto &entry : table)
        names.push_back(entry.name);
    return names;
}

// One help line per choice, "name: doc", the first marked as the default.
template <typename Table>
std::string ChoiceDoc(const Table &table) {
    std::string doc;
    for (const auto &entry : table)
        doc += std::string(doc.empty() ? "" : "\n") + entry.name +
               (doc.empty() ? " (default)" : "") + ": " + entry.doc;
    return doc;
}

// Why _flag_ does not apply to _command_, where more can be said than that.
std::string NotApplicable(const std::string &flag, const std::string &command) {
    if (command == "solve" && flag == "--count-only")
        return "--count-only does not apply to solve: it needs every link stored";
    if (command == "solve" && flag == "--method")
        return "--method does not apply to solve: it stores and enumerates every link (--solver "
               "chooses how it iterates)";
    return flag + " does not apply to " + command;
}

const std::vector<std::string> kRefining = {"run", "links", "solve"};
// The options that define what ProjectKernel links: check-links takes them too.
const std::vector<std::string> kLinking = {"run", "links", "check-links", "solve"};
// Where a scene comes from.
const std::vector<std::string> kSceneInput = {"run",  "links",      "check-links",
                                              "save", "dump-paths", "solve"};
// The commands that subdivide 3D patches (--subdivision).
const std::vector<std::string> kSubdividing = {"run", "links", "check-links", "solve",
                                               "dump-paths"};

}  // namespace

const std::vector<CommandSpec> &Commands() {
    static const std::vector<CommandSpec> commands = {
        {"run", "run SCENE [key=value ...] --eps E [options]",
         "refine a scene, print its counters"},
        {"links", "links SCENE [key=value ...] --eps E --out F.csv",
         "write every link (store mode) as CSV"},
        {"check-links", "check-links SCENE ... --eps E --links F",
         "validate a link dump (docs/probe.md): tiling, oracle, counts"},
        {"solve", "solve SCENE [key=value ...] --eps E [options]",
         "refine a scene and solve its radiosity on the hierarchy (docs/solve.md)"},
        {"dump-paths", "dump-paths SCENE ... --links IN --out OUT",
         "name a link dump's elements by paths, not corners (docs/dump-paths.md)"},
        {"save", "save SCENE [key=value ...] [--out F.json|F.obj]",
         "write a scene file (JSON), or a 3D scene as OBJ + MTL"},
        {"scenes", "scenes", "list scene families with their parameters, and the oracles"},
        {"capabilities", "capabilities --json",
         "describe families, oracles, methods, options and counters as JSON"},
    };
    return commands;
}

const std::vector<OptionSpec> &OptionTable() {
    using S = const std::string &;
    static const std::vector<OptionSpec> table = {
        {"eps",
         "--eps",
         "E",
         {},
         kLinking,
         "oracle threshold, a finite number > 0 (required)",
         [](Options &o, S v) { o.eps = ParseDouble(v, "--eps"); }},
        {"oracle", "--oracle", "NAME", ChoiceNames(OracleInfos()), kLinking,
         ChoiceDoc(OracleInfos()), [](Options &o, S v) { o.refine.oracle = FindOracle(v).name; }},
        {"ff_estimate", "--ff-estimate", "NAME", ChoiceNames(FfEstimates()), kLinking,
         "the form-factor estimate of the oracles " + JoinedNames(OraclesReading("ff_estimate")) +
             "\n(docs/conventions.md#oracles):\n" + ChoiceDoc(FfEstimates()),
         [](Options &o, S v) { o.refine.ffEstimate = ParseFfEstimate(v); }},
        {"min_area",
         "--min-area",
         "A",
         {},
         kLinking,
         "link a pair whose preferred element is smaller than A (length in\n2D, area in 3D; "
         "forced link)",
         [](Options &o, S v) { o.refine.minArea = ParseDouble(v, "--min-area"); }},
        {"sweep",
         "--sweep",
         "P=V,V,...",
         {},
         {"run"},
         "count the run at each value of P, eps or min_area, from one\nenumeration at "
         "the smallest (count-only, one thread; with --json one\nrecord per line, each "
         "with an equal share of the time in seconds)",
         [](Options &o, S v) { o.sweep = ParseSweep(v); },
         {{"method", "counts by enumeration"}, {"threads", "runs on one thread"}}},
        {"max_depth",
         "--max-depth",
         "D",
         {},
         kLinking,
         "link a pair whose preferred element has depth D (0..48; forced link)",
         [](Options &o, S v) { o.refine.maxDepth = ClampedInt(v, "--max-depth"); }},
        {"count_only",
         "--count-only",
         "",
         {},
         {"run"},
         "count links without storing them (default: store)",
         [](Options &o, S) { o.countOnly = true; }},
        {"link_form_factors",
         "--link-form-factors",
         "",
         {},
         {"run"},
         "also report the links' largest exact form factor, either way,\nand the share of "
         "links above eps (docs/solve.md; needs the\nlinks stored: not with --count-only, "
         "--method translation,\n--sweep)",
         [](Options &o, S) { o.linkFormFactors = true; },
         {{"sweep", "needs every link stored"}}},
        {"method",
         "--method",
         "M",
         ChoiceNames(Methods()),
         {"run"},
         ChoiceDoc(Methods()),
         [](Options &o, S v) { o.method = v; }},
        {"solver",
         "--solver",
         "S",
         ChoiceNames(SolveMethods()),
         {"solve"},
         ChoiceDoc(SolveMethods()),
         [](Options &o, S v) { o.solve.method = ParseSolveMethod(v); }},
        {"plain_gather",
         "--plain-gather",
         "",
         {},
         {"solve"},
         "HSA91's gather as published: no consistency scale of the\nleaves (docs/solve.md)",
         [](Options &o, S) { o.solve.plainGather = true; }},
        {"cluster_transfer",
         "--cluster-transfer",
         "T",
         ChoiceNames(ClusterTransfers()),
         {"solve"},
         "how light crosses a cluster link (docs/solve.md, Clusters):\n" +
             ChoiceDoc(ClusterTransfers()),
         [](Options &o, S v) { o.solve.clusterTransfer = ParseClusterTransfer(v); }},
        {"clusters",
         "--clusters",
         "",
         {},
         {"run", "links", "check-links", "solve"},
         "refine through a hierarchy of clusters of the root patches\n"
         "(docs/conventions.md#clusters; not with --method translation,\n--sweep); "
         "check-links: a dump with cluster links (docs/probe.md)",
         [](Options &o, S) { o.refine.clusters = true; },
         {{"sweep", "refines by enumeration"}}},
        {"cluster_bound",
         "--cluster-bound",
         "B",
         ChoiceNames(ClusterBounds()),
         {"run", "links", "check-links", "solve"},
         "with --clusters, which node pairs a link above the patches may\njoin "
         "(docs/conventions.md#clusters):\n" +
             ChoiceDoc(ClusterBounds()),
         [](Options &o, S v) { o.refine.clusterBound = ParseClusterBound(v); }},
        {"threads",
         "--threads",
         "N",
         {},
         kRefining,
         "worker threads (default 1); counts and ids never depend on N",
         [](Options &o, S v) { o.refine.threads = ClampedInt(v, "--threads"); }},
        {"max_memory",
         "--max-memory",
         "MIB",
         {},
         kRefining,
         "memory budget for elements and links in MiB (default: 90% of free)",
         [](Options &o, S v) { o.refine.memoryBudget = ParseMib(v, "--max-memory"); }},
        {"max_links",
         "--max-links",
         "N",
         {},
         kRefining,
         "refuse a run whose estimated links exceed N (default 1e11; 0:\nno cap; "
         "docs/limits.md#estimates)",
         [](Options &o, S v) { o.maxLinks = ParseMaxLinks(v); }},
        {"max_input",
         "--max-input",
         "MIB",
         {},
         kSceneInput,
         "size limit of a scene or mesh file in MiB (default 256)",
         [](Options &o, S v) { o.maxInputBytes = ParseMib(v, "--max-input"); }},
        {"json",
         "--json",
         "",
         {},
         {"run", "capabilities", "solve", "check-links"},
         "print one JSON object instead of a table",
         [](Options &o, S) { o.json = true; }},
        {"scene_file",
         "--scene-file",
         "F",
         {},
         kSceneInput,
         "load the scene from a JSON scene file instead of a family",
         [](Options &o, S v) { o.sceneFile = v; }},
        {"mesh",
         "--mesh",
         "F",
         {},
         kSceneInput,
         "load a 3D scene from an OFF or OBJ file (triangles, planar\nconvex quads; default "
         "reflectance 0.5, emission 0)",
         [](Options &o, S v) { o.mesh = v; }},
        {"triangulate",
         "--triangulate",
         "",
         {},
         kSceneInput,
         "with --mesh: split quads that are not planar or not convex\nand polygons of 5 or more "
         "corners into triangles (docs/3d.md)",
         [](Options &o, S) { o.triangulate = true; }},
        {"scale",
         "--scale",
         "S",
         {},
         kSceneInput,
         "with --mesh: multiply every coordinate by S, a finite number > 0\n(0.001 reads "
         "millimetres as metres)",
         [](Options &o, S v) {
             o.scale = ParseDouble(v, "--scale");
             if (!(*o.scale > 0))
                 throw InputError("--scale must be a finite number greater than 0, not " + v);
         }},
        {"subdivision",
         "--subdivision",
         "S",
         {"binary", "quadtree"},
         kSubdividing,
         "3D: binary (default, two halves across the longer edges) or\nquadtree (four children)",
         [](Options &o, S v) { o.refine.subdivision = ParseSubdivision(v); }},
        {"visibility",
         "--visibility",
         "V",
         {"none", "fraction", "refine"},
         kRefining,
         "none: ignore occlusion, as the papers do (run's and links'\ndefault); fraction: "
         "accept when the oracle's error times the\nvisible fraction is within eps (solve: and "
         "weigh each link's\nform factor by it); refine: split partially visible pairs down\n"
         "to the recursion limit (needs --min-area or --max-depth).\nsolve's default: fraction "
         "where, of 3 patches or more, one has\ncorners of the others strictly on both sides "
         "of its line or\nplane (it may block light between them), else none, then exact\n"
         "(docs/solve.md)",
         [](Options &o, S v) { o.visibility = ParseVisibility(v); }},
        {"rays_per_side",
         "--rays-per-side",
         "K",
         {},
         kRefining,
         "visibility samples per element side, 1..16 (default 3): K x K\nrays per pair in 2D, "
         "K^2 x K^2 in 3D; 3D rays are cast with Embree\nwhere the build has it (cmake "
         "-DHRBENCH_EMBREE=OFF: CGAL's\nAABB tree), with the same counts (docs/3d.md)",
         [](Options &o, S v) { o.refine.raysPerSide = ClampedInt(v, "--rays-per-side"); }},
        {"out",
         "--out",
         "F",
         {},
         {"links", "save", "solve", "dump-paths"},
         "output file (links: CSV; save: JSON, default standard output,\nor OBJ with an MTL "
         "library beside it where F ends in .obj;\nsolve: CSV, one row per leaf; dump-paths: "
         "the converted dump)",
         [](Options &o, S v) { o.out = v; }},
        {"format",
         "--format",
         "F",
         {"csv", "probe"},
         {"links"},
         "links: csv (default) or probe, the link dump of docs/probe.md\nthat check-links reads",
         [](Options &o, S v) { o.linksFormat = v; }},
        {"links",
         "--links",
         "F",
         {},
         {"check-links", "dump-paths"},
         "the link dump to check (docs/probe.md) or to convert",
         [](Options &o, S v) { o.linksFile = v; }},
        {"conventions",
         "--conventions",
         "C",
         {},
         {"check-links"},
         "the kernel's conventions: hrbench or \"KEY=VALUE ...\" (docs/probe.md);\na key the "
         "dump's conventions line also gives must agree",
         [](Options &o, S v) { o.linkConventions = v; }},
        {"summary",
         "--summary",
         "",
         {},
         {"check-links"},
         "list every violation by category and root pair on stdout",
         [](Options &o, S) { o.linkSummary = true; }},
        {"all",
         "--all",
         "",
         {},
         {"check-links"},
         "write every violation on stdout, one line each, as it is found\n(memory bounded "
         "whatever their number; --summary keeps the first 3\nof each category)",
         [](Options &o, S) { o.linkAll = true; },
         {{"json", "streams lines, not one JSON object"}}},
        {"tolerance",
         "--tolerance",
         "T",
         {},
         {"solve", "dump-paths"},
         "solve: stop when the largest change of a leaf's radiosity in a\nsweep, over the "
         "largest leaf radiosity, is below T (0 < T < 1;\ndefault 1e-6); dump-paths: match "
         "corners within T times the\ndiameter of their root patch (0 <= T < 0.01; default "
         "1e-5)",
         [](Options &o, S v) { o.tolerance = ParseDouble(v, "--tolerance"); }},
        {"max_iterations",
         "--max-iterations",
         "K",
         {},
         {"solve"},
         "sweeps allowed before giving up with exit code 3 (1..1000000;\ndefault 1000)",
         [](Options &o, S v) { o.solve.maxIterations = ClampedInt(v, "--max-iterations"); }},
        {"passes",
         "--passes",
         "K",
         {},
         {"solve"},
         "bf oracle only: refine-solve passes at most, each refining with\nB from the last "
         "solution, until links and nodes repeat (1..100;\ndefault 4; 1: refine with E once)",
         [](Options &o, S v) { o.solve.passes = ClampedInt(v, "--passes"); }},
        {"emission",
         "--emission",
         "E",
         {},
         {"solve"},
         "emitted radiosity of every patch, a finite number >= 0 (default:\nthe scene's)",
         [](Options &o, S v) { o.solve.emission = ParseDouble(v, "--emission"); }},
        {"reflectance",
         "--reflectance",
         "R",
         {},
         {"solve"},
         "reflectance of every patch, in [0, 1) (default: the scene's)",
         [](Options &o, S v) { o.solve.reflectance = ParseDouble(v, "--reflectance"); }},
        {"reference",
         "--reference",
         "D",
         {},
         {"solve"},
         "also solve the dense reference: every patch split to depth D,\nall pairs linked "
         "(at most 8192 elements); report it and the\nhierarchy's error against it",
         [](Options &o, S v) { o.solve.referenceDepth = ClampedInt(v, "--reference"); }},
    };
    return table;
}

std::string Usage() {
    std::ostringstream out;
    auto row = [&](const std::string &left, const std::string &doc, size_t width) {
        std::istringstream lines(doc);
        std::string line;
        for (bool first = true; std::getline(lines, line); first = false) {
            std::string label = first ? left : "";
            out << "  " << label
                << std::string(std::max(width, label.size() + 1) - label.size(), ' ') << line
                << "\n";
        }
    };
    out << "usage: hrbench <command> [arguments]\n\nCommands:\n";
    for (const CommandSpec &c : Commands())
        row(c.synopsis, c.doc, 48);
    out << "  (SCENE [key=value ...] may be replaced by --scene-file F.json or --mesh F)\n"
           "\nOptions:\n";
    for (const OptionSpec &o : OptionTable())
        row(o.flag + (o.value.empty() ? "" : " " + o.value), o.doc, 19);
    out << "\nGeneral:\n";
    row("--help", "print this text", 19);
    row("--version", "print the engine version", 19);
    out << "\nExit codes (docs/limits.md): 0 success, warnings and hints on stderr included;\n"
           "1 internal error (a bug); 2 usage or input error; 3 a limit was reached (memory\n"
           "budget or out of memory, safety depth, an element too small for double precision,\n"
           "a counter beyond 2^64, solve not converging or diverging); 4 check-links found a\n"
           "violation in the link dump.\n"
           "Example: hrbench run parallel l=64 d=1 --eps 0.25 --json\n";
    return out.str();
}

namespace {

// The entry of the option named _name_, a name the table itself uses (an exclusion).
const OptionSpec &FindOption(const std::string &name) {
    const auto &table = OptionTable();
    auto spec = std::find_if(table.begin(), table.end(),
                             [&](const OptionSpec &s) { return s.name == name; });
    if (spec == table.end())
        throw std::logic_error("the option table excludes an option it lacks: " + name);
    return *spec;
}

}  // namespace

Options ParseCommandLine(const std::vector<std::string> &args) {
    Options o;
    if (args.empty())
        throw InputError("no command given; see hrbench --help");
    o.command = args[0];
    const auto &commands = Commands();
    if (std::none_of(commands.begin(), commands.end(),
                     [&](const CommandSpec &c) { return c.name == o.command; }))
        throw InputError("unknown command '" + o.command + "'; see hrbench --help");

    // Apply every flag through its table entry, once; collect the scene and its parameters.
    std::set<std::string> seen;
    for (size_t k = 1; k < args.size(); ++k) {
        const std::string &a = args[k];
        const auto &table = OptionTable();
        auto spec = std::find_if(table.begin(), table.end(),
                                 [&](const OptionSpec &s) { return s.flag == a; });
        if (spec != table.end()) {
            if (!seen.insert(a).second)
                throw InputError("option " + a + " is given twice");
            if (std::find(spec->commands.begin(), spec->commands.end(), o.command) ==
                spec->commands.end())
                throw InputError(NotApplicable(a, o.command));
            std::string value;
            if (!spec->value.empty()) {
                if (k + 1 >= args.size())
                    throw InputError(a + " needs a value");
                value = args[++k];
            }
            const auto &choices = spec->choices;
            if (!choices.empty() &&
                std::find(choices.begin(), choices.end(), value) == choices.end()) {
                std::string names;
                for (const std::string &c : choices)
                    names += (names.empty() ? "" : ", ") + c;
                throw InputError("unknown " + spec->name + " '" + value +
                                 "' (choose one of: " + names + ")");
            }
            spec->apply(o, value);
        } else if (a.rfind("--", 0) == 0) {
            throw InputError("unknown option '" + a + "'; see hrbench --help");
        } else if (IsParamWord(a)) {
            o.params.push_back(a);
        } else if (o.scene.empty()) {
            o.scene = a;
        } else {
            throw InputError("unexpected argument '" + a + "'; see hrbench --help");
        }
    }

    // Reject the options given together that the table says exclude each other.
    for (const OptionSpec &spec : OptionTable())
        for (const OptionExclusion &x : spec.excludes)
            if (seen.count(spec.flag) && seen.count(FindOption(x.option).flag))
                throw InputError(spec.flag + " " + x.why + ", which " + FindOption(x.option).flag +
                                 " does not: drop one of them");

    // Reject combinations that make no sense, naming the flags.
    bool refines = o.command == "run" || o.command == "links" || o.command == "check-links" ||
                   o.command == "solve";
    if (refines || o.command == "save" || o.command == "dump-paths") {
        int sources = !o.scene.empty() + !o.sceneFile.empty() + !o.mesh.empty();
        if (sources != 1)
            throw InputError(o.command + " needs either a SCENE family, --scene-file or --mesh");
        if (o.scene.empty() && !o.params.empty())
            throw InputError(
                "key=value parameters apply to a family, not to --scene-file or --mesh");
        if (o.mesh.empty() && (o.triangulate || o.scale))
            throw InputError(std::string(o.triangulate ? "--triangulate" : "--scale") +
                             " applies to --mesh only");
    } else if (!o.scene.empty() || !o.params.empty()) {
        throw InputError(o.command + " takes no scene");
    }
    if (o.sweep) {
        bool eps = o.sweep->param == "eps";
        if (seen.count(eps ? "--eps" : "--min-area"))
            throw InputError(std::string("--sweep ") + o.sweep->param + " replaces " +
                             (eps ? "--eps" : "--min-area") + ": give one of them");
        if (eps)
            o.eps = o.sweep->values.front();  // each run's own is set when it is counted
    }
    if (o.refine.clusters && o.method != "enumerate")
        throw InputError(
            "--clusters refines by enumeration, which --method translation does not: drop one "
            "of them");
    if (seen.count("--cluster-bound") && !o.refine.clusters)
        throw InputError(
            "--cluster-bound says which pairs a cluster link may join: add --clusters");
    if (seen.count("--cluster-transfer") && !o.refine.clusters)
        throw InputError("--cluster-transfer is how light crosses cluster links: add --clusters");
    if (o.linkFormFactors) {
        const char *other = o.countOnly               ? "--count-only"
                            : o.method != "enumerate" ? "--method translation"
                                                      : nullptr;
        if (other)
            throw InputError(std::string("--link-form-factors needs every link stored, which ") +
                             other + " does not: drop one of them");
    }
    if (refines && !o.eps)
        throw InputError(o.command + " needs --eps");
    // check-links judges --ff-estimate against the dump's oracle when --oracle is not given
    // (ResolveConventions).
    bool dumpOracle = o.command == "check-links" && !seen.count("--oracle");
    if (seen.count("--ff-estimate") && !dumpOracle &&
        !FindOracle(o.refine.oracle).Reads("ff_estimate"))
        throw InputError("--ff-estimate applies to the oracles " +
                         JoinedNames(OraclesReading("ff_estimate")) + " only, not to " +
                         o.refine.oracle);
    if (o.command == "links" && o.out.empty())
        throw InputError("links needs --out F.csv");
    if (o.command == "check-links" && o.linksFile.empty())
        throw InputError("check-links needs --links F, the link dump to check");
    if (o.command == "dump-paths" && (o.linksFile.empty() || o.out.empty()))
        throw InputError("dump-paths needs --links IN, the dump to convert, and --out OUT");
    if (o.command == "dump-paths" && o.tolerance && !(*o.tolerance >= 0 && *o.tolerance < 0.01))
        throw InputError("--tolerance of dump-paths must be at least 0 and below 0.01, not " +
                         FormatDouble(*o.tolerance));
    if (o.command == "solve" && o.tolerance)
        o.solve.tolerance = *o.tolerance;
    o.oracleGiven = seen.count("--oracle");
    o.ffEstimateGiven = seen.count("--ff-estimate");
    if (o.command == "capabilities" && !o.json)
        throw InputError("capabilities prints JSON only; add --json");
    o.refine.eps = o.eps.value_or(0);
    o.refine.visibility = o.visibility.value_or(VisibilityMode::None);  // solve: see Main
    o.refine.storeLinks = o.command == "links" || !o.countOnly;
    return o;
}

}  // namespace hrbench
