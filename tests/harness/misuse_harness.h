/* What the two API-misuse programs share (tests/runtime/misuse.c against hand-written test
 * models, tests/codegen/misuse_generated.c against generated FMUs): loading an FMU's functions,
 * capturing its log, and TAP-like reporting.
 *
 * The includer defines HARNESS_FUNCTIONS(X), the list of fmi3 functions it calls (without the
 * prefix), before including this header. Output: "ok <n> - <kind>: <name>" or
 * "not ok <n> - <kind>: <name>: <why>" per case (kind "misuse" or "check"); harness_finish()
 * prints "# cases <n> misuse <k> failures <m>" and gives the exit status. */
#ifndef ROBOGEN_TEST_MISUSE_HARNESS_H
#define ROBOGEN_TEST_MISUSE_HARNESS_H

#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3FunctionTypes.h"

#ifndef HARNESS_FUNCTIONS
#error "define HARNESS_FUNCTIONS(X) before including misuse_harness.h"
#endif

typedef struct {
#define HARNESS_FIELD(name) fmi3##name##TYPE *name;
    HARNESS_FUNCTIONS(HARNESS_FIELD)
#undef HARNESS_FIELD
} fmu_api;

/* Looks every function up in the library at `path` (which stays loaded until exit). */
static int load(const char *path, fmu_api *api)
{
    void *library = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    void *symbol;
    if (library == NULL) {
        fprintf(stderr, "cannot load %s: %s\n", path, dlerror());
        return 0;
    }
#define HARNESS_LOOKUP(name)                                                   \
    symbol = dlsym(library, "fmi3" #name);                                     \
    if (symbol == NULL) {                                                      \
        fprintf(stderr, "%s does not export fmi3" #name "\n", path);           \
        return 0;                                                              \
    }                                                                          \
    memcpy(&api->name, &symbol, sizeof symbol);
    HARNESS_FUNCTIONS(HARNESS_LOOKUP)
#undef HARNESS_LOOKUP
    return 1;
}

/* ---- log capture: the last message, and every message since the current case began -------- */

static size_t log_count = 0;
static char last_log[2048];
static char case_logs[16384];
static size_t case_length = 0;

static void capture_log(fmi3InstanceEnvironment environment, fmi3Status status, fmi3String category,
                        fmi3String message)
{
    int n;
    (void)environment;
    log_count += 1;
    snprintf(last_log, sizeof last_log, "[%d %s] %s", (int)status, category, message);
    n = snprintf(case_logs + case_length, sizeof case_logs - case_length, "%s\n", last_log);
    if (n > 0 && (size_t)n < sizeof case_logs - case_length) case_length += (size_t)n;
}

static void begin_case(void)
{
    case_length = 0;
    case_logs[0] = '\0';
}

/* ---- reporting ------------------------------------------------------------------------------- */

static int cases = 0, misuse_cases = 0, failures = 0;

static void report_kind(const char *kind, const char *name, int ok, const char *why)
{
    cases += 1;
    if (ok) {
        printf("ok %d - %s: %s\n", cases, kind, name);
    } else {
        failures += 1;
        printf("not ok %d - %s: %s: %s\n", cases, kind, name, why);
    }
}

/* a control check: the harness itself works */
static void report(const char *name, int ok, const char *why)
{
    report_kind("check", name, ok, why);
}

static void report_misuse(const char *name, int ok, const char *why)
{
    misuse_cases += 1;
    report_kind("misuse", name, ok, why);
}

/* A misuse: fmi3Error or fmi3Discard and, if a logger can be reached (`expected` not NULL), a new
 * log message in this case that contains `expected`, so the case fails for the reason it tests. */
static void expect_failure(const char *name, fmi3Status status, size_t logs_before, const char *expected)
{
    char why[2300];
    if (status != fmi3Error && status != fmi3Discard) {
        snprintf(why, sizeof why, "returned status %d", (int)status);
        report_misuse(name, 0, why);
    } else if (expected != NULL && log_count == logs_before) {
        report_misuse(name, 0, "no log message");
    } else if (expected != NULL && strstr(case_logs, expected) == NULL) {
        snprintf(why, sizeof why, "log lacks \"%s\": %s", expected, last_log);
        report_misuse(name, 0, why);
    } else {
        report_misuse(name, 1, "");
    }
}

#define MISUSE(name, expected, call)                         \
    do {                                                     \
        size_t before_ = log_count;                          \
        begin_case();                                        \
        expect_failure(name, (call), before_, expected);     \
    } while (0)

/* NULL or dead instance: no logger to reach (the Python side checks stderr instead) */
#define MISUSE_UNLOGGABLE(name, call)                        \
    do {                                                     \
        size_t before_ = log_count;                          \
        begin_case();                                        \
        expect_failure(name, (call), before_, NULL);         \
    } while (0)

/* A step that must work for the cases to mean anything; a failure aborts the program. */
static void require(const char *what, fmi3Status status)
{
    if (status != fmi3OK && status != fmi3Warning) {
        printf("Bail out! '%s' returned %d (last log: %s)\n", what, (int)status, last_log);
        exit(2);
    }
}

static int harness_finish(void)
{
    printf("# cases %d misuse %d failures %d\n", cases, misuse_cases, failures);
    return failures == 0 ? 0 : 1;
}

#endif
