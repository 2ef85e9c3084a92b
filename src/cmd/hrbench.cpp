// hrbench: refine a scene with ProjectKernel and report exact counters.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "generators.h"
#include "hrbench.h"
#include "translation_count.h"

namespace hrbench {
namespace {

const char *kUsage = R"(usage: hrbench <command> [arguments]

Commands:
  run SCENE [key=value ...] --eps E [options]     refine a scene, print its counters
  run --scene-file F.json --eps E [options]       refine a saved scene
  run --mesh F.obj --eps E [options]              refine a mesh (OFF or OBJ, 3D)
  links SCENE [key=value ...] --eps E --out F.csv write every link (store mode)
  save SCENE [key=value ...] --out F.json         write a scene file
  scenes                                          list scene families and parameters

Options of run and links:
  --eps E            oracle threshold, a finite number > 0 (required)
  --oracle NAME      garmann (default): max(A_i,A_j)/r <= eps (3D: /r^2)
                     hanrahan: form-factor estimates F(i<-j), F(j<-i) <= eps
  --min-area A       link a pair whose preferred element is smaller than A (length in
                     2D, area in 3D; forced link)
  --max-depth D      link a pair whose preferred element has depth D (0..48; forced link)
  --count-only       count links without storing them (run only; default: store)
  --method M         enumerate (default): run ProjectKernel pair by pair
                     translation: exact counts of `parallel` with l2 = l, garmann,
                     --count-only, no recursion limit, from translation invariance
                     (run only; any number of links in milliseconds)
  --threads N        worker threads (default 1); counts and ids never depend on N
  --max-memory MIB   memory budget for elements and links in MiB (default: 90% of free)
  --json             print one JSON object instead of a table (run only)
  --scene-file F     load the scene from a JSON scene file instead of a family
  --mesh F           load a 3D scene from an OFF or OBJ file (triangles, planar
                     convex quads; default reflectance 0.5, emission 0)
  --subdivision S    3D: binary (default, two halves across the longer edges) or
                     quadtree (four children)
  --visibility V     none (default): ignore occlusion, as the papers do;
                     fraction: accept when the oracle's error times the visible
                     fraction is within eps; refine: split partially visible pairs
                     down to the recursion limit (needs --min-area or --max-depth)
  --rays-per-side K  visibility samples per element side, 1..16 (default 3): K x K
                     rays per pair in 2D, K^2 x K^2 in 3D
  --out F            output file (links: CSV; save: JSON, default standard output)

General:
  --help             print this text
  --version          print the engine version

Exit codes: 0 success, 2 usage or input error, 3 a refinement limit was reached
(safety depth or memory budget), 1 internal error.
Example: hrbench run parallel l=64 d=1 --eps 0.25 --json
)";

// Everything the command line can say, parsed once.
struct Options {
    std::string command;
    std::string scene;
    std::vector<std::string> params;
    std::string sceneFile;
    std::string mesh;
    std::string out;
    std::optional<double> eps;
    RefineOptions refine;
    bool json = false;
    bool countOnly = false;
    std::string method = "enumerate";
};

Options ParseCommandLine(int argc, char **argv) {
    Options o;
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.empty())
        throw InputError("no command given; see hrbench --help");
    o.command = args[0];
    for (size_t k = 1; k < args.size(); ++k) {
        const std::string &a = args[k];
        auto value = [&](const std::string &flag) -> std::string {
            if (k + 1 >= args.size())
                throw InputError(flag + " needs a value");
            return args[++k];
        };
        if (a == "--eps")
            o.eps = ParseDouble(value(a), "--eps");
        else if (a == "--oracle")
            o.refine.oracle = ParseOracle(value(a));
        else if (a == "--min-area")
            o.refine.minArea = ParseDouble(value(a), "--min-area");
        else if (a == "--max-depth")
            o.refine.maxDepth = int(std::min<int64_t>(ParseInt(value(a), "--max-depth"), 1 << 20));
        else if (a == "--max-memory")
            o.refine.memoryBudget = size_t(ParseInt(value(a), "--max-memory")) << 20;
        else if (a == "--threads")
            o.refine.threads = int(std::min<int64_t>(ParseInt(value(a), "--threads"), 1 << 20));
        else if (a == "--count-only")
            o.countOnly = true;
        else if (a == "--method")
            o.method = value(a);
        else if (a == "--json")
            o.json = true;
        else if (a == "--scene-file")
            o.sceneFile = value(a);
        else if (a == "--mesh")
            o.mesh = value(a);
        else if (a == "--subdivision")
            o.refine.subdivision = ParseSubdivision(value(a));
        else if (a == "--visibility")
            o.refine.visibility = ParseVisibility(value(a));
        else if (a == "--rays-per-side")
            o.refine.raysPerSide =
                int(std::min<int64_t>(ParseInt(value(a), "--rays-per-side"), 1 << 20));
        else if (a == "--out")
            o.out = value(a);
        else if (a.rfind("--", 0) == 0)
            throw InputError("unknown option '" + a + "'; see hrbench --help");
        else if (IsParamWord(a))
            o.params.push_back(a);
        else if (o.scene.empty())
            o.scene = a;
        else
            throw InputError("unexpected argument '" + a + "'; see hrbench --help");
    }

