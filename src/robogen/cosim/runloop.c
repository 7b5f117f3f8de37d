/* The master's whole run in C: quiet stretches, general steps and event iterations
 * (robogen.cosim.runloop describes when it runs and drives it; robogen.cosim.master describes
 * the algorithm). Compiled as one unit after stepper.c, whose stretch (the FMUs' steps, the
 * exchange of connected values, the reads and the CSV cells) it uses.
 *
 * It does what the master's Python loop does, call for call where a call can change what an FMU
 * does next, with the same arithmetic on times: the start's event iteration (or row), then up to
 * the stop time: a quiet stretch up to the next time event (where no FMU can return early), one
 * general step to the next point (the early returner first: the others go no further than where
 * it stopped), and there either the exchange and a plain row, or Event Mode: every FMU in Event
 * Mode enters it, the due periodic input clocks are set (one fmi3SetClock per FMU), and each
 * super-dense instant forwards clocks and values through a worklist in dependency order (an FMU's
 * watched output clocks read with one fmi3GetClock, each active one forwarded once along its
 * connections: the target clock set, the clocked values it carries read with one Get call per
 * type and set with one Set call per target and type; the connected values read and set as in
 * the stretch; an output read in the instant is not read again unless a Set it depends on came
 * since), records its row (the recorded clocked values whose clock is active), and closes with
 * fmi3UpdateDiscreteStates, then forwards the connected values; another instant follows while an
 * FMU asks for one or an input changed. The last row after the instants, fmi3EnterStepMode, the
 * next time event.
 *
 * It returns to Python when a chunk of rows is stored (or its wall-clock deadline passed), when
 * the run ends, when a call fails (the master's call notes say which), when memory runs out, and
 * for an event iteration or an instant that does not settle (Python reports it). Systems it does
 * not cover (robogen.cosim.runloop says which) run in the master's Python loop. */

#include "runloop.h"

enum { RUN_PAUSE = 0, RUN_DONE, RUN_FAILED, RUN_ZENO, RUN_NO_MEMORY, RUN_LOOP, RUN_WRITE };
enum { COL_VALUE = 0, COL_CLOCK, COL_CLOCKED };
enum { STAGE_ADVANCE = 0, STAGE_STRETCH, STAGE_STEP };
enum { BY_DO_STEP = 0, BY_UPDATE };


RG_EXPORT int rg_run_system(rg_run *r, long max_rows, double deadline, rg_rows *out, int *status);
RG_EXPORT void rg_run_release(rg_run *r);
static int event_iteration(rg_run *r, rg_rows *out, double t); /* instants.c */
static int event_mode(rg_run *r, rg_rows *out, double t);

static double tol(double t)
{
    double a = fabs(t);
    return 1e-9 * (a > 1.0 ? a : 1.0);
}

static long grid_index(double elapsed, double period) { return (long)floor(elapsed / period + 1e-9); }

static void terminated(rg_run *r, int u, int by, double t)
{
    if (r->term_who >= 0) return;
    r->term_who = u;
    r->term_by = by;
    r->term_t = t;
}

static bool finished(const rg_run *r) { return r->t >= r->stop_limit || r->term_who >= 0; }

static void all_at(rg_run *r, double t)
{
    int u;
    for (u = 0; u < r->s->n_instances; u++) r->time[u] = t;
}

/* ---------------------------------------------------------------------------------------------
 * Rows */

static int value_width(int kind)
{
    switch (kind) {
    case K_F64: case K_I64: case K_U64: return 8;
    case K_F32: case K_I32: case K_U32: return 4;
    case K_I16: case K_U16: return 2;
    case K_BOOL: return (int)sizeof(bool);
    default: return 1;
    }
}

static uint64_t slot_of(int kind, const void *buffer, size_t i)
{
    uint64_t slot;
    double d;
    if (kind != K_F64 && kind != K_F32) return integer_of(kind, buffer, i);
    d = real_of(kind, buffer, i);
    memcpy(&slot, &d, sizeof slot);
    return slot;
}

/* The values of these cells of instance u: those not read in this instant (or inputs) with one
 * Get call per type, in the order the cells meet the types. 0 or the failing status. */
