/* replay.c: drive a generated FMU, linked into this program, through input scenarios read from
 * a script, as robogen.differential.FmuRunner drives it from Python (the model fuzzer builds it
 * with AddressSanitizer and UndefinedBehaviorSanitizer: property 5 of docs/fuzzing.md).
 *
 * The script, one command per line (numbers in decimal, reals as C99 hexadecimal floats, texts
 * as hexadecimal bytes, "-" for the empty text):
 *
 *   token TEXT                       the instantiation token
 *   get TYPE VALUES VR...            the variables read at every super-dense step, by FMI type,
 *                                    and how many values they hold together (arrays count each)
 *   clock VR                         an output clock, read at every step
 *   clocked TYPE VALUES VR...        the variables of the last output clock, read when it ticks
 *   periodic VR INTERVAL HALF        the periodic clock; HALF: instants are half a period apart
 *   scenario                         a new run (fmi3Reset between runs)
 *   instant PERIODIC                 the next time instant; PERIODIC: the periodic clock ticks
 *   tick AT VR                       an input clock ticks (AT -1: before the first read, else
 *   set AT TYPE VR N VALUE...          after the read of super-dense step AT) with its values
 *   end                              run the scenario; print "run STEPS ERROR_INSTANT ERROR_K"
 *
 * TYPE is one of f64 i64 u64 bool str. Exit status 0 when every script line was understood.
 */
#include <inttypes.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"

#define MAX_WORDS 4096
#define MAX_INSTANTS 64
#define MAX_ACTIONS 32
#define MAX_STEPS 2000

enum { T_F64, T_I64, T_U64, T_BOOL, T_STR, N_TYPES };
static const char *const TYPE_NAMES[N_TYPES] = {"f64", "i64", "u64", "bool", "str"};

typedef struct {
    int at;       /* -1: before the first read */
    int type;     /* -1: a clock */
    fmi3ValueReference vr;
    size_t n;
    double f[64];
    int64_t i[64];
    uint64_t u[64];
    bool b[64];
    char *s[64];
} Action;

typedef struct {
    bool periodic;
    int n_actions;
    Action actions[MAX_ACTIONS];
} Instant;

static char token[256];
#define MAX_CLOCKS 64
#define MAX_CLOCKED 256
typedef struct {
    fmi3ValueReference vr[N_TYPES][MAX_CLOCKED];
    size_t n[N_TYPES];
    size_t values[N_TYPES];
} Group;
static fmi3ValueReference clock_vr[MAX_CLOCKS];
static Group clocked[MAX_CLOCKS];
static size_t n_clocks;
static Group observed;
static fmi3ValueReference periodic_vr;
static double interval;
static bool half = true;
static Instant instants[MAX_INSTANTS];
static int n_instants;

static void logger(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message)
{
    (void)env;
    if (getenv("REPLAY_LOG")) fprintf(stderr, "log %d %s: %s\n", (int)status, category, message);
}

static int type_of(const char *word)
{
    for (int t = 0; t < N_TYPES; t++)
        if (strcmp(word, TYPE_NAMES[t]) == 0) return t;
    fprintf(stderr, "replay: unknown type %s\n", word);
    exit(2);
}

static char *text_of(const char *hex)
{
    size_t n = strcmp(hex, "-") == 0 ? 0 : strlen(hex) / 2;
    char *out = malloc(n + 1);
    for (size_t k = 0; k < n; k++) {
        unsigned byte;
        sscanf(hex + 2 * k, "%2x", &byte);
        out[k] = (char)byte;
    }
    out[n] = '\0';
    return out;
}

static void free_actions(void)
{
    for (int i = 0; i < n_instants; i++)
        for (int a = 0; a < instants[i].n_actions; a++)
            if (instants[i].actions[a].type == T_STR)
                for (size_t k = 0; k < instants[i].actions[a].n; k++) free(instants[i].actions[a].s[k]);
    n_instants = 0;
}

static void apply(fmi3Instance inst, const Action *a, fmi3Status *status)
{
    fmi3Status s = fmi3OK;
    if (a->type < 0) {
        fmi3Clock on = fmi3ClockActive;
        s = fmi3SetClock(inst, &a->vr, 1, &on);
    } else if (a->type == T_F64) {
        s = fmi3SetFloat64(inst, &a->vr, 1, a->f, a->n);
    } else if (a->type == T_I64) {
        s = fmi3SetInt64(inst, &a->vr, 1, a->i, a->n);
    } else if (a->type == T_U64) {
        s = fmi3SetUInt64(inst, &a->vr, 1, a->u, a->n);
    } else if (a->type == T_BOOL) {
        s = fmi3SetBoolean(inst, &a->vr, 1, a->b, a->n);
    } else {
        s = fmi3SetString(inst, &a->vr, 1, (const fmi3String *)a->s, a->n);
    }
    if (s > *status) *status = s;
}

