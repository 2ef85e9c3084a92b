// The ways to count a refinement, as `run --method` names them: enumeration (Refine) or
// the exact alternative for parallel plates, from translation invariance.
#pragma once

#include <string>
#include <vector>

#include "hrbench/record.h"
#include "hrbench/refine_options.h"
#include "hrbench/scene.h"

namespace hrbench {

// A way to count a refinement, as `--method` names it.
struct MethodInfo {
    const char *name;                                          // "enumerate" or "translation"
    const char *doc;                                           // one line
    RunRecord (*count)(const Scene &, const RefineOptions &);  // counts a scene this way
};

// Every counting method, the default first.
const std::vector<MethodInfo> &Methods();

// The run record of _scene_ by the method the caller names: "enumerate" (Refine) or
// "translation" (CountByTranslation). Throws InputError for an unknown method.
RunRecord Count(const Scene &scene, const RefineOptions &options, const std::string &method);

}  // namespace hrbench
