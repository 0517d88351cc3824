// The test runner: doctest's own main, except that a run which selects no test case fails.
// doctest exits 0 when its filters match nothing, so a ctest entry whose name no longer matches a
// case (a renamed case, or a name doctest_discover_tests split at ';') would pass having run
// nothing. Listing and counting (--list-test-cases, --count, ...) are not runs and are unaffected.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <iostream>

namespace {

// Whether a run happened and how many cases it selected: doctest reports test_run_end only for
// runs, not for listings or queries.
struct RunCount
{
    bool ran = false;
    unsigned selected = 0;
};
RunCount run_count;

struct SelectionListener : public doctest::IReporter
{
    explicit SelectionListener(const doctest::ContextOptions&) {}
    void report_query(const doctest::QueryData&) override {}
    void test_run_start() override {}
    void test_run_end(const doctest::TestRunStats& stats) override
    {
        run_count.ran = true;
        run_count.selected = stats.numTestCasesPassingFilters;
    }
    void test_case_start(const doctest::TestCaseData&) override {}
    void test_case_reenter(const doctest::TestCaseData&) override {}
    void test_case_end(const doctest::CurrentTestCaseStats&) override {}
    void test_case_exception(const doctest::TestCaseException&) override {}
    void subcase_start(const doctest::SubcaseSignature&) override {}
    void subcase_end() override {}
    void log_assert(const doctest::AssertData&) override {}
    void log_message(const doctest::MessageData&) override {}
    void test_case_skipped(const doctest::TestCaseData&) override {}
};
REGISTER_LISTENER("selection", 1, SelectionListener);

}  // namespace

int main(int argc, char** argv)
{
    doctest::Context context(argc, argv);
    const int result = context.run();
    if (context.shouldExit() || !run_count.ran)
        return result;
    if (run_count.selected == 0)
    {
        std::cerr << "vessel_tests: the filters selected no test case, so nothing was tested; "
                     "check the name given to -tc/--test-case against --list-test-cases (a ctest "
                     "entry with no case means a case was renamed, or its name holds a ';' that "
                     "doctest_discover_tests split)\n";
        return 1;
    }
    return result;
}