/* Read the variables of a group, one call per type. */
static fmi3Status read_group(fmi3Instance inst, const Group *g)
{
    static double f[MAX_CLOCKED * 64];
    static int64_t i[MAX_CLOCKED * 64];
    static uint64_t u[MAX_CLOCKED * 64];
    static bool b[MAX_CLOCKED * 64];
    static fmi3String s[MAX_CLOCKED * 64];
    fmi3Status worst = fmi3OK, st = fmi3OK;
    for (int t = 0; t < N_TYPES; t++) {
        size_t m = g->values[t];
        if (!g->n[t] || m > MAX_CLOCKED * 64) continue;
        if (t == T_F64) st = fmi3GetFloat64(inst, g->vr[t], g->n[t], f, m);
        else if (t == T_I64) st = fmi3GetInt64(inst, g->vr[t], g->n[t], i, m);
        else if (t == T_U64) st = fmi3GetUInt64(inst, g->vr[t], g->n[t], u, m);
        else if (t == T_BOOL) st = fmi3GetBoolean(inst, g->vr[t], g->n[t], b, m);
        else st = fmi3GetString(inst, g->vr[t], g->n[t], s, m);
        if (st > worst) worst = st;
    }
    return worst;
}

/* Read what FmuRunner reads at every step: the output clocks, the variables of those that
 * tick, the observed variables. */
static fmi3Status observe(fmi3Instance inst)
{
    fmi3Clock active[MAX_CLOCKS];
    fmi3Status worst = fmi3OK, st;
    if (n_clocks) {
        if ((st = fmi3GetClock(inst, clock_vr, n_clocks, active)) > worst) worst = st;
        for (size_t c = 0; c < n_clocks && worst <= fmi3Warning; c++)
            if (active[c] && (st = read_group(inst, &clocked[c])) > worst) worst = st;
    }
    if (worst <= fmi3Warning && (st = read_group(inst, &observed)) > worst) worst = st;
    return worst;
}

static void read_vrs(Group *g, char **words, int n)
{
    int t = type_of(words[1]);
    g->values[t] = (size_t)strtoul(words[2], NULL, 10);
    g->n[t] = 0;
    for (int k = 3; k < n && g->n[t] < MAX_CLOCKED; k++) g->vr[t][g->n[t]++] = (fmi3ValueReference)strtoul(words[k], NULL, 10);
}

/* One scenario, as FmuRunner.run: steps taken, and where an error stopped it (-1: none). */
static void run(fmi3Instance inst, bool fresh)
{
    int steps = 0, err_instant = -1, err_k = -1, instant = 0, k = 0;
    double h = half ? interval / 2 : interval;
    fmi3Status status = fmi3OK;
    if (!fresh && fmi3Reset(inst) > fmi3Warning) status = fmi3Error;
    if (status <= fmi3Warning) status = fmi3EnterInitializationMode(inst, fmi3False, 0.0, 0.0, fmi3False, 0.0);
    if (status <= fmi3Warning) status = fmi3ExitInitializationMode(inst);
    for (instant = 0; instant < n_instants && status <= fmi3Warning; instant++) {
        const Instant *it = &instants[instant];
        k = 0;
        if (instant > 0) {
            fmi3Boolean event, terminate, early;
            fmi3Float64 last;
            status = fmi3EnterStepMode(inst);
            if (status <= fmi3Warning) status = fmi3DoStep(inst, (instant - 1) * h, h, fmi3True, &event, &terminate, &early, &last);
            if (status <= fmi3Warning) status = fmi3EnterEventMode(inst);
            if (status > fmi3Warning) break;
        }
        if (it->periodic) {
            fmi3Clock on = fmi3ClockActive;
            status = fmi3SetClock(inst, &periodic_vr, 1, &on);
        }
        for (int a = 0; a < it->n_actions && status <= fmi3Warning; a++)
            if (it->actions[a].at < 0) apply(inst, &it->actions[a], &status);
        while (status <= fmi3Warning) {
            fmi3Boolean need, terminate, nominals, values, defined;
            fmi3Float64 next;
            status = observe(inst);
            for (int a = 0; a < it->n_actions && status <= fmi3Warning; a++)
                if (it->actions[a].at == k) apply(inst, &it->actions[a], &status);
            if (status <= fmi3Warning) status = fmi3UpdateDiscreteStates(inst, &need, &terminate, &nominals, &values, &defined, &next);
            if (status > fmi3Warning) break;
            steps++;
            if (!need) break;
            if (++k > MAX_STEPS) { printf("runaway\n"); return; }
        }
        if (status > fmi3Warning) break;
    }
    if (status > fmi3Warning) { err_instant = instant; err_k = k; }
    printf("run %d %d %d\n", steps, err_instant, err_k);
}

