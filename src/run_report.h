// How a run is presented: the JSON record, the human table, the links CSV.
#pragma once

#include <ostream>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "refine.h"

namespace hrbench {

constexpr int kRunSchemaVersion = 1;

// The JSON record of one run: context, scene, parameters, options, every counter
// as a top-level key (DESIGN section 2 names) and `seconds`.
nlohmann::json RunToJson(const Scene &scene, const RefineOptions &options,
                         const Refinement &refinement);

// Prints the same record as an aligned two-column table.
void PrintRunTable(const nlohmann::json &record, std::ostream &out);

// Writes every stored link as a CSV row: roots, element ids, their intervals in
// arc length along their roots, and depths; in 3D, areas and centroids instead of
// intervals.
void WriteLinksCsv(const Refinement &refinement, std::ostream &out);

// Version of the engine; results of different versions are never mixed.
std::string EngineVersion();

}  // namespace hrbench