    // Reject combinations that make no sense, naming the flags.
    bool refines = o.command == "run" || o.command == "links";
    if (refines || o.command == "save") {
        int sources = !o.scene.empty() + !o.sceneFile.empty() + !o.mesh.empty();
        if (sources != 1)
            throw InputError(o.command + " needs either a SCENE family, --scene-file or --mesh");
        if (o.scene.empty() && !o.params.empty())
            throw InputError("key=value parameters apply to a family, not to --scene-file or --mesh");
    }
    if (refines && !o.eps)
        throw InputError(o.command + " needs --eps");
    if (o.command == "links" && o.out.empty())
        throw InputError("links needs --out F.csv");
    if (o.command == "links" && o.countOnly)
        throw InputError("links stores links; --count-only does not apply");
    if (o.method != "enumerate" && o.method != "translation")
        throw InputError("--method must be enumerate or translation, not '" + o.method + "'");
    if (o.method != "enumerate" && o.command != "run")
        throw InputError("--method applies to run only");
    if (o.command != "run" && o.json)
        throw InputError("--json applies to run only");
    o.refine.eps = o.eps.value_or(0);
    o.refine.storeLinks = o.command == "links" || !o.countOnly;
    return o;
}

Scene SceneOf(const Options &o) {
    if (!o.mesh.empty())
        return LoadMesh(o.mesh);
    return o.sceneFile.empty() ? MakeScene(o.scene, ParseParams(o.params)) : LoadScene(o.sceneFile);
}

void ListScenes() {
    for (const Family &f : Families()) {
        std::cout << f.name << ": [" << f.dimension << "D] " << f.help << "\n";
        for (const ParamSpec &p : f.params) {
            std::string def = p.defaultFrom.empty() ? FormatDouble(p.defaultValue) : p.defaultFrom;
            std::printf("  %-8s default %-8s %-28s %s\n", p.name.c_str(), def.c_str(),
                        DescribeRange(p).c_str(), p.help.c_str());
        }
    }
}

int Main(int argc, char **argv) {
    for (int k = 1; k < argc; ++k) {
        std::string a = argv[k];
        if (a == "--help" || a == "-h" || a == "help") {
            std::cout << kUsage;
            return kExitOk;
        }
        if (a == "--version") {
            std::cout << "hrbench " << EngineVersion() << "\n";
            return kExitOk;
        }
    }
    Options o = ParseCommandLine(argc, argv);
    if (o.command == "scenes") {
        ListScenes();
        return kExitOk;
    }
    if (o.command == "save") {
        Scene scene = SceneOf(o);
        if (o.out.empty())
            std::cout << SceneToJson(scene);
        else
            SaveScene(scene, o.out);
        return kExitOk;
    }
    if (o.command != "run" && o.command != "links")
        throw InputError("unknown command '" + o.command + "'; see hrbench --help");

    Scene scene = SceneOf(o);
    Refinement refinement = o.method == "translation"
                                ? AsRefinement(CountByTranslation(scene, o.refine), scene)
                                : Refine(scene, o.refine);
    if (o.command == "links") {
        std::ofstream out(o.out, std::ios::binary);
        WriteLinksCsv(refinement, out);
        if (!out.flush())
            throw InputError("cannot write links file '" + o.out + "'");
        return kExitOk;
    }
    nlohmann::json record = RunToJson(scene, o.refine, refinement);
    if (!o.sceneFile.empty())
        record["scene_file"] = o.sceneFile;
    if (!o.mesh.empty())
        record["mesh_file"] = o.mesh;
    record["method"] = o.method;
    if (o.json)
        std::cout << record.dump() << "\n";
    else
        PrintRunTable(record, std::cout);
    return kExitOk;
}

}  // namespace
}  // namespace hrbench

int main(int argc, char **argv) {
    try {
        return hrbench::Main(argc, argv);
    } catch (const hrbench::Error &e) {
        std::cerr << "hrbench: error: " << e.what() << "\n";
        return e.ExitCode();
    } catch (const std::bad_alloc &) {
        std::cerr << "hrbench: error: out of memory; use --count-only or a larger eps\n";
        return hrbench::kExitLimit;
    } catch (const std::exception &e) {
        std::cerr << "hrbench: internal error: " << e.what() << "\n";
        return hrbench::kExitInternal;
    }
}
