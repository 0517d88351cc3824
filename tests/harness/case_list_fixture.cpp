// Cases with the names that ctest entries get wrong, for the test of check_case_list.py and of the
// test main's refusal of a run that selects nothing (check_case_list_test.py). Built with
// tests/main.cpp, never discovered into ctest, never run as part of the suite.
#include <doctest/doctest.h>

TEST_CASE("fixture: a plain name") { CHECK(true); }

TEST_CASE("fixture: split here; and here") { CHECK(true); }

TEST_CASE("fixture: twice") { CHECK(true); }
TEST_CASE("fixture: twice") { CHECK(true); }

TEST_CASE("fixture: any*") { CHECK(true); }
TEST_CASE("fixture: any other") { CHECK(true); }

TEST_SUITE("slow")
{
    TEST_CASE("fixture: a slow one") { CHECK(true); }
    TEST_CASE("fixture: slow, with a comma") { CHECK(true); }
}
