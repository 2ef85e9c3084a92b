// Command-line plumbing: strict number parsing and key=value words.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace hrbench {

// Parses a finite double; throws InputError naming _what_ otherwise.
double ParseDouble(const std::string &text, const std::string &what);

// Parses a non-negative integer that fits in int64; throws InputError otherwise.
int64_t ParseInt(const std::string &text, const std::string &what);

// Parses `key=value` words into a map from key to value; throws InputError on a
// malformed word, a repeated key or a value that is not a finite number.
std::map<std::string, double> ParseParams(const std::vector<std::string> &words);

// True when _word_ has the form key=value (and is not a flag).
bool IsParamWord(const std::string &word);

}  // namespace hrbench
