// Shared basics: the user-facing error type, notes and progress.
#pragma once

#include "inkwell/error.h"
#include "inkwell/files.h"

#include <chrono>
#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace ink {

// The public error type (include/inkwell/error.h): one line that says what is wrong and, where possible,
// how to fix it; apps print it and exit non-zero.
using Error = inkwell::Error;

// The text of messages and capped reads (include/inkwell/files.h).
using inkwell::escapeText;
using inkwell::quoted;
using inkwell::readFileCapped;

// Where the library's notes and progress go (include/inkwell/error.h): the library prints nothing itself. An
// application installs a reporter for a stretch of work on its thread (ScopedReporter); without one, notes and
// progress are dropped.
using Reporter = inkwell::Reporter;

// Installs `reporter` for this thread until the guard goes (guards nest; the previous one comes back).
class ScopedReporter {
public:
    explicit ScopedReporter(const Reporter& reporter);
    ~ScopedReporter();
    ScopedReporter(const ScopedReporter&) = delete;
    ScopedReporter& operator=(const ScopedReporter&) = delete;

private:
    const Reporter* previous_;
};

// To the installed reporter, if any.
void note(const std::string& line);

// Progress of one piece of long work, reported to the installed reporter when a step changes the percentage;
// done when destroyed.
struct Progress {
    Progress(const char* what, size_t total);
    ~Progress();
    void update(size_t done);
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

private:
    const char* what_;
    size_t total_;
    int lastPercent_ = -1;
};

// Wall-clock seconds since t.
inline double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Wall-clock milliseconds since it was made or last asked.
struct Stopwatch {
    std::chrono::steady_clock::time_point mark = std::chrono::steady_clock::now();
    double lap() {
        const auto now = std::chrono::steady_clock::now();
        const double ms = std::chrono::duration<double, std::milli>(now - mark).count();
        mark = now;
        return ms;
    }
};

// Wall-clock milliseconds of the named steps of a long piece of work, in the order they first ran (a step run
// again, as the fit's rounds do, adds up): `lap(name)` charges the time since the last lap to `name`.
struct PhaseTimes {
    std::vector<std::pair<const char*, double>> ms;
    Stopwatch clock;

    void lap(const char* name) { add(name, clock.lap()); }
    // Adds to `name` without a lap: a step that ran beside the others, on a thread of its own.
    void add(const char* name, double elapsedMs) {
        for (auto& [step, total] : ms)
            if (std::string_view(step) == name) {
                total += elapsedMs;
                return;
            }
        ms.emplace_back(name, elapsedMs);
    }
};

}  // namespace ink
