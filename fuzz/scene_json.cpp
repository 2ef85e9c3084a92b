// Fuzzes the scene JSON reader (docs/scene-format.md): SceneFromJson on arbitrary text;
// a scene that parses is validated and, when small, refined (fuzz_common.h).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    std::string text(reinterpret_cast<const char *>(data), size);
    hrbench_fuzz::Guarded([&] {
        hrbench::Scene scene = hrbench::SceneFromJson(text, "fuzz");
        hrbench_fuzz::CheckScene(scene, hrbench_fuzz::Hash(data, size));
    });
    return 0;
}
