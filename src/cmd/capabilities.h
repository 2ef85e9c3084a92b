// `hrbench capabilities --json`: what this engine offers, read from the tables that
// drive it (families, oracle registry, methods, options, counters).
#pragma once

#include <nlohmann/json_fwd.hpp>

namespace hrbench {

// Schema version of the capabilities document.
constexpr int kCapabilitiesSchemaVersion = 1;

nlohmann::json Capabilities();

}  // namespace hrbench
