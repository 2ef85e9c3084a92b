#include "oracle.h"

#include "util/error.h"

namespace hrbench {

std::string OracleName(OracleKind kind) {
    switch (kind) {
    case OracleKind::Garmann:
        return "garmann";
    case OracleKind::Hanrahan:
        return "hanrahan";
    }
    return "unknown";
}

std::vector<std::string> OracleNames() { return {"garmann", "hanrahan"}; }

OracleKind ParseOracle(const std::string &name) {
    if (name == "garmann")
        return OracleKind::Garmann;
    if (name == "hanrahan")
        return OracleKind::Hanrahan;
    throw InputError("unknown oracle '" + name + "' (choose garmann or hanrahan)");
}

}  // namespace hrbench
