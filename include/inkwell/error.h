// Inkwell's error type and the reporter its long operations talk to. Included by inkwell.h; the engine
// throws and reports through these same types.
#pragma once

#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>

namespace inkwell {

// Everything a user can cause (a bad file, no device, too many points) is thrown as an Error whose message is
// one sentence saying what is wrong and, where it can, how to fix it. Programmer errors and driver failures
// (out of memory, a lost device) are Errors too, naming the Vulkan call.
struct Error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The library prints nothing. Long operations (loading and fitting, refining) take a Reporter and send it
// their notes and progress; an empty one drops them.
struct Reporter {
    // A one-line remark: "merged 3 duplicate points", "--control-points is ignored for a .hrbf model".
    std::function<void(const std::string& line)> note;
    // Long work ("fit", "refine"): `done` of `total` steps, and done == total once more when it ends.
    std::function<void(const char* task, size_t done, size_t total)> progress;
};

}  // namespace inkwell