static int clocked_values(rg_run *r, int u, const int *cells, int n_cells)
{
    int i, j, st;
    for (i = 0; i < n_cells; i++) r->cell_need[cells[i]] = !r->cell_fresh[cells[i]];
    for (i = 0; i < n_cells; i++) {
        int c = cells[i], n = 0, type = r->cell_type[c], width = value_width(r->cell_kind[c]);
        if (!r->cell_need[c]) continue;
        for (j = i; j < n_cells; j++) /* every cell of this type still needed: one call */
            if (r->cell_need[cells[j]] && r->cell_type[cells[j]] == type) {
                r->get_vrs[n] = r->cell_vr[cells[j]];
                r->get_cells[n++] = cells[j];
            }
        *r->s->note_call = r->cell_note[c];
        if (r->cell_kind[c] == K_BINARY)
            st = r->cell_get_binary[c](r->s->instance[u], r->get_vrs, (size_t)n, r->get_sizes,
                                       (const uint8_t **)r->get_buffer, (size_t)n);
        else
            st = r->cell_get[c](r->s->instance[u], r->get_vrs, (size_t)n, r->get_buffer, (size_t)n);
        if (st > 1) return st;
        for (j = 0; j < n; j++) {
            int d = r->get_cells[j];
            if (is_bytes(r->cell_kind[d])) { /* copied at once: a later call may free what it points to */
                const char *data = ((const char *const *)r->get_buffer)[j];
                size_t size = data == NULL ? 0 : r->cell_kind[d] == K_STRING ? strlen(data) : r->get_sizes[j];
                if ((r->cell_raw[d] = keep_bytes(&r->s->arena, data == NULL ? "" : data, size)) == UINT64_MAX) return -1;
            } else {
                memcpy(&r->cell_raw[d], (const char *)r->get_buffer + (size_t)width * (size_t)j, (size_t)width);
            }
            r->cell_need[d] = false;
            if (r->cell_output[d]) r->cell_fresh[d] = true;
        }
    }
    return 0;
}

/* The recorded clocked cells of group g whose clock is active, read (see clocked_values). */
static int recorded_values(rg_run *r, int g)
{
    int first = r->group_first[g], count = r->group_count[g], i, j, live = 0;
    int u = r->cell_instance[r->group_cell[first]];
    uint64_t active = 0;
    for (j = 0; j < r->clock_count[u]; j++)
        if (r->active[r->clock_first[u] + j]) active |= (uint64_t)1 << j;
    for (i = first; i < first + count; i++) {
        int c = r->group_cell[i];
        r->cell_live[c] = (r->cell_mask[c] & active) != 0;
        if (r->cell_live[c]) r->get_cells[live++] = c;
    }
    if (live == 0) return 0;
    memcpy(r->route_scratch, r->get_cells, (size_t)live * sizeof(int));
    return clocked_values(r, u, r->route_scratch, live);
}

static bool text_cell(rg_run *r, int c)
{
    rg_stretch *s = r->s;
    int ref = r->column_ref[c];
    if (r->column_kind[c] == COL_VALUE) return cell(s, s->column_read[c], (size_t)s->column_index[c]);
    if (r->column_kind[c] == COL_CLOCK) {
        if (!reserve(&s->text, 1)) return false;
        put(&s->text, ref >= 0 && r->active[ref] ? "1" : "0", 1);
        return true;
    }
    if (!r->cell_live[ref]) return true;
    if (is_bytes(r->cell_kind[ref])) return bytes_cell(&s->text, r->cell_kind[ref], &s->arena, r->cell_raw[ref]);
    return number_cell(&s->text, r->cell_kind[ref], &r->cell_raw[ref], 0);
}

static bool text_line(rg_run *r, double t, int k)
{
    rg_stretch *s = r->s;
    int c;
    if (!reserve(&s->text, 48)) return false;
    s->text.used += rg_format_double(s->text.data + s->text.used, t);
    s->text.used += (size_t)sprintf(s->text.data + s->text.used, ",%d", k);
    for (c = 0; c < r->n_columns; c++) {
        if (!reserve(&s->text, 1)) return false;
        put(&s->text, ",", 1);
        if (!text_cell(r, c)) return false;
    }
    if (!reserve(&s->text, 1)) return false;
    put(&s->text, "\n", 1);
    return true;
}

