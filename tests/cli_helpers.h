// Running the hrbench command from tests: its streams, exit code and scratch files.
#pragma once

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace hrbench_test {

struct CliResult {
    int exitCode;
    std::string out, err;
};

// A scratch file in a folder of this test process, so that runs never collide.
inline std::string Scratch(const std::string &name) {
    static const std::filesystem::path dir = [] {
        auto d = std::filesystem::temp_directory_path() /
                 ("hrbench_cli_test_" + std::to_string(getpid()));
        std::filesystem::create_directories(d);
        return d;
    }();
    return (dir / name).string();
}

inline std::string ReadFile(const std::string &path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

// Runs a shell command and captures both streams and the exit code.
inline CliResult Run(const std::string &command) {
    std::string errPath = Scratch("stderr.txt");
    FILE *pipe = popen((command + " 2>" + errPath).c_str(), "r");
    REQUIRE(pipe);
    std::string out;
    char buffer[4096];
    while (size_t n = fread(buffer, 1, sizeof buffer, pipe))
        out.append(buffer, n);
    int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out, ReadFile(errPath)};
}

// The standard output of a shell command that must succeed (an example kernel, say).
inline std::string RunOk(const std::string &command) {
    CliResult r = Run(command);
    INFO(command << ": " << r.err);
    REQUIRE(r.exitCode == 0);
    return r.out;
}

// Runs `hrbench ARGS` through the shell, after the shell commands _before_ (a ulimit, say),
// and captures both streams and the exit code.
inline CliResult Cli(const std::string &args, const std::string &before = "") {
    return Run(before + std::string(HRBENCH_CLI) + " " + args);
}

// An error is exactly one line on stderr and the given exit code.
inline void CheckError(const std::string &args, int exitCode, const std::string &fragment) {
    INFO("hrbench " << args);
    CliResult r = Cli(args);
    CHECK(r.exitCode == exitCode);
    CHECK(r.out.empty());
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_THAT(r.err, Catch::Contains(fragment));
}

}  // namespace hrbench_test
