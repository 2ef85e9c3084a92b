// The command line of hrbench: its commands and options, each listed once. Parsing,
// the usage text and `hrbench capabilities` all read these tables.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "count/sweep_count.h"
#include "hrbench/refine_options.h"
#include "hrbench/solve.h"
#include "hrbench/util/input_file.h"
#include "refine/estimate.h"

namespace hrbench {

// Everything the command line can say, parsed once.
struct Options {
    std::string command;
    std::string scene;
    std::vector<std::string> params;  // key=value words
    std::string sceneFile;
    std::string mesh;
    bool triangulate = false;     // --triangulate (mesh only)
    std::optional<double> scale;  // --scale (mesh only)
    std::string out;
    std::string linksFormat = "csv";                    // links --format: csv or probe
    std::string linksFile;                              // check-links, dump-paths --links
    std::optional<double> tolerance;                    // --tolerance as given (solve, dump-paths)
    std::string linkConventions;                        // check-links --conventions
    bool linkSummary = false;                           // check-links --summary
    bool linkAll = false;                               // check-links --all
    bool oracleGiven = false, ffEstimateGiven = false;  // --oracle, --ff-estimate given
    std::optional<double> eps;
    RefineOptions refine;
    // --visibility as given. Without it, refine.visibility is the papers' none, except for
    // solve, whose default depends on the scene (DefaultSolveVisibility).
    std::optional<VisibilityMode> visibility;
    bool json = false;
    bool countOnly = false;
    bool linkFormFactors = false;      // run --link-form-factors: measure the stored links
    std::string method = "enumerate";  // run: how to count (Methods())
    std::optional<SweepValues> sweep;  // run --sweep: one record per value
    SolveOptions solve;
    size_t maxInputBytes = kDefaultMaxInputBytes;  // size limit of a scene or mesh file
    uint64_t maxLinks = kDefaultMaxLinks;          // --max-links: the estimate's link cap
};

struct CommandSpec {
    std::string name;
    std::string synopsis;  // after "hrbench "
    std::string doc;       // one line
};

// An option that another cannot be given with, and why, worded to follow the other's flag:
// "--clusters refines by enumeration, which --sweep does not: drop one of them".
struct OptionExclusion {
    std::string option;  // the excluded option's name: "sweep"
    std::string why;     // "refines by enumeration"
};

struct OptionSpec {
    std::string name;                   // the option's name in claim files: "min_area"
    std::string flag;                   // "--min-area"
    std::string value;                  // metavariable, "" for a switch
    std::vector<std::string> choices;   // the values it accepts, if a closed set
    std::vector<std::string> commands;  // the commands it applies to
    std::string doc;                    // help text; lines after the first are indented
    std::function<void(Options &, const std::string &)> apply;  // stores the value
    // The options it cannot be given with, whatever the values (symmetric: listed on one
    // of the two). ParseCommandLine refuses them and `capabilities` lists them, so that
    // the analysis plans only the runs the engine accepts.
    std::vector<OptionExclusion> excludes = {};
};

const std::vector<CommandSpec> &Commands();
const std::vector<OptionSpec> &OptionTable();

// The text of `hrbench --help`.
std::string Usage();

// Parses the arguments after the program name and rejects combinations that make no
// sense, naming the flags; throws InputError.
Options ParseCommandLine(const std::vector<std::string> &args);

}  // namespace hrbench
