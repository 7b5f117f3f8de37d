/* The master's quiet stretches in C: consecutive plain communication steps with no event, no
 * early return and no value to forward between FMUs (robogen.cosim.stretch describes the
 * contract; robogen.cosim.stepper.CStretch drives this loop).
 *
 * Built once with the system C compiler (robogen.cosim.stepper) and called through cffi. Each
 * step does exactly what the Python stretch does, in the same order and with the same arithmetic:
 * t_next = start + n * h; fmi3DoStep of every FMU from t with step t_next - t; then, unless an FMU
 * asked for Event Mode, the fmi3Get<Type> calls of the recorded variables, whose values are
 * stored as one row of 8-byte slots (reals as doubles, signed integers as int64, unsigned ones as
 * uint64, Booleans as 0/1, Strings and Binaries as the offset of a copy in the row arena: a
 * size_t length, then the bytes). Python turns the rows into result rows, so the results are
 * byte-identical to those of the Python loop.
 *
 * Before each FMI call the loop notes it (rg_stretch.note_call/note_time, the master's
 * robogen.cosim.fmi3.CallNotes), so a crash inside an FMU can be reported by instance, function
 * and time. A chunk also ends at a wall-clock deadline, so the rows reach the results file at
 * least that often however slow the FMUs are. */
#define _POSIX_C_SOURCE 199309L
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef int (*rg_do_step_fn)(void *, double, double, bool, bool *, bool *, bool *, double *);
typedef int (*rg_get_fn)(void *, const uint32_t *, size_t, void *, size_t);
typedef int (*rg_get_binary_fn)(void *, const uint32_t *, size_t, size_t *, const uint8_t **, size_t);

enum { K_F64 = 0, K_F32, K_I64, K_U64, K_I32, K_U32, K_I16, K_U16, K_I8, K_U8, K_BOOL, K_STRING, K_BINARY };
enum { WHY_LIMIT = 0, WHY_EVENT, WHY_TERMINATE, WHY_STEP_FAILED, WHY_GET_FAILED, WHY_NO_MEMORY, WHY_PAUSE };

typedef struct {
    int n_instances;
    rg_do_step_fn *do_step;  /* per FMU */
    void **instance;
    const bool *event_mode;  /* an event of an FMU without Event Mode does not stop the loop */
    bool *flags;             /* 4 per FMU: eventHandlingNeeded, terminateSimulation, earlyReturn */
    double *last_time;       /* 1 per FMU: lastSuccessfulTime */
    const int32_t *step_note; /* per FMU: the note of its fmi3DoStep */
    int n_reads;
    rg_get_fn *get;          /* per read: its fmi3Get<Type> (NULL for K_BINARY) */
    rg_get_binary_fn *get_binary; /* per read: fmi3GetBinary for K_BINARY, else NULL */
    void **read_instance;
    const uint32_t **vrs;
    const size_t *count;
    const int *kind;
    void **buffer;           /* where each fmi3Get writes (the master's own buffers) */
    size_t **sizes;          /* per read: fmi3GetBinary's valueSizes (K_BINARY only) */
    const int32_t *read_note; /* per read: the note of its call */
    int width;               /* slots per row: the sum of count */
    int32_t *note_call;      /* the master's call notes */
    double *note_time;
    char *arena;             /* the Strings and Binaries of the stored rows (malloc'd here) */
    size_t arena_size, arena_used;
} rg_stretch;

#if defined(__GNUC__)
#define RG_EXPORT __attribute__((visibility("default")))
#else
#define RG_EXPORT
#endif

RG_EXPORT long rg_run_stretch(rg_stretch *s, double start, double h, long *n, double *t, double limit, long max_rows,
                              double deadline, double *times, uint64_t *slots, int *why, int *who, int *status);
RG_EXPORT void rg_release(rg_stretch *s);

/* A copy of `size` bytes in the arena (a size_t length, then the bytes); its offset, or
 * UINT64_MAX when memory runs out. */
static uint64_t keep_bytes(rg_stretch *s, const void *data, size_t size)
{
    size_t need = s->arena_used + sizeof(size_t) + size;
    uint64_t offset = s->arena_used;
    if (need > s->arena_size) {
        size_t grown = s->arena_size ? 2 * s->arena_size : 65536;
        char *arena;
        while (grown < need) grown *= 2;
        arena = (char *)realloc(s->arena, grown);
        if (arena == NULL) return UINT64_MAX;
        s->arena = arena;
        s->arena_size = grown;
    }
    memcpy(s->arena + s->arena_used, &size, sizeof(size_t));
    if (size) memcpy(s->arena + s->arena_used + sizeof(size_t), data, size);
    s->arena_used = need;
    return offset;
}

