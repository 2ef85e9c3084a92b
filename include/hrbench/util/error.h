// Errors that end a run with a documented exit code instead of a crash.
#pragma once

#include <stdexcept>
#include <string>

namespace hrbench {

// Process exit codes shared by every command.
enum ExitCode : int {
    kExitOk = 0,
    kExitInternal = 1,   // a bug: should never happen
    kExitInput = 2,      // usage error or invalid input (scene, parameter, file)
    kExitLimit = 3,      // refinement reached a safety or memory limit
    kExitViolation = 4,  // check-links: the link dump breaks a rule
};

// Base of every error the library reports to a user; carries its exit code.
class Error : public std::runtime_error {
  public:
    Error(const std::string &message, int exitCode)
        : std::runtime_error(message), exitCode_(exitCode) {}
    int ExitCode() const { return exitCode_; }

  private:
    int exitCode_;
};

// Bad command line, parameter, scene or file: exit code 2.
class InputError : public Error {
  public:
    explicit InputError(const std::string &message) : Error(message, kExitInput) {}
};

// Refinement hit the depth safety cap or the memory budget: exit code 3.
class LimitError : public Error {
  public:
    explicit LimitError(const std::string &message) : Error(message, kExitLimit) {}
};

}  // namespace hrbench
