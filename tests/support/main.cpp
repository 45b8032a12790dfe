// The tests' main: doctest's, and the skips (tests/support/skip.h) counted and listed. A run whose every test case
// skipped exits kSkipExitCode (CTest: SKIP_RETURN_CODE), so that a skip is never reported as a pass.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include "skip.h"

#include <cstdio>
#include <string>
#include <vector>

namespace {

struct Skip {
    std::string test, reason;
};
std::vector<Skip> skips;
std::string currentTest;
size_t testsRun = 0;

// Knows which test case runs, for skipTest.
struct TestNames : doctest::IReporter {
    explicit TestNames(const doctest::ContextOptions&) {}
    void report_query(const doctest::QueryData&) override {}
    void test_run_start() override {}
    void test_run_end(const doctest::TestRunStats&) override {}
    void test_case_start(const doctest::TestCaseData& data) override {
        currentTest = data.m_name;
        ++testsRun;
    }
    void test_case_reenter(const doctest::TestCaseData&) override {}
    void test_case_end(const doctest::CurrentTestCaseStats&) override {}
    void test_case_exception(const doctest::TestCaseException&) override {}
    void subcase_start(const doctest::SubcaseSignature&) override {}
    void subcase_end() override {}
    void log_assert(const doctest::AssertData&) override {}
    void log_message(const doctest::MessageData&) override {}
    void test_case_skipped(const doctest::TestCaseData&) override {}
};
REGISTER_LISTENER("test-names", 1, TestNames);

}  // namespace

void skipTest(const std::string& reason) {
    MESSAGE("SKIPPED: " << reason);
    if (skips.empty() || skips.back().test != currentTest) skips.push_back({currentTest, reason});
}

int main(int argc, char** argv) {
    doctest::Context context(argc, argv);
    int result = context.run();
    if (context.shouldExit()) return result;
    for (const Skip& s : skips) std::printf("SKIPPED: %s: %s\n", s.test.c_str(), s.reason.c_str());
    if (!skips.empty()) std::printf("[inkwell] %zu of %zu test cases skipped\n", skips.size(), testsRun);
    if (result == 0 && !skips.empty() && skips.size() == testsRun) return kSkipExitCode;
    return result;
}
