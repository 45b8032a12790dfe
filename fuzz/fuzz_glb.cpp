// libFuzzer target: the glTF reader on .glb bytes (ink::io::parseGltf, binary), with external files off so that
// no input can make it read the disk: only the container, its JSON (through tinygltf) and its binary chunk. A
// .glb holds the JSON of a .gltf, so this covers both. See docs/robustness.md.
#include "fuzz_points.h"
#include "io/readers.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return fuzz::parseOnce(data, size,
                           [](const std::string& bytes) { return ink::io::parseGltf(bytes, "fuzz.glb", true, false); });
}