static void slot_line(rg_run *r, uint64_t *slots, uint8_t *present)
{
    rg_stretch *s = r->s;
    int c;
    for (c = 0; c < r->n_columns; c++) {
        int ref = r->column_ref[c], read = s->column_read[c];
        present[c] = 1;
        if (r->column_kind[c] == COL_VALUE) {
            size_t i = (size_t)s->column_index[c];
            slots[c] = is_bytes(s->kind[read]) ? s->copies[read][i] : slot_of(s->kind[read], s->buffer[read], i);
        } else if (r->column_kind[c] == COL_CLOCK) {
            slots[c] = ref >= 0 && r->active[ref];
        } else if ((present[c] = r->cell_live[ref]) != 0) {
            slots[c] = is_bytes(r->cell_kind[ref]) ? r->cell_raw[ref] : slot_of(r->cell_kind[ref], &r->cell_raw[ref], 0);
        }
    }
}

/* The row (t, k): the reads (after the exchange of a plain row), the clocked values, the row.
 * 0, the failing status, or -1 when memory runs out. */
static int record(rg_run *r, rg_rows *out, double t, int k, bool event)
{
    rg_stretch *s = r->s;
    int why, who, st, g;
    long row = out->rows;
    /* an instant's row: the connected instances were read while forwarding */
    st = event ? run_ops(s, r->n_exchange_ops, s->n_ops, &why, &who) : exchange_and_read(s, &why, &who);
    for (g = 0; st == 0 && g < r->n_groups; g++) st = recorded_values(r, g);
    if (st != 0) return st;
    if (s->mode == MODE_TEXT) {
        size_t start = s->text.used;
        if (!text_line(r, t, k)) {
            s->text.used = start;
            return -1;
        }
        r->text_rows++;
    } else if (s->mode == MODE_SLOTS) {
        slot_line(r, out->slots + (size_t)row * (size_t)r->n_columns, out->present + (size_t)row * (size_t)r->n_columns);
    }
    out->times[row] = t;
    out->index[row] = k;
    out->event[row] = event;
    out->rows = row + 1;
    return 0;
}

/* The CSV lines so far to the results file (its Python buffer was flushed before this call):
 * they are on disk as an event iteration ends, as the Python loop's flush puts them. 0, or -4
 * when the file cannot be written. */
