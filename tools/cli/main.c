// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol-cli: collisions and self-collisions of triangle meshes from the
// command line. Commands: check (one mesh, two meshes, or a sequence of
// frames of one topology), track (a sequence through the contact store) and
// info. Uses only the public libselfcol API.
#define _POSIX_C_SOURCE 200809L
#include "commands.h"

#include <string.h>

int main(int argc, char **argv) {
    if (argc < 2) {
        fputs(cli_main_help, stderr);
        return CLI_EXIT_ERROR;
    }
    const char *command = argv[1];
    if (strcmp(command, "--version") == 0 || strcmp(command, "version") == 0) {
        printf("selfcol-cli %s\n", selfcol_version_string());
        return CLI_EXIT_CLEAN;
    }
    if (strcmp(command, "-h") == 0 || strcmp(command, "--help") == 0 ||
        strcmp(command, "help") == 0) {
        fputs(cli_main_help, stdout);
        return CLI_EXIT_CLEAN;
    }
    cli_options o;
    if (strcmp(command, "check") == 0 || strcmp(command, "track") == 0 ||
        strcmp(command, "info") == 0) {
        int rc = cli_parse_options(argc, argv, 2, command, &o);
        if (rc < 0)
            return CLI_EXIT_CLEAN; // --help
        if (rc > 0)
            return rc;
        return strcmp(command, "check") == 0   ? cli_command_check(&o)
               : strcmp(command, "track") == 0 ? cli_command_track(&o)
                                               : cli_command_info(&o);
    }
    return cli_usage_error(NULL, "unknown command '%s' (check, track, info)", command);
}
