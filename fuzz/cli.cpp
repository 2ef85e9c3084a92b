// Fuzzes the command-line parser of hrbench (src/cmd/options.cpp, compiled into this
// harness): the input is split at NUL bytes and newlines into words, the arguments after
// the program name. What parses has its key=value words and its refinement options
// checked too, as the CLI would before running.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cmd/options.h"
#include "fuzz_common.h"
#include "util/args.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    std::vector<std::string> words(1);
    for (size_t k = 0; k < size; ++k) {
        char c = char(data[k]);
        if (c == '\0' || c == '\n')
            words.emplace_back();
        else
            words.back() += c;
    }
    if (words.back().empty())
        words.pop_back();  // a trailing separator ends the last word
    hrbench_fuzz::Guarded([&] {
        hrbench::Options options = hrbench::ParseCommandLine(words);
        FUZZ_CHECK(!options.command.empty(), "a command line parsed without a command");
        hrbench_fuzz::Guarded([&] { hrbench::ParseParams(options.params); });
        for (int dimension : {2, 3})
            hrbench_fuzz::Guarded([&] { hrbench::ValidateOptions(options.refine, dimension); });
        hrbench_fuzz::Guarded([&] { hrbench::ValidateSolveOptions(options.solve); });
    });
    return 0;
}
