// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#include "query/contacts.h"

#include "base/alloc.h"
#include "base/core.h"

#include <stddef.h>
#include <string.h>

int selfcol_contacts_options_init(selfcol_contacts_options *opts, unsigned int version) {
    SELFCOL_CHECK(opts != NULL);
    if (version == 0 || version > SELFCOL_CONTACTS_OPTIONS_VERSION)
        return SELFCOL_EVERSION;
    memset(opts, 0, sizeof *opts);
    opts->version = version;
    return SELFCOL_OK;
}

int selfcol_contacts_create(selfcol_contacts **out, const selfcol_contacts_options *opts) {
    SELFCOL_CHECK(out != NULL);
    *out = NULL;
    SELFCOL_CHECK_VERSION(opts, SELFCOL_CONTACTS_OPTIONS_VERSION);
    selfcol_allocator allocator = {NULL, NULL, NULL};
    if (opts != NULL)
        allocator = opts->allocator;
    SELFCOL_CHECK(selfcol_alloc__valid(&allocator));
    selfcol_contacts *c = selfcol_alloc__raw(&allocator, sizeof *c);
    if (c == NULL)
        return SELFCOL_ENOMEM;
    memset(c, 0, sizeof *c);
    selfcol_records__init(&c->records, &allocator);
    *out = c;
    return SELFCOL_OK;
}

void selfcol_contacts_destroy(selfcol_contacts *contacts) {
    if (contacts == NULL)
        return;
    selfcol_allocator allocator = contacts->records.allocator;
    if (!contacts->context_borrowed)
        selfcol_context_destroy(contacts->implicit_context);
    selfcol_records__free(&contacts->records);
    selfcol_alloc__free(&allocator, contacts, sizeof *contacts);
}

void selfcol_contacts_clear(selfcol_contacts *contacts) {
    if (contacts != NULL)
        selfcol_records__clear(&contacts->records);
}

size_t selfcol_contacts_count(const selfcol_contacts *contacts) {
    return contacts != NULL ? contacts->records.count : 0;
}

int selfcol_contacts_data(const selfcol_contacts *contacts, const selfcol_contact **data_out,
                          size_t *count_out) {
    SELFCOL_CHECK(contacts != NULL && data_out != NULL && count_out != NULL);
    *data_out = contacts->records.count > 0 ? contacts->records.items : NULL;
    *count_out = contacts->records.count;
    return SELFCOL_OK;
}

int selfcol_contacts_stats(const selfcol_contacts *contacts, selfcol_query_stats *stats) {
    SELFCOL_CHECK(contacts != NULL && stats != NULL);
    if (stats->version == 0 || stats->version > SELFCOL_QUERY_STATS_VERSION)
        return SELFCOL_EVERSION;
    // Each version appends fields: copy only the prefix the caller's version
    // knows (its struct may be shorter than ours).
    static const size_t size_of_version[SELFCOL_QUERY_STATS_VERSION + 1] = {
        0, offsetof(selfcol_query_stats, nodes_visited),
        offsetof(selfcol_query_stats, contour_tests),
        offsetof(selfcol_query_stats, pairs_separated), sizeof(selfcol_query_stats)};
    unsigned int version = stats->version;
    memcpy(stats, &contacts->records.stats, size_of_version[version]);
    stats->version = version;
    return SELFCOL_OK;
}

size_t selfcol_contacts_byte_count(const selfcol_contacts *contacts) {
    if (contacts == NULL)
        return 0;
    size_t bytes = sizeof *contacts + selfcol_records__byte_count(&contacts->records);
    if (!contacts->context_borrowed)
        bytes += selfcol_context_byte_count(contacts->implicit_context);
    return bytes;
}

void selfcol_contacts__lend_context(selfcol_contacts *contacts, selfcol_context *context) {
    if (!contacts->context_borrowed)
        selfcol_context_destroy(contacts->implicit_context);
    contacts->implicit_context = context;
    contacts->context_borrowed = context != NULL;
}