static int write_all(int fd, rg_bytes *b)
{
    size_t done = 0;
    while (done < b->used) {
        ssize_t n = write(fd, b->data + done, b->used - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return -4;
        done += (size_t)n;
    }
    b->used = 0;
    return 0;
}

static int write_text(rg_run *r)
{
    if (write_all(r->fd, &r->s->text) != 0) return -4;
    r->written += r->text_rows;
    r->text_rows = 0;
    return 0;
}

/* The events logged so far to the events log (its Python buffer was flushed before this call). */
static int write_events(rg_run *r) { return r->events_fd >= 0 ? write_all(r->events_fd, &r->events) : 0; }

/* ---------------------------------------------------------------------------------------------
 * Step Mode */

/* The next grid point, clock tick or nextEventTime after t (the stop time within its tolerance). */
static double next_point(const rg_run *r, double t)
{
    long n = grid_index(t - r->start, r->step);
    double grid = r->start + (double)(n + 1) * r->step, point;
    if (grid <= t + tol(t)) grid = r->start + (double)(n + 2) * r->step;
    point = r->stop < grid ? r->stop : grid;
    if (r->next_time < point) point = r->next_time;
    return point >= r->stop_limit ? r->stop : point;
}

/* Every FMU towards `end`, the early returner first: the others go no further than where it
 * stopped. 0 or the failing status; *end the time all reached. */
static int step_with_early_return(rg_run *r, double *end, bool *event)
{
    rg_stretch *s = r->s;
    double reached = *end - tol(*end);
    int i, u, st;
    for (u = 0; u < s->n_instances; u++) s->flags[4 * u + 3] = false; /* the fourth flag: stepped */
    for (i = 0; i < s->n_instances; i++) {
        bool *f;
        u = r->step_order[i];
        f = s->flags + 4 * u;
        if (r->time[u] >= reached) continue;
        *s->note_call = s->step_note[u];
        st = s->do_step[u](s->instance[u], r->time[u], *end - r->time[u], true, f, f + 1, f + 2, s->last_time + u);
        if (st > 1) return st;
        f[3] = true;
        r->time[u] = f[2] ? s->last_time[u] : *end;
        if (r->time[u] < reached) {
            *end = r->time[u];
            reached = *end - tol(*end);
            r->early_returns++;
        }
    }
    for (u = 0; u < s->n_instances; u++) {
        bool *f = s->flags + 4 * u;
        if (!f[3]) continue;
        if (f[1]) terminated(r, u, BY_DO_STEP, r->time[u]);
        if (f[0] && s->event_mode[u]) *event = true;
    }
    return 0;
}

/* One general step from r->t to the next point; there Event Mode or the exchange and a row. */
static int general_step(rg_run *r, rg_rows *out)
{
    double t_next = next_point(r, r->t);
    bool event = false, terminate = false;
    int st, who = -1, u;
    *r->s->note_time = r->t;
    if (r->early) {
        st = step_with_early_return(r, &t_next, &event);
    } else {
        st = step_all(r->s, r->t, t_next, &event, &terminate, &who);
        if (st > 1) return st;
        for (u = 0; u < r->s->n_instances; u++) r->time[u] = t_next;
        if (terminate) terminated(r, who, BY_DO_STEP, t_next);
    }
    if (st != 0) return st;
    r->t = t_next;
    r->steps++;
    if (event || r->next_time <= r->t + tol(r->t)) return event_mode(r, out, r->t);
    *r->s->note_time = r->t;
    return record(r, out, r->t, 0, false);
}

/* One step of a quiet stretch (or its end: the general step is next). */
static int stretch_step(rg_run *r, rg_rows *out)
{
    long k = r->n + 1;
    double t_next = r->start + (double)k * r->step;
    bool event = false, terminate = false;
    int st, who = -1;
    if (t_next >= r->limit || t_next <= r->t) {
        r->stage = finished(r) ? STAGE_ADVANCE : STAGE_STEP;
        return 0;
    }
    st = step_all(r->s, r->t, t_next, &event, &terminate, &who);
    if (st != 0) return st;
    r->n = k;
    r->t = t_next;
    r->steps++;
    all_at(r, t_next);
    if (terminate) terminated(r, who, BY_DO_STEP, t_next);
    if (event) {
        r->stage = STAGE_ADVANCE;
        return event_mode(r, out, t_next);
    }
    *r->s->note_time = t_next;
    if ((st = record(r, out, t_next, 0, false)) != 0) return st;
    if (terminate) r->stage = STAGE_ADVANCE;
    return 0;
}

static int advance(rg_run *r, rg_rows *out)
{
    double horizon;
    switch (r->stage) {
    case STAGE_STRETCH:
        return stretch_step(r, out);
    case STAGE_STEP:
        r->stage = STAGE_ADVANCE;
        return general_step(r, out);
    default:
        if (r->early) {
            r->stage = STAGE_STEP;
            return 0;
        }
        horizon = r->next_time < r->stop ? r->next_time : r->stop;
        r->limit = horizon - tol(horizon);
        r->n = grid_index(r->t - r->start, r->step);
        r->stage = STAGE_STRETCH;
        return 0;
    }
}

/* Runs from where the last call stopped until `max_rows` rows are stored (or the monotonic clock
 * passed `deadline` after at least one, or an event iteration ended where its rows are to be
 * flushed at once), the run ends, a call fails (*status; the call notes say
 * which), memory runs out or an event iteration does not settle (RUN_ZENO). The rows go to
 * `out`, which has room for max_rows + max_iterations + 1. */
RG_EXPORT int rg_run_system(rg_run *r, long max_rows, double deadline, rg_rows *out, int *status)
{
    int st = 0;
    out->rows = r->text_rows = r->written = 0;
    r->s->arena.used = r->s->text.used = 0;
    *status = 0;
    if (r->phase == 0) {
        r->phase = 1;
        all_at(r, r->start);
        st = r->n_event > 0 ? event_iteration(r, out, r->start) : record(r, out, r->start, 0, false);
        r->event_ended = true; /* the start's rows are flushed as an event iteration's */
        if (st == 0 && r->n_event == 0 && r->fd >= 0) st = write_text(r);
    }
    while (st == 0 && !finished(r)) {
        if (r->event_ended && r->pause_at_events) return write_events(r) == 0 ? RUN_PAUSE : RUN_WRITE;
        if (out->rows >= max_rows || (out->rows > 0 && wall_clock() > deadline)) return RUN_PAUSE;
        st = advance(r, out);
    }
    *status = st;
    if (write_events(r) != 0 && st == 0) st = -4; /* what an event iteration that failed logged */
    return st == 0 ? RUN_DONE : st == -1 ? RUN_NO_MEMORY : st == -2 ? RUN_ZENO : st == -3 ? RUN_LOOP
         : st == -4 ? RUN_WRITE : RUN_FAILED;
}

RG_EXPORT void rg_run_release(rg_run *r)
{
    free(r->events.data);
    r->events.data = NULL;
    r->events.size = r->events.used = 0;
}
