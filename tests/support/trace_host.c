/* A portable FMI 3.0 Co-Simulation host for the cross-platform tests: the same source is built
 * for Linux (dlopen) and Windows (LoadLibrary), natively and with zig, and runs one scenario on an
 * FMU binary of its own platform. The scenario is read from stdin, one command per line; the
 * transcript goes to stdout, so the transcripts of two platforms compare byte for byte.
 *
 *   load FILE                      load the library, resolve the functions the host calls
 *   instantiate TOKEN              fmi3InstantiateCoSimulation, event mode used, no early return
 *   init / exit_init               fmi3EnterInitializationMode (start 0, no stop) / fmi3ExitInitializationMode
 *   step T H                       fmi3EnterStepMode, fmi3DoStep(T, H), fmi3EnterEventMode
 *   clock VR                       fmi3SetClock: VR ticks now
 *   set TYPE VR VALUE              fmi3Set<TYPE> of one value (TYPE: Int64 UInt64 Float64 Boolean)
 *   watch CLOCK_VR [TYPE:VR ...]   an output clock and its clocked values, read when it ticks
 *   observe [TYPE:VR ...]          values read at every super-dense step
 *   settle I                       the super-dense steps of instant I: each prints "instant I k K",
 *                                  the ticking output clocks ("tick VR" and their values), the
 *                                  observed values, then fmi3UpdateDiscreteStates ("need N"),
 *                                  until no further update is needed
 *   free                           fmi3FreeInstance
 *
 * A value prints as "TYPE:VR=VALUE" (reals with 17 significant digits, so equal text is equal
 * bits). A call that returns more than fmi3Warning prints "FUNCTION -> status N" and ends the run
 * with exit code 1; the FMU's log messages print as "log STATUS CATEGORY: TEXT".
 */
#if !defined(_WIN32)
#define _POSIX_C_SOURCE 200809L
#endif

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3_library.h"

#if defined(_WIN32)
#include <fcntl.h>
#include <io.h>
#endif

#define MAX_WATCHED 64
#define MAX_VALUES 32
#define MAX_STEPS 1000

typedef enum { T_INT64, T_UINT64, T_FLOAT64, T_BOOLEAN } value_type;

typedef struct {
    value_type type;
    fmi3ValueReference vr;
} value_ref;

typedef struct {
    fmi3ValueReference clock;
    value_ref values[MAX_VALUES];
    int n_values;
} watched_clock;

static fmi3_api api;

static fmi3Instance instance;
static watched_clock watched[MAX_WATCHED];
static int n_watched;
static value_ref observed[MAX_VALUES];
static int n_observed;

static const char *const TYPE_NAMES[] = {"Int64", "UInt64", "Float64", "Boolean"};

static void fail(const char *what)
{
    printf("%s\n", what);
    fflush(stdout);
    exit(2);
}

static void check(const char *function, fmi3Status status)
{
    if (status > fmi3Warning) {
        printf("%s -> status %d\n", function, (int)status);
        fflush(stdout);
        exit(1);
    }
}

static void log_message(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message)
{
    (void)env;
    printf("log %d %s: %s\n", (int)status, category, message);
}

static void load(const char *path)
{
    void *library = fmi3_library_open(path);
    if (library == NULL) fail("cannot load the library");
    fmi3_api_load(library, &api);
}

static value_type type_named(const char *name)
{
    int t;
    for (t = 0; t < 4; t++) {
        if (strcmp(name, TYPE_NAMES[t]) == 0) return (value_type)t;
    }
    fail("unknown type");
    return T_INT64;
}

/* "TYPE:VR" */
static value_ref parse_ref(char *word)
{
    value_ref ref;
    char *colon = strchr(word, ':');
    if (colon == NULL) fail("expected TYPE:VR");
    *colon = '\0';
    ref.type = type_named(word);
    ref.vr = (fmi3ValueReference)strtoul(colon + 1, NULL, 10);
    return ref;
}

static int parse_refs(value_ref *refs, int most)
{
    int n = 0;
    char *word;
    while ((word = strtok(NULL, " \n")) != NULL) {
        if (n == most) fail("too many values");
        refs[n++] = parse_ref(word);
    }
    return n;
}

static void print_value(value_ref ref)
{
    printf("  %s:%u=", TYPE_NAMES[ref.type], (unsigned)ref.vr);
    switch (ref.type) {
    case T_INT64: {
        fmi3Int64 v;
        check("fmi3GetInt64", api.get_int64(instance, &ref.vr, 1, &v, 1));
        printf("%" PRId64 "\n", (int64_t)v);
        break;
    }
    case T_UINT64: {
        fmi3UInt64 v;
        check("fmi3GetUInt64", api.get_uint64(instance, &ref.vr, 1, &v, 1));
        printf("%" PRIu64 "\n", (uint64_t)v);
        break;
    }
    case T_FLOAT64: {
        fmi3Float64 v;
        check("fmi3GetFloat64", api.get_float64(instance, &ref.vr, 1, &v, 1));
        printf("%.17g\n", v);
        break;
    }
    case T_BOOLEAN: {
        fmi3Boolean v;
        check("fmi3GetBoolean", api.get_boolean(instance, &ref.vr, 1, &v, 1));
        printf("%d\n", v ? 1 : 0);
        break;
    }
    }
}

