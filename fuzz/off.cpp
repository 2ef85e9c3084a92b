// Fuzzes the OFF reader (mesh_io.h): ParseMesh on arbitrary text; a mesh that parses
// is validated and, when small, refined (fuzz_common.h).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    std::string text(reinterpret_cast<const char *>(data), size);
    hrbench_fuzz::Guarded([&] {
        // OFF has no material libraries: an empty reader.
        hrbench::Scene scene = hrbench::ParseMesh(text, hrbench::MeshFormat::Off, "fuzz", {});
        hrbench_fuzz::CheckScene(scene, hrbench_fuzz::Hash(data, size));
    });
    return 0;
}
