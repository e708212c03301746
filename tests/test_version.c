// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Version and status strings, through the public API.
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include <selfcol/selfcol.h>

static void test_version_runtime_matches_headers(void **state) {
    (void)state;
    char expected[32];
    snprintf(expected, sizeof expected, "%d.%d.%d", SELFCOL_VERSION_MAJOR, SELFCOL_VERSION_MINOR,
             SELFCOL_VERSION_PATCH);
    assert_string_equal(selfcol_version_string(), expected);
    assert_string_equal(SELFCOL_VERSION_STRING, expected);
    assert_int_equal(selfcol_version_number(), SELFCOL_VERSION_MAJOR * 10000 +
                                                   SELFCOL_VERSION_MINOR * 100 +
                                                   SELFCOL_VERSION_PATCH);
    assert_true(SELFCOL_VERSION_CHECK(SELFCOL_VERSION_MAJOR, SELFCOL_VERSION_MINOR, 0));
    assert_false(SELFCOL_VERSION_CHECK(SELFCOL_VERSION_MAJOR + 1, 0, 0));
}

static void test_version_status_strings_are_distinct_and_never_null(void **state) {
    (void)state;
    const int codes[] = {SELFCOL_OK,     SELFCOL_ERROR,    SELFCOL_ENOMEM,
                         SELFCOL_EINVAL, SELFCOL_EVERSION, SELFCOL_EBUFS,
                         SELFCOL_EUSER,  SELFCOL_ERANGE,   SELFCOL_EMISMATCH};
    const size_t n = sizeof codes / sizeof codes[0];
    for (size_t i = 0; i < n; ++i) {
        assert_non_null(selfcol_status_string(codes[i]));
        for (size_t j = 0; j < i; ++j)
            assert_string_not_equal(selfcol_status_string(codes[i]),
                                    selfcol_status_string(codes[j]));
    }
    assert_string_equal(selfcol_status_string(-12345), "unknown status");
    // Pinned values (the ABI promise).
    assert_int_equal(SELFCOL_ENOMEM, -2);
    assert_int_equal(SELFCOL_EINVAL, -3);
    assert_int_equal(SELFCOL_EVERSION, -4);
    assert_int_equal(SELFCOL_CONTACT_EF, 2);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_version_runtime_matches_headers),
        cmocka_unit_test(test_version_status_strings_are_distinct_and_never_null),
    };
    return cmocka_run_group_tests_name("version", tests, NULL, NULL);
}
