/* The master's quiet stretches in C: consecutive plain communication steps with no event, no
 * early return and no value to forward between FMUs (robogen.cosim.stretch describes the
 * contract; robogen.cosim.stepper.CStretch drives this loop).
 *
 * Built once with the system C compiler (robogen.cosim.stepper) and called through cffi. Each
 * step does exactly what the Python stretch does, in the same order and with the same arithmetic:
 * t_next = start + n * h; fmi3DoStep of every FMU from t with step t_next - t; then, unless an FMU
 * asked for Event Mode, the fmi3Get<Type> calls of the recorded variables, whose values are
 * stored as one row of 8-byte slots (reals as doubles, signed integers as int64, unsigned ones as
 * uint64, Booleans as 0/1). Python turns the rows into result rows, so the results are
 * byte-identical to those of the Python loop. */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef int (*rg_do_step_fn)(void *, double, double, bool, bool *, bool *, bool *, double *);
typedef int (*rg_get_fn)(void *, const uint32_t *, size_t, void *, size_t);

enum { K_F64 = 0, K_F32, K_I64, K_U64, K_I32, K_U32, K_I16, K_U16, K_I8, K_U8, K_BOOL };
enum { WHY_LIMIT = 0, WHY_EVENT = 1, WHY_TERMINATE = 2, WHY_STEP_FAILED = 3, WHY_GET_FAILED = 4 };

typedef struct {
    int n_instances;
    rg_do_step_fn *do_step;  /* per FMU */
    void **instance;
    const bool *event_mode;  /* an event of an FMU without Event Mode does not stop the loop */
    bool *flags;             /* 4 per FMU: eventHandlingNeeded, terminateSimulation, earlyReturn */
    double *last_time;       /* 1 per FMU: lastSuccessfulTime */
    int n_reads;
    rg_get_fn *get;          /* per read */
    void **read_instance;
    const uint32_t **vrs;
    const size_t *count;
    const int *kind;
    void **buffer;           /* where each fmi3Get writes (the master's own buffers) */
    int width;               /* slots per row: the sum of count */
} rg_stretch;

static uint64_t slot(const void *buffer, int kind, size_t i)
{
    uint64_t out = 0;
    double d;
    switch (kind) {
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
    default: out = ((const bool *)buffer)[i] ? 1u : 0u; break;
    }
    return out;
}

/* Steps from (*n, *t) until the grid point reaches `limit`, an FMU asks for Event Mode or to
 * terminate, a call fails, or `max_rows` rows are stored. Returns the number of steps taken;
 * rows stored = steps, or steps - 1 when the last step ended in an event or a failed read.
 * *why says why it stopped; *who is the FMU (or read) concerned, *status the failing status. */
#if defined(__GNUC__)
#define RG_EXPORT __attribute__((visibility("default")))
#else
#define RG_EXPORT
#endif

RG_EXPORT long rg_run_stretch(const rg_stretch *s, double start, double h, long *n, double *t, double limit,
                              long max_rows, double *times, uint64_t *slots, int *why, int *who, int *status);

RG_EXPORT long rg_run_stretch(const rg_stretch *s, double start, double h, long *n, double *t, double limit,
                              long max_rows, double *times, uint64_t *slots, int *why, int *who, int *status)
{
    long steps = 0, rows = 0;
    *why = WHY_LIMIT;
    *who = -1;
    *status = 0;
    while (rows < max_rows) {
        long k = *n + 1;
        double t_next = start + (double)k * h;
        bool event = false, terminate = false;
        int u, r;
        if (t_next >= limit || t_next <= *t) break;
        for (u = 0; u < s->n_instances; u++) {
            bool *f = s->flags + 4 * u;
            int st = s->do_step[u](s->instance[u], *t, t_next - *t, true, f, f + 1, f + 2, s->last_time + u);
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
        {
            uint64_t *row = slots + (size_t)rows * (size_t)s->width;
            int col = 0;
            for (r = 0; r < s->n_reads; r++) {
                size_t i;
                int st = s->get[r](s->read_instance[r], s->vrs[r], s->count[r], s->buffer[r], s->count[r]);
                if (st > 1) {
                    *why = WHY_GET_FAILED;
                    *who = r;
                    *status = st;
                    return steps;
                }
                for (i = 0; i < s->count[r]; i++) row[col++] = slot(s->buffer[r], s->kind[r], i);
            }
            times[rows++] = t_next;
        }
        if (terminate) {
            *why = WHY_TERMINATE;
            return steps;
        }
    }
    return steps;
}
