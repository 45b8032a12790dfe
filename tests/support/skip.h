// A test that cannot run where it runs (no root, not lavapipe, no shaderFloat64) says so with skipTest and
// returns: it is counted as skipped, never as passed. Run alone (as ctest runs each test case), the test
// program then exits kSkipExitCode, which CTest's SKIP_RETURN_CODE reports as "Not Run (Skipped)"; every run
// ends by listing its skips with their reasons (tests/support/main.cpp).
#pragma once

#include <string>

inline constexpr int kSkipExitCode = 77;

// Records that the current test case skips (the rest of) its checks, and why. Call it, then return.
void skipTest(const std::string& reason);
