// Fuzzes the OBJ reader and its material libraries (mesh_io.h): ParseMesh on
// arbitrary text, with every `mtllib` reading one fixed MTL file, so that `usemtl` and
// the materials are exercised; a mesh that parses is validated and, when small, refined
// (fuzz_common.h).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_common.h"

namespace {

// Materials the OBJ inputs (fuzz/corpus/obj, fuzz/obj.dict) can select with `usemtl`.
const char *const kMaterialLibrary = "# fixed material library of the OBJ harness\n"
                                     "newmtl white\n"
                                     "Kd 0.75 0.75 0.75\n"
                                     "newmtl light\n"
                                     "Kd 0.78 0.78 0.78\n"
                                     "Ke 17 12 4\n"
                                     "newmtl red\n"
                                     "Ka 0 0 0\n"
                                     "Kd 0.63 0.065 0.05\n"
                                     "newmtl bright\n"
                                     "Kd 1.5 2 3\n";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    std::string text(reinterpret_cast<const char *>(data), size);
    hrbench_fuzz::Guarded([&] {
        hrbench::Scene scene =
            hrbench::ParseMesh(text, hrbench::MeshFormat::Obj, "fuzz",
                               [](const std::string &) { return std::string(kMaterialLibrary); });
        hrbench_fuzz::CheckScene(scene, hrbench_fuzz::Hash(data, size));
    });
    return 0;
}
