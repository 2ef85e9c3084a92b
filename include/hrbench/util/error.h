// Errors that end a run with a documented exit code instead of a crash.
#pragma once

#include <algorithm>
#include <cstdio>
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

// _message_ as one line of a sane length, whatever input it quotes: a control byte (a
// NUL, a line break) written as \xNN, and a word longer than 200 bytes (a hostile token
// of a file) shown as its first 60 bytes, "..." and its length.
inline std::string OneLineMessage(const std::string &message) {
    constexpr size_t kLongWord = 200, kShownBytes = 60;
    std::string line;
    for (size_t start = 0;; ++start) {
        size_t end = std::min(message.find(' ', start), message.size());
        size_t size = end - start, shown = size > kLongWord ? kShownBytes : size;
        for (size_t k = start; k < start + shown; ++k) {
            unsigned char c = message[k];
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", unsigned(c));
            line += c < 0x20 || c == 0x7f ? std::string(hex) : std::string(1, char(c));
        }
        if (shown < size)
            line += "... (" + std::to_string(size) + " bytes)";
        if (end == message.size())
            return line;
        line += ' ';
        start = end;
    }
}

// Base of every error the library reports to a user; carries its exit code. Its message
// is one line (OneLineMessage), so that what() is never cut short by a NUL byte.
class Error : public std::runtime_error {
  public:
    Error(const std::string &message, int exitCode)
        : std::runtime_error(OneLineMessage(message)), exitCode_(exitCode) {}
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
