// The `--method` table: enumeration, or the translation method where it applies.
#include "hrbench/count.h"

#include <utility>
#include <variant>

#include "count/translation_count.h"
#include "hrbench/refine.h"
#include "util/named.h"

namespace hrbench {

const std::vector<MethodInfo> &Methods() {
    static const std::vector<MethodInfo> methods = {
        {"enumerate", "run ProjectKernel pair by pair (any scene, oracle and option)",
         [](const Scene &scene, const RefineOptions &options) {
             return std::visit([](auto &&r) { return std::move(r.record); },
                               Refine(scene, options));
         }},
        {"translation",
         "exact counts of `parallel` with l2 = l and `parallel3d` with ox = oy = 0, garmann, "
         "--count-only, no recursion limit, from translation invariance (any number of links "
         "in milliseconds)",
         [](const Scene &scene, const RefineOptions &options) {
             return CountByTranslation(scene, options).record;
         }},
    };
    return methods;
}

RunRecord Count(const Scene &scene, const RefineOptions &options, const std::string &method) {
    return FindNamed(Methods(), method, "method").count(scene, options);
}

}  // namespace hrbench
