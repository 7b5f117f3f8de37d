/* A small FMI 3.0 host for the tests: loads an FMU binary with dlopen(RTLD_LOCAL), as most C
 * importers do, and runs the calls read from stdin, one per line, printing each result.
 *
 *   load PATH                                  dlopen the binary, resolve all fmi3* it needs
 *   instantiate NAME TOKEN RESOURCES EVENTMODE EARLY   -> "instance K" (K counts from 0) or "instance NULL"
 *   init K START                               fmi3EnterInitializationMode (no stop time)
 *   exit_init K | event_mode K | step_mode K | terminate K | free K
 *   set_clock K VR | get_clock K VR
 *   set_i64 K VR VALUE | get_i64 K VR | set_f64 K VR VALUE | get_f64 K VR
 *   update K                                   -> need_update terminate next_defined next_time
 *   do_step K T H                              -> event terminate early last
 *
 * Every call prints "status N" after its outputs; log messages print as "log STATUS CATEGORY: TEXT".
 * Not linked with libpython: the FMU must bring and set up everything it needs.
 */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3_library.h"

#define MAX_INSTANCES 8

static fmi3_api api;

static fmi3Instance instances[MAX_INSTANCES];
static int n_instances;

static void log_message(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message)
{
    (void)env;
    printf("log %d %s: %s\n", (int)status, category, message);
    fflush(stdout);
}

static void load(const char *path)
{
    void *library = fmi3_library_open(path);
    if (library == NULL) exit(2);
    fmi3_api_load(library, &api);
    printf("loaded\n");
}

static fmi3Instance instance(const char *text)
{
    int k = atoi(text);
    return (k >= 0 && k < n_instances) ? instances[k] : NULL;
}

int main(void)
{
    char line[4096];
    while (fgets(line, sizeof line, stdin) != NULL) {
        char *words[8] = {0};
        int n = 0;
        char *save = NULL;
        char *word = strtok_r(line, " \t\r\n", &save);
        fmi3Status status = fmi3OK;
        while (word != NULL && n < 8) {
            words[n++] = word;
            word = strtok_r(NULL, " \t\r\n", &save);
        }
        if (n == 0 || words[0][0] == '#') {
            continue;
        }
        if (strcmp(words[0], "load") == 0 && n == 2) {
            load(words[1]);
            continue;
        }
        if (strcmp(words[0], "instantiate") == 0 && n == 6) {
            fmi3Instance inst = api.instantiate(words[1], words[2], words[3], fmi3False, fmi3True, atoi(words[4]) != 0,
                                                atoi(words[5]) != 0, NULL, 0, NULL, log_message, NULL);
            if (inst == NULL || n_instances == MAX_INSTANCES) {
                printf("instance NULL\n");
            } else {
                instances[n_instances] = inst;
                printf("instance %d\n", n_instances++);
            }
            fflush(stdout);
            continue;
        }
        if (n < 2) {
            printf("bad command\n");
            return 2;
        }
        if (strcmp(words[0], "init") == 0 && n == 3) {
            status = api.enter_init(instance(words[1]), fmi3False, 0.0, atof(words[2]), fmi3False, 0.0);
        } else if (strcmp(words[0], "exit_init") == 0) {
            status = api.exit_init(instance(words[1]));
        } else if (strcmp(words[0], "event_mode") == 0) {
            status = api.enter_event_mode(instance(words[1]));
        } else if (strcmp(words[0], "step_mode") == 0) {
            status = api.enter_step_mode(instance(words[1]));
        } else if (strcmp(words[0], "terminate") == 0) {
            status = api.terminate(instance(words[1]));
        } else if (strcmp(words[0], "free") == 0) {
            api.free_instance(instance(words[1]));
        } else if (strcmp(words[0], "set_clock") == 0 && n == 3) {
            fmi3ValueReference vr = (fmi3ValueReference)atol(words[2]);
            fmi3Clock on = fmi3ClockActive;
            status = api.set_clock(instance(words[1]), &vr, 1, &on);
        } else if (strcmp(words[0], "get_clock") == 0 && n == 3) {
            fmi3ValueReference vr = (fmi3ValueReference)atol(words[2]);
            fmi3Clock value = fmi3ClockInactive;
            status = api.get_clock(instance(words[1]), &vr, 1, &value);
            printf("clock %d\n", (int)value);
        } else if (strcmp(words[0], "set_i64") == 0 && n == 4) {
            fmi3ValueReference vr = (fmi3ValueReference)atol(words[2]);
            fmi3Int64 value = strtoll(words[3], NULL, 10);
            status = api.set_int64(instance(words[1]), &vr, 1, &value, 1);
        } else if (strcmp(words[0], "get_i64") == 0 && n == 3) {
            fmi3ValueReference vr = (fmi3ValueReference)atol(words[2]);
            fmi3Int64 value = 0;
            status = api.get_int64(instance(words[1]), &vr, 1, &value, 1);
            printf("int64 %lld\n", (long long)value);
        } else if (strcmp(words[0], "set_f64") == 0 && n == 4) {
            fmi3ValueReference vr = (fmi3ValueReference)atol(words[2]);
            fmi3Float64 value = atof(words[3]);
            status = api.set_float64(instance(words[1]), &vr, 1, &value, 1);
        } else if (strcmp(words[0], "get_f64") == 0 && n == 3) {
            fmi3ValueReference vr = (fmi3ValueReference)atol(words[2]);
            fmi3Float64 value = 0.0;
            status = api.get_float64(instance(words[1]), &vr, 1, &value, 1);
            printf("float64 %.17g\n", value);
        } else if (strcmp(words[0], "update") == 0) {
            fmi3Boolean need = fmi3False, term = fmi3False, nominals = fmi3False, values = fmi3False;
            fmi3Boolean defined = fmi3False;
            fmi3Float64 next = 0.0;
            status = api.update(instance(words[1]), &need, &term, &nominals, &values, &defined, &next);
            printf("update %d %d %d %.17g\n", (int)need, (int)term, (int)defined, next);
        } else if (strcmp(words[0], "do_step") == 0 && n == 4) {
            fmi3Boolean event = fmi3False, term = fmi3False, early = fmi3False;
            fmi3Float64 last = 0.0;
            status = api.do_step(instance(words[1]), atof(words[2]), atof(words[3]), fmi3True, &event, &term, &early,
                                 &last);
            printf("step %d %d %d %.17g\n", (int)event, (int)term, (int)early, last);
        } else {
            printf("bad command %s\n", words[0]);
            return 2;
        }
        printf("status %d\n", (int)status);
        fflush(stdout);
    }
    return 0;
}