static uint64_t slot(rg_stretch *s, int r, size_t i)
{
    const void *buffer = s->buffer[r];
    uint64_t out = 0;
    double d;
    const char *text;
    switch (s->kind[r]) {
    case K_F64: memcpy(&out, (const double *)buffer + i, sizeof out); break;
    case K_F32: d = (double)((const float *)buffer)[i]; memcpy(&out, &d, sizeof out); break;
    case K_I64: out = (uint64_t)((const int64_t *)buffer)[i]; break;
    case K_U64: out = ((const uint64_t *)buffer)[i]; break;
    case K_I32: out = (uint64_t)(int64_t)((const int32_t *)buffer)[i]; break;
    case K_U32: out = ((const uint32_t *)buffer)[i]; break;
    case K_I16: out = (uint64_t)(int64_t)((const int16_t *)buffer)[i]; break;
    case K_U16: out = ((const uint16_t *)buffer)[i]; break;
    case K_I8: out = (uint64_t)(int64_t)((const int8_t *)buffer)[i]; break;
    case K_U8: out = ((const uint8_t *)buffer)[i]; break;
    case K_STRING:
        text = ((const char *const *)buffer)[i];
        out = keep_bytes(s, text ? text : "", text ? strlen(text) : 0);
        break;
    case K_BINARY:
        out = keep_bytes(s, ((const uint8_t *const *)buffer)[i], ((const uint8_t *const *)buffer)[i] ? s->sizes[r][i] : 0);
        break;
    default: out = ((const bool *)buffer)[i] ? 1u : 0u; break;
    }
    return out;
}

static double wall_clock(void)
{
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (double)now.tv_sec + 1e-9 * (double)now.tv_nsec;
}

/* The recorded values after a step: one row of slots. 0, or the failing read's status (its
 * index in *who), or -1 when memory for the strings runs out. */
static int read_row(rg_stretch *s, uint64_t *row, int *who)
{
    int col = 0, r;
    for (r = 0; r < s->n_reads; r++) {
        size_t i;
        int st;
        *s->note_call = s->read_note[r];
        if (s->kind[r] == K_BINARY)
            st = s->get_binary[r](s->read_instance[r], s->vrs[r], s->count[r], s->sizes[r],
                                  (const uint8_t **)s->buffer[r], s->count[r]);
        else
            st = s->get[r](s->read_instance[r], s->vrs[r], s->count[r], s->buffer[r], s->count[r]);
        if (st > 1) {
            *who = r;
            return st;
        }
        for (i = 0; i < s->count[r]; i++) {
            row[col] = slot(s, r, i);
            if (row[col] == UINT64_MAX && (s->kind[r] == K_STRING || s->kind[r] == K_BINARY)) return -1;
            col++;
        }
    }
    return 0;
}

/* Steps from (*n, *t) until the grid point reaches `limit` (WHY_LIMIT), an FMU asks for Event Mode
 * or to terminate, a call fails, or it pauses (WHY_PAUSE) because `max_rows` rows are stored or
 * the monotonic clock passed `deadline` (seconds, CLOCK_MONOTONIC, as Python's time.monotonic)
 * after at least one row. Returns the number of steps taken;
 * rows stored = steps, or steps - 1 when the last step ended in an event or a failed read.
 * *why says why it stopped; *who is the FMU (or read) concerned, *status the failing status.
 * The arena is emptied first: the previous chunk's strings have been read. */
RG_EXPORT long rg_run_stretch(rg_stretch *s, double start, double h, long *n, double *t, double limit, long max_rows,
                              double deadline, double *times, uint64_t *slots, int *why, int *who, int *status)
{
    long steps = 0, rows = 0;
    *why = WHY_LIMIT;
    *who = -1;
    *status = 0;
    s->arena_used = 0;
    for (;;) {
        long k = *n + 1;
        double t_next = start + (double)k * h;
        bool event = false, terminate = false;
        int u, st;
        if (t_next >= limit || t_next <= *t) return steps;
        if (rows >= max_rows || (rows > 0 && wall_clock() > deadline)) {
            *why = WHY_PAUSE;
            return steps;
        }
        *s->note_time = *t;
        for (u = 0; u < s->n_instances; u++) {
            bool *f = s->flags + 4 * u;
            *s->note_call = s->step_note[u];
            st = s->do_step[u](s->instance[u], *t, t_next - *t, true, f, f + 1, f + 2, s->last_time + u);
            if (st > 1) {
                *why = WHY_STEP_FAILED;
                *who = u;
                *status = st;
                return steps;
            }
            if (f[0] && s->event_mode[u]) event = true;
            if (f[1] && !terminate) {
                terminate = true;
                *who = u;
            }
        }
        *n = k;
        *t = t_next;
        steps++;
        if (event) {
            *why = WHY_EVENT;
            return steps;
        }
        *s->note_time = t_next;
        st = read_row(s, slots + (size_t)rows * (size_t)s->width, who);
        if (st != 0) {
            *why = st < 0 ? WHY_NO_MEMORY : WHY_GET_FAILED;
            *status = st;
            return steps;
        }
        times[rows++] = t_next;
        if (terminate) {
            *why = WHY_TERMINATE;
            return steps;
        }
    }
}

RG_EXPORT void rg_release(rg_stretch *s)
{
    free(s->arena);
    s->arena = NULL;
    s->arena_size = s->arena_used = 0;
}
