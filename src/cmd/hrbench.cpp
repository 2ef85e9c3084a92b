// hrbench: refine a scene with ProjectKernel and report exact counters.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cmd/capabilities.h"
#include "cmd/options.h"
#include "count/sweep_count.h"
#include "generators.h"
#include "hrbench/hrbench.h"
#include "hrbench/util/input_file.h"
#include "io/dump_paths.h"
#include "refine/progress.h"
#include "util/args.h"
#include "util/format.h"
#include "util/output.h"
#include "visibility/culling.h"

namespace hrbench {
namespace {

Scene SceneOf(const Options &o) {
    if (!o.mesh.empty())
        return LoadMesh(o.mesh, o.maxInputBytes, {o.triangulate, o.scale.value_or(1)});
    if (!o.sceneFile.empty())
        return LoadScene(o.sceneFile, o.maxInputBytes, o.command != "check-links");
    return MakeScene(o.scene, ParseParams(o.params));
}

// The extension of the file _out_ in lower case ("obj"), "" if none.
std::string ExtensionOf(const std::string &out) {
    size_t dot = out.find_last_of('.');
    std::string ext = dot == std::string::npos ? "" : out.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

// The files the command writes: --out, and beside an OBJ that `save` writes its MTL.
std::vector<std::string> OutputPaths(const Options &o) {
    std::vector<std::string> paths;
    if (!o.out.empty())
        paths.push_back(o.out);
    if (o.command == "save" && ExtensionOf(o.out) == "obj")
        paths.push_back(MaterialLibraryPath(o.out));
    return paths;
}

// `hrbench scenes`: every family with its parameters, then every oracle and every
// form-factor estimate.
void ListScenes() {
    for (const Family &f : Families()) {
        std::cout << f.name << ": [" << f.dimension << "D] " << f.help << "\n";
        for (const ParamSpec &p : f.params) {
            std::string def = !p.defaultFrom.empty()       ? p.defaultFrom
                              : std::isnan(p.defaultValue) ? "none"
                                                           : FormatDouble(p.defaultValue);
            std::printf("  %-8s default %-8s %-28s %s\n", p.name.c_str(), def.c_str(),
                        DescribeRange(p).c_str(), p.help.c_str());
        }
    }
    std::cout << "\noracles (--oracle):\n";
    for (const OracleInfo &info : OracleInfos())
        std::printf("  %-9s %s\n", info.name, info.doc);
    std::cout
        << "\nform-factor estimates (--ff-estimate; F(i<-j), 2D | 3D; docs/conventions.md):\n";
    for (const FfEstimateInfo &info : FfEstimates())
        std::printf("  %-15s %s | %s%s\n", info.name, info.formula2d, info.formula3d,
                    info.estimate == kDefaultFfEstimate ? "  (default)" : "");
}

// `hrbench solve`'s output: the JSON object or the table, and the CSV of the leaves if asked.
int PrintSolve(const Scene &scene, const Options &o, const SolveResult &result) {
    if (!o.out.empty()) {
        std::ostringstream csv;
        WriteSolveCsv(result, scene.Dimension(), csv);
        WriteOutputFile(o.out, "solve file", csv.str());
    }
    nlohmann::json record = SolveToJson(scene, o.refine, o.solve, result);
    if (o.json)
        std::cout << record.dump() << "\n";
    else
        PrintSolveTable(record, std::cout);
    return kExitOk;
}

// `hrbench check-links`: the summary on success; a violation is a LinkViolation.
int CheckLinksCommand(const Scene &scene, const Options &o) {
    std::istringstream text(ReadRegularFile(o.linksFile, "link dump", o.maxInputBytes));
    LinkDump dump =
        ReadLinkDump(text, o.linksFile, SubdivisionArity(o.refine.subdivision), scene.NumPatches());
    CheckLinksOptions extra{o.linkConventions, o.oracleGiven, o.ffEstimateGiven,
                            o.linkAll ? &std::cout : nullptr};
    try {
        LinkCheck check = CheckLinks(scene, o.refine, dump, extra);
        if (o.json)
            std::cout << LinkCheckJson(dump, nullptr, &check) << "\n";
        else
            PrintLinkCheck(check, dump, o.refine, std::cout);
    } catch (const LinkViolation &v) {
        // The summary on stdout when asked; the first violation, one line, on stderr.
        if (v.summary && o.json)
            std::cout << LinkCheckJson(dump, v.summary.get(), v.check.get()) << "\n";
        else if (v.summary && o.linkSummary)
            PrintLinkSummary(*v.summary, std::cout);
        throw;
    }
    return kExitOk;
}

// `hrbench save`: the scene as JSON (standard output, or a file), or as OBJ with its MTL
// library where the file ends in .obj (docs/scene-format.md).
int SaveCommand(const Scene &scene, const std::string &out) {
    std::string ext = ExtensionOf(out);
    if (ext == "off")
        throw InputError("save writes .json or .obj files, not OFF (it holds no emission)");
    if (ext != "obj") {
        if (out.empty())
            std::cout << SceneToJson(scene);
        else
            SaveScene(scene, out);
        return kExitOk;
    }
    if (scene.Dimension() != 3)
        throw InputError("save --out " + out +
                         ": an OBJ file holds 3D faces, and this scene is "
                         "2D (segments); write it as .json");
    SaveMesh(scene, out);
    return kExitOk;
}

// `hrbench run --sweep`: one record per value, in the order given.
int PrintSweep(const Scene &scene, const Options &o) {
    std::vector<RunRecord> records = CountSweep(scene, o.refine, *o.sweep);
    for (size_t k = 0; k < records.size(); ++k) {
        nlohmann::json record = RunToJson(scene, o.refine, records[k]);
        if (o.json)
            std::cout << record.dump() << "\n";
        else
            PrintRunTable(record, std::cout << (k ? "\n" : ""));
    }
    return kExitOk;
}

int Main(int argc, char **argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    for (const std::string &a : args) {
        if (a == "--help" || a == "-h" || a == "help") {
            std::cout << Usage();
            return kExitOk;
        }
        if (a == "--version") {
            std::cout << "hrbench " << EngineVersion() << "\n";
            return kExitOk;
        }
    }
    Options o = ParseCommandLine(args);
    if (o.command == "scenes") {
        ListScenes();
        return kExitOk;
    }
    if (o.command == "capabilities") {
        std::cout << Capabilities().dump(2) << "\n";
        return kExitOk;
    }
    // An output that is also an input is refused before anything is read or written.
    for (const auto &[input, flag] :
         {std::pair{o.mesh, "--mesh"}, {o.sceneFile, "--scene-file"}, {o.linksFile, "--links"}})
        for (const std::string &output : OutputPaths(o))
            RefuseOutputOverInput(output, "--out", input, flag);
    Scene scene = SceneOf(o);
    for (const std::string &warning : scene.warnings)
        std::cerr << "hrbench: warning: " << warning << std::endl;
    if (o.command == "solve" && !o.visibility)
        o.refine.visibility = DefaultSolveVisibility(scene);
    if (o.command == "save")
        return SaveCommand(scene, o.out);
    // Refining: a warning when the scene's size and --min-area disagree by orders of
    // magnitude, and a progress line on a terminal (not with --json, which is for programs),
    // stopped before anything else is printed.
    RefineProgress progress;
    std::optional<ProgressDisplay> display;
    if (o.command == "run" || o.command == "links" || o.command == "solve") {
        // --sweep min_area: the values at either end, the only ones that can draw a
        // warning the others do not.
        std::set<std::string> warnings = {MinAreaWarning(scene, o.refine)};
        if (o.sweep && o.sweep->param == "min_area") {
            const std::vector<double> &values = o.sweep->values;
            auto [low, high] = std::minmax_element(values.begin(), values.end());
            for (double m : {*low, *high}) {
                RefineOptions one = o.refine;
                one.minArea = m;
                warnings.insert(MinAreaWarning(scene, one));
            }
        }
        for (const std::string &warning : warnings)
            if (!warning.empty())
                std::cerr << "hrbench: warning: " << warning << std::endl;
        if (std::string hint = FacingAwayHint(scene); !hint.empty())
            std::cerr << "hrbench: hint: " << hint << std::endl;
        // Estimate the run before it starts, and refuse one beyond its memory or
        // --max-links (exit code 3); a sweep by its dearest value.
        RefineOptions dearest = o.refine;
        if (o.sweep) {
            double least = *std::min_element(o.sweep->values.begin(), o.sweep->values.end());
            (o.sweep->param == "eps" ? dearest.eps : dearest.minArea) = least;
        }
        CheckEstimate(EstimateRun(scene, dearest, o.command, o.method, o.maxLinks), dearest,
                      o.method, o.maxLinks);
        if (!o.json && !o.sweep && isatty(fileno(stderr))) {
            o.refine.progress = &progress;
            display.emplace(progress, stderr);
        }
    }
    if (o.command == "links") {
        AnyRefinement refinement = Refine(scene, o.refine);
        display.reset();
        OutputFile out(o.out, "links file");
        if (o.linksFormat == "probe")
            WriteLinkDump(refinement, out.Stream());
        else
            WriteLinksCsv(refinement, out.Stream());
        out.Commit();
        return kExitOk;
    }
    if (o.command == "check-links")
        return CheckLinksCommand(scene, o);
    if (o.command == "dump-paths") {
        std::istringstream in(ReadRegularFile(o.linksFile, "link dump", o.maxInputBytes));
        std::ostringstream out;
        ConvertDumpPaths(scene, o.refine.subdivision, o.tolerance.value_or(kDefaultPathTolerance),
                         in, o.linksFile, out);
        WriteOutputFile(o.out, "link dump", out.str());
        return kExitOk;
    }
    if (o.command == "solve") {
        SolveResult result = Solve(scene, o.refine, o.solve);
        display.reset();
        if (!result.energyWarning.empty())
            std::cerr << "hrbench: warning: " << result.energyWarning << std::endl;
        return PrintSolve(scene, o, result);
    }
    if (o.sweep)
        return PrintSweep(scene, o);
    nlohmann::json record;
    if (o.linkFormFactors) {
        // Enumerate as Count does, keeping the links to measure their form factors.
        AnyRefinement refinement = Refine(scene, o.refine);
        LinkFormFactors formFactors = MeasureLinkFormFactors(refinement, o.refine);
        record =
            RunToJson(scene, o.refine, std::visit([](auto &r) { return r.record; }, refinement));
        AddLinkFormFactors(formFactors, record);
    } else {
        record = RunToJson(scene, o.refine, Count(scene, o.refine, o.method));
    }
    display.reset();
    if (o.json)
        std::cout << record.dump() << "\n";
    else
        PrintRunTable(record, std::cout);
    return kExitOk;
}

// The advice of the out-of-memory line: --count-only only where it would help, a `run`
// that stores its links. Allocates nothing: memory has just run out.
const char *OutOfMemoryAdvice(int argc, char **argv) {
    bool storing = argc > 1 && std::strcmp(argv[1], "run") == 0 &&
                   std::none_of(argv + 2, argv + argc,
                                [](const char *a) { return std::strcmp(a, "--count-only") == 0; });
    return storing ? "use --count-only or a larger eps" : "use a larger eps";
}

// Runs a command and checks that everything it printed reached standard output.
int MainChecked(int argc, char **argv) {
    int code = Main(argc, argv);
    CheckOutput(std::cout, "standard output");
    return code;
}

}  // namespace
}  // namespace hrbench

int main(int argc, char **argv) {
    // A closed pipe is then a failed write, reported like any other, not a signal.
    std::signal(SIGPIPE, SIG_IGN);
    try {
        return hrbench::MainChecked(argc, argv);
    } catch (const hrbench::Error &e) {
        std::cerr << "hrbench: error: " << e.what() << "\n";
        return e.ExitCode();
    } catch (const std::bad_alloc &) {
        std::cerr << "hrbench: error: out of memory; " << hrbench::OutOfMemoryAdvice(argc, argv)
                  << "\n";
        return hrbench::kExitLimit;
    } catch (const std::exception &e) {
        std::cerr << "hrbench: internal error: " << e.what() << "\n";
        return hrbench::kExitInternal;
    }
}