static int read_action(char **words, int n, Instant *it)
{
    Action *a = &it->actions[it->n_actions++];
    a->at = atoi(words[1]);
    if (strcmp(words[0], "tick") == 0) {
        a->type = -1;
        a->vr = (fmi3ValueReference)strtoul(words[2], NULL, 10);
        return 0;
    }
    a->type = type_of(words[2]);
    a->vr = (fmi3ValueReference)strtoul(words[3], NULL, 10);
    a->n = (size_t)atoi(words[4]);
    if (a->n > 64 || (int)a->n != n - 5) return 1;
    for (size_t k = 0; k < a->n; k++) {
        const char *w = words[5 + k];
        if (a->type == T_F64) a->f[k] = strtod(w, NULL);
        else if (a->type == T_I64) a->i[k] = strtoll(w, NULL, 10);
        else if (a->type == T_U64) a->u[k] = strtoull(w, NULL, 10);
        else if (a->type == T_BOOL) a->b[k] = atoi(w) != 0;
        else a->s[k] = text_of(w);
    }
    return 0;
}

static int split(char *line, char **words)
{
    int n = 0;
    for (char *w = strtok(line, " \t\r\n"); w && n < MAX_WORDS; w = strtok(NULL, " \t\r\n")) words[n++] = w;
    return n;
}

int main(int argc, char **argv)
{
    static char line[1 << 16];
    static char *words[MAX_WORDS];
    fmi3Instance inst = NULL;
    bool fresh = true;
    FILE *in = argc > 1 ? fopen(argv[1], "r") : stdin;
    if (!in) return 2;
    while (fgets(line, sizeof line, in)) {
        int n = split(line, words);
        if (n == 0) continue;
        if (strcmp(words[0], "token") == 0 && n == 2) {
            snprintf(token, sizeof token, "%s", words[1]);
        } else if (strcmp(words[0], "get") == 0 && n >= 3) {
            read_vrs(&observed, words, n);
        } else if (strcmp(words[0], "clock") == 0 && n == 2 && n_clocks < MAX_CLOCKS) {
            clock_vr[n_clocks++] = (fmi3ValueReference)strtoul(words[1], NULL, 10);
        } else if (strcmp(words[0], "clocked") == 0 && n >= 3 && n_clocks > 0) {
            read_vrs(&clocked[n_clocks - 1], words, n);
        } else if (strcmp(words[0], "periodic") == 0 && n == 4) {
            periodic_vr = (fmi3ValueReference)strtoul(words[1], NULL, 10);
            interval = strtod(words[2], NULL);
            half = atoi(words[3]) != 0;
        } else if (strcmp(words[0], "scenario") == 0) {
            free_actions();
            if (!inst) inst = fmi3InstantiateCoSimulation("replay", token, NULL, fmi3False, fmi3False, fmi3True, fmi3False,
                                                          NULL, 0, NULL, logger, NULL);
            if (!inst) { printf("instantiate failed\n"); return 1; }
        } else if (strcmp(words[0], "instant") == 0 && n == 2 && n_instants < MAX_INSTANTS) {
            instants[n_instants].periodic = atoi(words[1]) != 0;
            instants[n_instants++].n_actions = 0;
        } else if ((strcmp(words[0], "tick") == 0 || strcmp(words[0], "set") == 0) && n_instants > 0
                   && instants[n_instants - 1].n_actions < MAX_ACTIONS) {
            if (read_action(words, n, &instants[n_instants - 1])) { fprintf(stderr, "replay: bad line\n"); return 2; }
        } else if (strcmp(words[0], "end") == 0 && inst) {
            run(inst, fresh);
            fresh = false;
        } else {
            fprintf(stderr, "replay: cannot read the line starting with '%s'\n", words[0]);
            return 2;
        }
    }
    free_actions();
    if (inst) fmi3FreeInstance(inst);
    if (in != stdin) fclose(in);
    return 0;
}
