// What an oracle is: a rule that decides whether one element pair may be linked.
// The concrete oracles live in oracles.h; the kernel is instantiated once per kind.
#pragma once

#include <string>
#include <vector>

namespace hrbench {

// The closed set of oracles (DESIGN section 2).
enum class OracleKind {
    Garmann,   // max(A_i, A_j) / r <= eps
    Hanrahan,  // form-factor estimates F(i<-j) <= eps and F(j<-i) <= eps
};

// Name used on the command line and in JSON ("garmann", "hanrahan").
std::string OracleName(OracleKind kind);

// Parses an oracle name; throws InputError listing the valid names.
OracleKind ParseOracle(const std::string &name);

std::vector<std::string> OracleNames();

}  // namespace hrbench
