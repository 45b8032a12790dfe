// libFuzzer target: ink::parseHrbf, the .hrbf model reader. See docs/robustness.md. ink::Error is the
// reader's answer to bad input; anything else (another exception, a crash, a sanitizer report, a hang, a
// huge allocation, a model that breaks what the reader promises) is a finding.
#include "common.h"
#include "hrbf_io.h"
#include "model.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

[[noreturn]] void broken(const char* what) {
    std::fprintf(stderr, "fuzz: a parse succeeded but broke its promise: %s\n", what);
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string bytes(reinterpret_cast<const char*>(data), size);
    ink::Hrbf m;
    try {
        m = ink::parseHrbf(bytes, "fuzz.hrbf");
    } catch (const ink::Error& e) {
        std::string message = e.what();
        if (message.empty() || message.find('\n') != std::string::npos) broken("an error message is not one line");
        return 0;
    }
    const size_t n = m.size();
    if (n < 2 || n > ink::kMaxControlPoints) broken("centre count outside 2..kMaxControlPoints");
    if (m.alpha.size() != n || m.beta.size() != n || m.normals.size() != n) broken("arrays differ in size");
    if (!(m.frame.scale > 0) || !std::isfinite(m.frame.scale) || !m.frame.center.allFinite())
        broken("the frame is not finite with a positive scale");
    if (!m.a.allFinite() || !std::isfinite(m.b)) broken("the linear term is not finite");
    for (size_t j = 0; j < n; ++j) {
        if (!m.centers[j].allFinite() || !m.beta[j].allFinite() || !std::isfinite(m.alpha[j]))
            broken("a coefficient is not finite");
        if (!m.normals[j].allFinite() || m.normals[j].squaredNorm() == 0) broken("a normal is zero or not finite");
    }
    return 0;
}
