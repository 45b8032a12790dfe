// libFuzzer target: ink::readPngFromMemory, the PNG reader of `compare` (stb_image behind a header check).
// See docs/robustness.md. ink::Error is the reader's answer to bad input; anything else (another exception,
// a crash, a sanitizer report, a hang, an allocation past the pixel limit, a message that is not one
// printable line) is a finding.
#include "base/common.h"
#include "base/image.h"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

[[noreturn]] void broken(const char* what) {
    std::fprintf(stderr, "fuzz: the PNG reader broke its promise: %s\n", what);
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string bytes(reinterpret_cast<const char*>(data), size);
    ink::RgbaImage image;
    try {
        image = ink::readPngFromMemory(bytes, "fuzz.png");
    } catch (const ink::Error& e) {
        std::string message = e.what();
        if (message.empty()) broken("an empty error message");
        for (unsigned char c : message)
            if (c < 0x20 || c >= 0x7f) broken("an error message with a byte outside printable ASCII");
        return 0;
    }
    if (image.width < 1 || image.height < 1 || image.width > ink::kMaxImageSide || image.height > ink::kMaxImageSide ||
        uint64_t(image.width) * image.height > ink::kMaxImagePixels)
        broken("an image outside the limits");
    if (image.pixels.size() != size_t(image.width) * image.height * 4) broken("pixels do not match the size");
    return 0;
}
