// libFuzzer target: ink::parsePoints(bytes, "off", ...). See docs/robustness.md.
#include "fuzz_points.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return fuzz::parsePointsOnce(data, size, "off");
}
