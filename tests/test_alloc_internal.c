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

// Fills n uint32 elements with their indices offset by `salt`.
static void fill(uint32_t *a, size_t from, size_t to, uint32_t salt) {
    for (size_t i = from; i < to; ++i)
        a[i] = (uint32_t)i ^ salt;
}

static void assert_filled(const uint32_t *a, size_t n, uint32_t salt) {
    for (size_t i = 0; i < n; ++i)
        if (a[i] != ((uint32_t)i ^ salt))
            fail_msg("element %zu is %u, not %u", i, a[i], (unsigned)((uint32_t)i ^ salt));
}

// Growing keeps the used elements and the alignment, from small blocks
// through sizes glibc maps on their own (realloc then remaps the pages), with
// the default allocator and with a caller's (new block, copy, free).
static void test_alloc_grow_keeps_the_used_elements(void **state) {
    (void)state;
    test_allocator_state st = {0};
    const selfcol_allocator hooks = test_allocator(&st);
    const selfcol_allocator *allocators[2] = {NULL, &hooks};
    for (int k = 0; k < 2; ++k) {
        const selfcol_allocator *al = allocators[k];
        uint32_t *a = selfcol_alloc__grow_array(al, NULL, 0, 0, 3, sizeof *a);
        assert_non_null(a);
        size_t capacity = 3, used = 3;
        fill(a, 0, used, 0x5a5a5a5au);
        while (capacity < ((size_t)1 << 21)) { // up to 8 MB
            const size_t grown = capacity * 2 + 5;
            uint32_t *b = selfcol_alloc__grow_array(al, a, used, capacity, grown, sizeof *b);
            assert_non_null(b);
            assert_int_equal((uintptr_t)b % SELFCOL_ALIGNMENT, 0);
            assert_filled(b, used, 0x5a5a5a5au);
            fill(b, used, grown, 0x5a5a5a5au); // the new part is writable
            a = b;
            used = grown - grown / 3; // keep a part only: the rest may be lost
            capacity = grown;
        }
        selfcol_alloc__free_array(al, a, capacity, sizeof *a);
    }
    assert_int_equal(st.live, 0);
    assert_false(st.misaligned);
}

// Bad arguments and a failing allocator: NULL, and the old array is left
// intact and still the caller's.
static void test_alloc_grow_failure_keeps_the_old_array(void **state) {
    (void)state;
    test_allocator_state st = {0};
    const selfcol_allocator hooks = test_allocator(&st);
    uint32_t *a = selfcol_alloc__array(&hooks, 100, sizeof *a);
    assert_non_null(a);
    fill(a, 0, 100, 7u);
    assert_null(selfcol_alloc__grow_array(&hooks, a, 100, 100, 50, sizeof *a));  // shrinks
    assert_null(selfcol_alloc__grow_array(&hooks, a, 101, 100, 200, sizeof *a)); // used > old
    assert_null(selfcol_alloc__grow_array(&hooks, a, 100, 100, SIZE_MAX / 2, sizeof *a));
    assert_null(selfcol_alloc__grow_array(NULL, NULL, 0, 0, 0, sizeof *a));
    st.fail_at = st.calls + 1;
    assert_null(selfcol_alloc__grow_array(&hooks, a, 100, 100, 200, sizeof *a));
    st.fail_at = 0;
    assert_filled(a, 100, 7u);
    assert_int_equal(st.live, 1);
    selfcol_alloc__free_array(&hooks, a, 100, sizeof *a);
    assert_int_equal(st.live, 0);
    // (The default allocator's realloc failing cannot be provoked portably:
    // sanitizers abort on an impossible size instead of returning NULL. Its
    // failure path is the same "old block untouched" contract of realloc.)
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_alloc_grow_keeps_the_used_elements),
        cmocka_unit_test(test_alloc_grow_failure_keeps_the_old_array),
        cmocka_unit_test(test_alloc_default_allocator_aligns_and_frees),
        cmocka_unit_test(test_alloc_array_rejects_overflow),
        cmocka_unit_test(test_alloc_validates_half_set_allocators),
    };
    return cmocka_run_group_tests_name("alloc_internal", tests, NULL, NULL);
}
