#include "util/args.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "hrbench/util/error.h"

namespace hrbench {

double ParseDouble(const std::string &text, const std::string &what) {
    if (text.empty())
        throw InputError(what + ": expected a number, got an empty string");
    errno = 0;
    char *end = nullptr;
    double value = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size())
        throw InputError(what + ": '" + text + "' is not a number");
    // Decimal notation only: strtod would also take leading spaces and hexadecimal.
    bool decimal = text.find_first_not_of("0123456789+-.eE") == std::string::npos;
    if (!decimal && std::isfinite(value))
        throw InputError(what + ": '" + text + "' is not a decimal number");
    if (!std::isfinite(value) && errno != ERANGE)
        throw InputError(what + ": '" + text + "' is not a finite number");
    // strtod reports both ends of the range as ERANGE: overflow returns infinity,
    // underflow a denormal or zero.
    if (errno == ERANGE && std::isinf(value))
        throw InputError(what + ": '" + text + "' overflows double precision (largest 1.8e308)");
    if (errno == ERANGE)
        throw InputError(what + ": '" + text +
                         "' underflows double precision (smallest normal 2.2e-308)");
    return value;
}

int64_t ParseInt(const std::string &text, const std::string &what) {
    double value = ParseDouble(text, what);
    if (value < 0 || value != std::floor(value) || value > 9.0e15)
        throw InputError(what + ": '" + text + "' is not a non-negative integer");
    return static_cast<int64_t>(value);
}

bool IsParamWord(const std::string &word) {
    size_t eq = word.find('=');
    return eq != std::string::npos && eq > 0 && word.rfind("--", 0) != 0;
}

std::map<std::string, double> ParseParams(const std::vector<std::string> &words) {
    std::map<std::string, double> params;
    for (const std::string &word : words) {
        if (!IsParamWord(word))
            throw InputError("expected a parameter key=value, got '" + word + "'");
        size_t eq = word.find('=');
        std::string key = word.substr(0, eq);
        if (params.count(key))
            throw InputError("parameter '" + key + "' is given twice");
        params[key] = ParseDouble(word.substr(eq + 1), "parameter " + key);
    }
    return params;
}

}  // namespace hrbench