static void set_value(value_ref ref, const char *text)
{
    switch (ref.type) {
    case T_INT64: {
        fmi3Int64 v = (fmi3Int64)strtoll(text, NULL, 10);
        check("fmi3SetInt64", api.set_int64(instance, &ref.vr, 1, &v, 1));
        break;
    }
    case T_UINT64: {
        fmi3UInt64 v = (fmi3UInt64)strtoull(text, NULL, 10);
        check("fmi3SetUInt64", api.set_uint64(instance, &ref.vr, 1, &v, 1));
        break;
    }
    case T_FLOAT64: {
        fmi3Float64 v = strtod(text, NULL);
        check("fmi3SetFloat64", api.set_float64(instance, &ref.vr, 1, &v, 1));
        break;
    }
    case T_BOOLEAN: {
        fmi3Boolean v = strcmp(text, "0") != 0;
        check("fmi3SetBoolean", api.set_boolean(instance, &ref.vr, 1, &v, 1));
        break;
    }
    }
}

/* The super-dense steps of one instant. */
static void settle(long at)
{
    int k, i, j;
    for (k = 0; k < MAX_STEPS; k++) {
        fmi3Boolean need, terminate, nominals_changed, values_changed, next_defined;
        fmi3Float64 next;
        printf("instant %ld k %d\n", at, k);
        for (i = 0; i < n_watched; i++) {
            fmi3Clock ticking = fmi3ClockInactive;
            check("fmi3GetClock", api.get_clock(instance, &watched[i].clock, 1, &ticking));
            if (!ticking) continue;
            printf("  tick %u\n", (unsigned)watched[i].clock);
            for (j = 0; j < watched[i].n_values; j++) print_value(watched[i].values[j]);
        }
        for (i = 0; i < n_observed; i++) print_value(observed[i]);
        check("fmi3UpdateDiscreteStates", api.update(instance, &need, &terminate, &nominals_changed, &values_changed,
                                                             &next_defined, &next));
        printf("  need %d terminate %d\n", need ? 1 : 0, terminate ? 1 : 0);
        if (!need) return;
    }
    fail("more than MAX_STEPS super-dense steps");
}

static void command(char *line)
{
    char *name = strtok(line, " \n");
    char *arg = name != NULL ? strtok(NULL, " \n") : NULL;
    if (name == NULL) return;
    if (strcmp(name, "load") == 0 && arg != NULL) {
        load(arg);
    } else if (strcmp(name, "instantiate") == 0 && arg != NULL) {
        instance = api.instantiate("trace", arg, NULL, fmi3False, fmi3False, fmi3True, fmi3False, NULL, 0, NULL,
                                   log_message, NULL);
        if (instance == NULL) fail("fmi3InstantiateCoSimulation -> NULL");
    } else if (strcmp(name, "init") == 0) {
        check("fmi3EnterInitializationMode", api.enter_init(instance, fmi3False, 0.0, 0.0, fmi3False, 0.0));
    } else if (strcmp(name, "exit_init") == 0) {
        check("fmi3ExitInitializationMode", api.exit_init(instance));
    } else if (strcmp(name, "step") == 0 && arg != NULL) {
        char *h = strtok(NULL, " \n");
        fmi3Boolean event, terminate, early;
        fmi3Float64 last;
        if (h == NULL) fail("step T H");
        check("fmi3EnterStepMode", api.enter_step_mode(instance));
        check("fmi3DoStep", api.do_step(instance, strtod(arg, NULL), strtod(h, NULL), fmi3True, &event, &terminate,
                                        &early, &last));
        printf("step %s %s: event %d terminate %d early %d last %.17g\n", arg, h, event ? 1 : 0, terminate ? 1 : 0,
               early ? 1 : 0, last);
        check("fmi3EnterEventMode", api.enter_event_mode(instance));
    } else if (strcmp(name, "clock") == 0 && arg != NULL) {
        fmi3ValueReference vr = (fmi3ValueReference)strtoul(arg, NULL, 10);
        fmi3Clock on = fmi3ClockActive;
        check("fmi3SetClock", api.set_clock(instance, &vr, 1, &on));
    } else if (strcmp(name, "set") == 0 && arg != NULL) {
        char *vr = strtok(NULL, " \n");
        char *value = vr != NULL ? strtok(NULL, " \n") : NULL;
        value_ref ref;
        if (value == NULL) fail("set TYPE VR VALUE");
        ref.type = type_named(arg);
        ref.vr = (fmi3ValueReference)strtoul(vr, NULL, 10);
        set_value(ref, value);
    } else if (strcmp(name, "watch") == 0 && arg != NULL) {
        if (n_watched == MAX_WATCHED) fail("too many watched clocks");
        watched[n_watched].clock = (fmi3ValueReference)strtoul(arg, NULL, 10);
        watched[n_watched].n_values = parse_refs(watched[n_watched].values, MAX_VALUES);
        n_watched++;
    } else if (strcmp(name, "observe") == 0) {
        if (arg != NULL) {
            observed[n_observed++] = parse_ref(arg);
            n_observed += parse_refs(observed + n_observed, MAX_VALUES - n_observed);
        }
    } else if (strcmp(name, "settle") == 0 && arg != NULL) {
        settle(strtol(arg, NULL, 10));
    } else if (strcmp(name, "free") == 0) {
        api.free_instance(instance);
        instance = NULL;
        printf("freed\n");
    } else {
        fail("unknown command");
    }
}

int main(void)
{
    char line[4096];
#if defined(_WIN32)
    (void)_setmode(_fileno(stdout), _O_BINARY); /* "\n", as on Linux: the transcripts compare byte for byte */
#endif
    while (fgets(line, sizeof line, stdin) != NULL) {
        command(line);
        fflush(stdout);
    }
    return 0;
}
