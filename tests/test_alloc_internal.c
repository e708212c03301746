// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The allocation layer every handle goes through.
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <string.h>

#include "base/alloc.h"
#include "test_alloc.h"

static void test_alloc_default_allocator_aligns_and_frees(void **state) {
    (void)state;
    for (size_t size = 1; size < 4096; size = size * 3 + 1) {
        unsigned char *p = selfcol_alloc__raw(NULL, size);
        assert_non_null(p);
        assert_int_equal((uintptr_t)p % SELFCOL_ALIGNMENT, 0);
        memset(p, 0xab, size); // the whole block is writable (ASan/valgrind check)
        selfcol_alloc__free(NULL, p, size);
    }
    assert_null(selfcol_alloc__raw(NULL, 0));
    selfcol_alloc__free(NULL, NULL, 0);
}

static void test_alloc_array_rejects_overflow(void **state) {
    (void)state;
    test_allocator_state st = {0};
    selfcol_allocator a = test_allocator(&st);
    assert_null(selfcol_alloc__array(&a, SIZE_MAX / 2, 4));
    assert_null(selfcol_alloc__array(&a, 0, 4));
    assert_int_equal(st.calls, 0);
    void *p = selfcol_alloc__array(&a, 10, 8);
    assert_non_null(p);
    assert_int_equal((uintptr_t)p % SELFCOL_ALIGNMENT, 0);
    selfcol_alloc__free_array(&a, p, 10, 8);
    assert_int_equal(st.live, 0);
    assert_false(st.misaligned);
}

static void test_alloc_validates_half_set_allocators(void **state) {
    (void)state;
    test_allocator_state st = {0};
    selfcol_allocator a = test_allocator(&st);
    assert_true(selfcol_alloc__valid(&a));
    assert_true(selfcol_alloc__valid(NULL));
    a.alloc = NULL;
    assert_false(selfcol_alloc__valid(&a));
    a = test_allocator(&st);
    a.free = NULL;
    assert_false(selfcol_alloc__valid(&a));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_alloc_default_allocator_aligns_and_frees),
        cmocka_unit_test(test_alloc_array_rejects_overflow),
        cmocka_unit_test(test_alloc_validates_half_set_allocators),
    };
    return cmocka_run_group_tests_name("alloc_internal", tests, NULL, NULL);
}
