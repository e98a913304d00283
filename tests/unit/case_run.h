/*
 * case_run: shared helpers of the case tests: run bin/pcisph on an edited
 * copy of a case under tests/output/, and read key=value facts printed by
 * the inspection scripts in tests/cases/.  Programs come from $SLUICE_BIN
 * (tests/run_tests sets it), default bin/.
 */
#ifndef SL_TEST_CASE_RUN_H
#define SL_TEST_CASE_RUN_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static inline const char *bin_dir(void)
{
    const char *b = getenv("SLUICE_BIN");
    return b ? b : "bin";
}

/* Copy src to tests/output/<name>, run the shell commands `edit` inside
 * it, then the solver; returns the shell's status. */
static inline int run_edited(const char *src, const char *name, const char *edit)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd,
             "rm -rf tests/output/%s && mkdir -p tests/output && cp -r %s tests/output/%s && "
             "(cd tests/output/%s && %s) && %s/pcisph -case tests/output/%s -quiet "
             "> tests/output/%s/log.pcisph 2>&1",
             name, src, name, name, edit, bin_dir(), name, name);
    return system(cmd);
}

/* The value of `key=` in the output of cmd (the last one); -1 if absent.
 * The command must exit 0. */
static inline double script_value(const char *cmd, const char *key)
{
    char line[512];
    double v = -1;
    FILE *p = popen(cmd, "r");
    if (!p) return -1;
    while (fgets(line, sizeof line, p))
        if (!strncmp(line, key, strlen(key)) && line[strlen(key)] == '=')
            v = strtod(line + strlen(key) + 1, NULL);
    if (pclose(p) != 0) return -1;
    return v;
}

#endif
