// libFuzzer target: ink::parseHrbf, the .hrbf model reader (text versions 1 and 2, binary version 3). See
// docs/robustness.md. ink::Error is the reader's answer to bad input; anything else (another exception, a crash, a
// sanitizer report, a hang, a huge allocation, a model that breaks what the reader promises) is a finding.
#include "base/common.h"
#include "io/hrbf_io.h"
#include "surface/model.h"
#include "surface/surface.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

[[noreturn]] void broken(const char* what) {
    std::fprintf(stderr, "fuzz: a parse succeeded but broke its promise: %s\n", what);
    std::abort();
}

// One parse and the promises of what it returns.
void check(const std::string& bytes) {
    ink::Surface m;
    try {
        m = ink::parseHrbf(bytes, "fuzz.hrbf");
    } catch (const ink::Error& e) {
        std::string message = e.what();
        if (message.empty() || message.find('\n') != std::string::npos) broken("an error message is not one line");
        return;
    }
    const size_t n = m.size();
    if (n < 2) broken("fewer than 2 points");
    if (m.normals.size() != n) broken("arrays differ in size");
    if (!(m.frame.scale > 0) || !std::isfinite(m.frame.scale) || !m.frame.center.allFinite())
        broken("the frame is not finite with a positive scale");
    for (size_t j = 0; j < n; ++j) {
        if (!m.centers[j].allFinite()) broken("a point is not finite");
        if (!m.normals[j].allFinite() || m.normals[j].squaredNorm() == 0) broken("a normal is zero or not finite");
    }
    if (m.method == ink::FitMethod::Global) {
        const ink::Hrbf& h = m.global;
        if (h.size() != n || h.size() > ink::kMaxControlPoints) broken("centre count outside 2..kMaxControlPoints");
        if (h.alpha.size() != n || h.beta.size() != n) broken("arrays differ in size");
        if (!h.a.allFinite() || !std::isfinite(h.b)) broken("the linear term is not finite");
        for (size_t j = 0; j < n; ++j)
            if (!h.beta[j].allFinite() || !std::isfinite(h.alpha[j])) broken("a coefficient is not finite");
    } else {
        size_t nodes = 0;
        for (const ink::PuPatch& p : m.pu.patches) {
            if (!(p.radius > 0) || !p.center.allFinite()) broken("a patch is not finite with a positive radius");
            if (p.first != nodes) broken("patches do not tile the nodes");
            nodes += p.count;
        }
        if (nodes != m.pu.nodes.size()) broken("the patches do not hold the nodes");
        for (const ink::PuNode& node : m.pu.nodes)
            if (!node.p.allFinite() || !std::isfinite(node.alpha) || !node.beta.allFinite())
                broken("a node is not finite");
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string bytes(reinterpret_cast<const char*>(data), size);
    check(bytes);
    // A binary (version 3) input again with its checksum made right, so that mutations reach the checks behind it
    // (a hostile file can carry a valid checksum).
    if (bytes.size() >= ink::kHrbf3ChecksumOffset + 4 && bytes.compare(0, 8, ink::kHrbf3Magic) == 0) {
        std::memset(bytes.data() + ink::kHrbf3ChecksumOffset, 0, 4);
        const uint32_t crc = ink::crc32c(bytes);
        std::memcpy(bytes.data() + ink::kHrbf3ChecksumOffset, &crc, 4);
        check(bytes);
    }
    return 0;
}
