/* The engine's run: quiet stretches, general steps, and the loop Python calls (rg_engine_run).
 * Compiled as one unit after engine_values.c (the values, the exchange, the CSV cells); Event Mode
 * is engine_events.c's. robogen.cosim.engine drives it; robogen.cosim.master describes the
 * algorithm and is its executable reference (the same plan, the same results byte for byte).
 *
 * It does what the reference does, call for call where a call can change what an FMU does next,
 * with the same arithmetic on times: the start's event iteration (or row), then up to the stop
 * time: a quiet stretch up to the next time event (where no FMU can return early: the steps to
 * start + n * step, each followed by the exchange and a plain row, stopping early at a step that
 * asks for Event Mode or to terminate), one general step to the next point (the early returner
 * first: the others go no further than where it stopped), and there either the exchange and a
 * plain row, or Event Mode (engine_events.c).
 *
 * It returns to Python (enum rg_end) when a chunk of rows is stored (or its wall-clock deadline
 * passed), when the run ends, when a call fails (the master's call notes say which), when memory
 * runs out, for an event iteration or an instant that does not settle (Python reports it), and
 * where Python does a part of the run: after every communication point of a paced run
 * (END_PACE: Python waits for the wall clock), and for every general step of a system where
 * several FMUs may return early (END_STEP: Python steps them, rolling back with FMU state, then
 * rg_engine_stepped). Each call resumes where the last one returned. */



enum { STAGE_ADVANCE = 0, STAGE_STRETCH, STAGE_STEP, STAGE_AFTER_STEP, STAGE_IN_PYTHON };
enum { ST_NO_MEMORY = -1, ST_ZENO = -2, ST_LOOP = -3, ST_WRITE = -4, ST_PACE = -5, ST_PYTHON_STEP = -6, ST_RANGE = -7 };

RG_EXPORT rg_engine *rg_engine_new(const rg_plan *p);
RG_EXPORT void rg_engine_free(rg_engine *e);
RG_EXPORT int rg_engine_run(rg_engine *r, long max_rows, double deadline, int *status);
RG_EXPORT void rg_engine_stepped(rg_engine *r, double t, bool event);
static int event_iteration(rg_engine *r, rg_rows *out, double t); /* engine_events.c */
static int event_mode(rg_engine *r, rg_rows *out, double t);

/* How close to t counts as t (robogen.fmu.fmi.tolerance, with the plan's tolerance and resolution). */
static double tol(const rg_engine *r, double t)
{
    double scale = fabs(t) > 1.0 ? fabs(t) : 1.0, close = r->p->time_tolerance * scale;
    double floor_ = (double)r->p->time_ulps * (nextafter(scale, INFINITY) - scale);
    if (r->p->resolution > 0.0 && close > r->p->resolution / 4) close = r->p->resolution / 4;
    return close > floor_ ? close : floor_;
}

/* k of the last grid point origin + k * period at or before t, one within the tolerance at t
 * counting as reached: from the integer index, checked against the points themselves
 * (robogen.cosim.clocks.grid_index). */
static long grid_index(const rg_engine *r, double origin, double period, double t)
{
    double close = tol(r, t);
    long k = (long)floor((t - origin) / period);
    while (origin + (double)(k + 1) * period <= t + close) k++;
    while (origin + (double)k * period > t + close) k--;
    return k;
}

static void terminated(rg_engine *r, int u, int by, double t)
{
    if (r->term_who >= 0) return;
    r->term_who = u;
    r->term_by = by;
    r->term_t = t;
}

static bool finished(const rg_engine *r) { return r->t >= r->p->stop_limit || r->term_who >= 0; }

static void all_at(rg_engine *r, double t)
{
    int u;
    for (u = 0; u < r->p->n_instances; u++) r->time[u] = t;
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
static int clocked_values(rg_engine *r, int u, const int *cells, int n_cells)
{
    int i, j, st;
    for (i = 0; i < n_cells; i++) r->cell_need[cells[i]] = !r->cell_fresh[cells[i]];
    for (i = 0; i < n_cells; i++) {
        int c = cells[i], n = 0, type = r->p->cell_type[c], width = value_width(r->p->cell_kind[c]);
        if (!r->cell_need[c]) continue;
        for (j = i; j < n_cells; j++) /* every cell of this type still needed: one call */
            if (r->cell_need[cells[j]] && r->p->cell_type[cells[j]] == type) {
                r->get_vrs[n] = r->p->cell_vr[cells[j]];
                r->get_cells[n++] = cells[j];
            }
        *r->p->note_call = r->p->cell_note[c];
        if (r->p->cell_kind[c] == K_BINARY)
            st = r->p->cell_get_binary[c](r->p->instance[u], r->get_vrs, (size_t)n, r->get_sizes,
                                       (const uint8_t **)r->get_buffer, (size_t)n);
        else
            st = r->p->cell_get[c](r->p->instance[u], r->get_vrs, (size_t)n, r->get_buffer, (size_t)n);
        if (st > 1) return st;
        for (j = 0; j < n; j++) {
            int d = r->get_cells[j];
            if (is_bytes(r->p->cell_kind[d])) { /* copied at once: a later call may free what it points to */
                const char *data = ((const char *const *)r->get_buffer)[j];
                size_t size = data == NULL ? 0 : r->p->cell_kind[d] == K_STRING ? strlen(data) : r->get_sizes[j];
                if ((r->cell_raw[d] = keep_bytes(&r->arena, data == NULL ? "" : data, size)) == UINT64_MAX) return -1;
            } else {
                memcpy(&r->cell_raw[d], (const char *)r->get_buffer + (size_t)width * (size_t)j, (size_t)width);
            }
            r->cell_need[d] = false;
            if (r->p->cell_output[d]) r->cell_fresh[d] = true;
        }
    }
    return 0;
}

/* The recorded clocked cells of group g whose clock is active, read (see clocked_values). */
static int recorded_values(rg_engine *r, int g)
{
    int first = r->p->group_first[g], count = r->p->group_count[g], i, j, live = 0;
    int u = r->p->cell_instance[r->p->group_cell[first]];
    for (i = first; i < first + count; i++) {
        int c = r->p->group_cell[i];
        r->cell_live[c] = false;
        for (j = r->p->cell_clock_first[c]; j < r->p->cell_clock_first[c] + r->p->cell_clock_count[c]; j++)
            if (r->active[r->p->cell_clock[j]]) r->cell_live[c] = true;
        if (r->cell_live[c]) r->get_cells[live++] = c;
    }
    if (live == 0) return 0;
    memcpy(r->route_scratch, r->get_cells, (size_t)live * sizeof(int));
    return clocked_values(r, u, r->route_scratch, live);
}

static bool text_cell(rg_engine *r, int c)
{
    rg_engine *s = r;
    int ref = r->p->column_ref[c];
    if (r->p->column_kind[c] == COL_VALUE) return cell(s, s->p->column_read[c], (size_t)s->p->column_index[c]);
    if (r->p->column_kind[c] == COL_CLOCK) {
        if (!reserve(&s->text, 1)) return false;
        put(&s->text, ref >= 0 && r->active[ref] ? "1" : "0", 1);
        return true;
    }
    if (!r->cell_live[ref]) return true;
    if (is_bytes(r->p->cell_kind[ref])) return bytes_cell(&s->text, r->p->cell_kind[ref], &s->arena, r->cell_raw[ref]);
    return number_cell(&s->text, r->p->cell_kind[ref], &r->cell_raw[ref], 0);
}

static bool text_line(rg_engine *r, double t, int k)
{
    rg_engine *s = r;
    int c;
    if (!reserve(&s->text, 48)) return false;
    s->text.used += rg_format_double(s->text.data + s->text.used, t);
    put(&s->text, ",", 1);
    s->text.used += format_integer(s->text.data + s->text.used, (uint64_t)k, false); /* k >= 0 */
    for (c = 0; c < r->p->n_columns; c++) {
        if (!reserve(&s->text, 1)) return false;
        put(&s->text, ",", 1);
        if (!text_cell(r, c)) return false;
    }
    if (!reserve(&s->text, 1)) return false;
    put(&s->text, "\n", 1);
    return true;
}

/* The row's values into their columns: column c's slot of this row at slots[c * stride]. */
static void slot_line(rg_engine *r, uint64_t *slots, uint8_t *present, size_t stride)
{
    rg_engine *s = r;
    int c;
    for (c = 0; c < r->p->n_columns; c++, slots += stride, present += stride) {
        int ref = r->p->column_ref[c], read = r->p->column_read[c];
        *present = 1;
        if (r->p->column_kind[c] == COL_VALUE) {
            size_t i = (size_t)r->p->column_index[c];
            *slots = is_bytes(r->p->kind[read]) ? s->copies[read][i] : slot_of(r->p->kind[read], r->p->buffer[read], i);
        } else if (r->p->column_kind[c] == COL_CLOCK) {
            *slots = ref >= 0 && r->active[ref];
        } else if ((*present = r->cell_live[ref]) != 0) {
            *slots = is_bytes(r->p->cell_kind[ref]) ? r->cell_raw[ref] : slot_of(r->p->cell_kind[ref], &r->cell_raw[ref], 0);
        } else {
            *slots = 0; /* an empty cell */
        }
    }
}

/* Room for twice as many rows, each column's slots moved to its place at the new capacity
 * (the last column first: a column moves to a higher place than any column before it held);
 * false when memory runs out. */
static bool grow_rows(rg_rows *out, int width)
{
    long capacity = out->capacity ? 2 * out->capacity : 4096;
    size_t n = (size_t)capacity, old = (size_t)out->capacity, cells = (size_t)capacity * (size_t)(width > 0 ? width : 1);
    size_t rows = (size_t)out->rows;
    int c;
    double *times = (double *)realloc(out->times, n * sizeof(double));
    int32_t *index = times ? (int32_t *)realloc(out->index, n * sizeof(int32_t)) : NULL;
    uint8_t *event = index ? (uint8_t *)realloc(out->event, n) : NULL;
    uint64_t *slots = event ? (uint64_t *)realloc(out->slots, cells * sizeof(uint64_t)) : NULL;
    uint8_t *present = slots ? (uint8_t *)realloc(out->present, cells) : NULL;
    if (times) out->times = times;
    if (index) out->index = index;
    if (event) out->event = event;
    if (slots) out->slots = slots;
    if (present == NULL) return false;
    out->present = present;
    for (c = width - 1; c > 0 && rows > 0; c--) {
        memmove(out->slots + (size_t)c * n, out->slots + (size_t)c * old, rows * sizeof(uint64_t));
        memmove(out->present + (size_t)c * n, out->present + (size_t)c * old, rows);
    }
    out->capacity = capacity;
    return true;
}

/* The row (t, k): the reads (after the exchange of a plain row), the clocked values, the row.
 * 0, the failing status, or -1 when memory runs out. */
static int record(rg_engine *r, rg_rows *out, double t, int k, bool event)
{
    int st, g;
    long row = out->rows;
    /* an instant's row: the connected instances were read while forwarding */
    st = event ? run_ops(r, r->p->n_exchange_ops, r->p->n_ops) : exchange_and_read(r);
    for (g = 0; st == 0 && g < r->p->n_groups; g++) st = recorded_values(r, g);
    if (st != 0) return st;
    if (row >= out->capacity && !grow_rows(out, r->p->n_columns)) return -1;
    if (r->p->store == STORE_TEXT) {
        size_t start = r->text.used;
        if (!text_line(r, t, k)) {
            r->text.used = start;
            return -1;
        }
        r->text_rows++;
    } else if (r->p->store == STORE_SLOTS) {
        slot_line(r, out->slots + row, out->present + row, (size_t)out->capacity);
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

static int write_text(rg_engine *r)
{
    if (write_all(r->p->fd, &r->text) != 0) return -4;
    r->written += r->text_rows;
    r->text_rows = 0;
    return 0;
}

/* The events logged so far to the events log (its Python buffer was flushed before this call). */
static int write_events(rg_engine *r) { return r->p->events_fd >= 0 ? write_all(r->p->events_fd, &r->events) : 0; }

/* ---------------------------------------------------------------------------------------------
 * Step Mode */

/* The next grid point, clock tick or nextEventTime after t (the stop time within its tolerance). */
static double next_point(const rg_engine *r, double t)
{
    long n = grid_index(r, r->p->start, r->p->step, t);
    double grid = r->p->start + (double)(n + 1) * r->p->step, point;
    if (grid <= t + tol(r, t)) grid = r->p->start + (double)(n + 2) * r->p->step;
    point = r->p->stop < grid ? r->p->stop : grid;
    if (r->next_time < point) point = r->next_time;
    return point >= r->p->stop_limit ? r->p->stop : point;
}

/* Every FMU towards `end`, the early returner first: the others go no further than where it
 * stopped. 0 or the failing status; *end the time all reached. */
static int step_with_early_return(rg_engine *r, double *end, bool *event)
{
    const rg_plan *p = r->p;
    double reached = *end - tol(r, *end);
    int i, u, st;
    for (u = 0; u < p->n_instances; u++) r->flags[4 * u + 3] = false; /* the fourth flag: stepped */
    for (i = 0; i < p->n_instances; i++) {
        bool *f;
        u = p->step_order[i];
        f = r->flags + 4 * u;
        if (r->time[u] >= reached) continue;
        *p->note_call = p->step_note[u];
        st = p->do_step[u](p->instance[u], r->time[u], *end - r->time[u], true, f, f + 1, f + 2, r->last_time + u);
        if (st > 1) return st;
        f[3] = true;
        r->time[u] = f[2] ? r->last_time[u] : *end;
        if (r->time[u] < reached) {
            *end = r->time[u];
            reached = *end - tol(r, *end);
            r->early_returns++;
        }
    }
    for (u = 0; u < p->n_instances; u++) {
        bool *f = r->flags + 4 * u;
        if (!f[3]) continue;
        if (f[1]) terminated(r, u, BY_DO_STEP, r->time[u]);
        if (f[0] && p->event_mode[u]) *event = true;
    }
    return 0;
}

/* After the step to r->t (of a stretch, or a general one): Event Mode, or the exchange and a row. */
static int after_step(rg_engine *r, rg_rows *out)
{
    int st;
    if (r->step_in_stretch) {
        r->stage = STAGE_STRETCH;
        if (r->step_event) {
            r->stage = STAGE_ADVANCE;
            return event_mode(r, out, r->t);
        }
        *r->p->note_time = r->t;
        if ((st = record(r, out, r->t, 0, false)) != 0) return st;
        if (r->term_who >= 0) r->stage = STAGE_ADVANCE;
        return 0;
    }
    r->stage = STAGE_ADVANCE;
    if (r->step_event || r->next_time <= r->t + tol(r, r->t)) return event_mode(r, out, r->t);
    *r->p->note_time = r->t;
    return record(r, out, r->t, 0, false);
}

/* The step to r->t is done (event: an FMU asked for Event Mode): on to after_step, unless Python
 * paces the run first. */
static int stepped(rg_engine *r, rg_rows *out, bool event, bool in_stretch)
{
    r->step_event = event;
    r->step_in_stretch = in_stretch;
    r->steps++;
    if (r->p->paced) {
        r->stage = STAGE_AFTER_STEP;
        return ST_PACE;
    }
    return after_step(r, out);
}

/* One general step from r->t to the next point (Python's where FMUs roll back). */
static int general_step(rg_engine *r, rg_rows *out)
{
    double t_next = next_point(r, r->t);
    bool event = false, terminate = false;
    int st, who = -1;
    *r->p->note_time = r->t;
    if (r->p->rollback) {
        r->step_to = t_next;
        r->stage = STAGE_IN_PYTHON;
        return ST_PYTHON_STEP;
    }
    if (r->p->early) {
        if ((st = step_with_early_return(r, &t_next, &event)) != 0) return st;
    } else {
        if ((st = step_all(r, r->t, t_next, &event, &terminate, &who)) != 0) return st;
        all_at(r, t_next);
        if (terminate) terminated(r, who, BY_DO_STEP, t_next);
    }
    r->t = t_next;
    return stepped(r, out, event, false);
}

/* One step of a quiet stretch (or its end: the general step is next). */
static int stretch_step(rg_engine *r, rg_rows *out)
{
    long k = r->n + 1;
    double t_next = r->p->start + (double)k * r->p->step;
    bool event = false, terminate = false;
    int st, who = -1;
    if (t_next >= r->limit || t_next <= r->t) {
        r->stage = finished(r) ? STAGE_ADVANCE : STAGE_STEP;
        return 0;
    }
    if ((st = step_all(r, r->t, t_next, &event, &terminate, &who)) != 0) return st;
    r->n = k;
    r->t = t_next;
    all_at(r, t_next);
    if (terminate) terminated(r, who, BY_DO_STEP, t_next);
    return stepped(r, out, event, true);
}

static int advance(rg_engine *r, rg_rows *out)
{
    double horizon;
    switch (r->stage) {
    case STAGE_STRETCH:
        return stretch_step(r, out);
    case STAGE_STEP:
        r->stage = STAGE_ADVANCE;
        return general_step(r, out);
    case STAGE_AFTER_STEP:
        return after_step(r, out);
    case STAGE_IN_PYTHON:
        return ST_PYTHON_STEP; /* rg_engine_stepped was not called */
    default:
        if (r->p->early) {
            r->stage = STAGE_STEP;
            return 0;
        }
        horizon = r->next_time < r->p->stop ? r->next_time : r->p->stop;
        r->limit = horizon - tol(r, horizon);
        r->n = grid_index(r, r->p->start, r->p->step, r->t);
        r->stage = STAGE_STRETCH;
        return 0;
    }
}

/* Python stepped every FMU to t (END_STEP; it set r->time and the termination): on with the point. */
RG_EXPORT void rg_engine_stepped(rg_engine *r, double t, bool event)
{
    r->t = t;
    r->step_event = event;
    r->step_in_stretch = false;
    r->steps++;
    r->stage = STAGE_AFTER_STEP;
}

/* Runs from where the last call stopped until `max_rows` rows are stored (or the monotonic clock
 * passed `deadline` after at least one, or an event iteration ended where its rows are to be
 * flushed at once), the run ends, a call fails (*status; the call notes say which), memory runs
 * out, an event iteration does not settle, or Python's part is due (enum rg_end). The rows are in
 * r->rows (and the CSV lines in r->text, STORE_TEXT). */
RG_EXPORT int rg_engine_run(rg_engine *r, long max_rows, double deadline, int *status)
{
    rg_rows *out = &r->rows;
    int st = 0;
    out->rows = r->text_rows = r->written = 0;
    r->arena.used = r->text.used = 0;
    *status = 0;
    if (r->phase == 0) {
        r->phase = 1;
        r->t = r->p->start;
        all_at(r, r->p->start);
        st = r->p->n_event > 0 ? event_iteration(r, out, r->p->start) : record(r, out, r->p->start, 0, false);
        r->event_ended = true; /* the start's rows are flushed as an event iteration's */
        if (st == 0 && r->p->n_event == 0 && r->p->fd >= 0) st = write_text(r);
    }
    while (st == 0 && (r->stage == STAGE_AFTER_STEP || !finished(r))) {
        if (r->event_ended && r->p->pause_at_events) return write_events(r) == 0 ? END_PAUSE : END_WRITE;
        if (out->rows >= max_rows || (out->rows > 0 && wall_clock() > deadline)) return END_PAUSE;
        st = advance(r, out);
    }
    if (st == ST_PACE || st == ST_PYTHON_STEP) return st == ST_PACE ? END_PACE : END_STEP;
    *status = st;
    if (write_events(r) != 0 && st == 0) st = ST_WRITE; /* what an event iteration that failed logged */
    return st == 0 ? END_DONE : st == ST_NO_MEMORY ? END_NO_MEMORY : st == ST_ZENO ? END_ZENO : st == ST_LOOP ? END_LOOP
         : st == ST_WRITE ? END_WRITE : st == ST_RANGE ? END_RANGE : END_FAILED;
}

/* ---------------------------------------------------------------------------------------------
 * The engine's memory */

static void *zeroed(size_t count, size_t size, bool *ok)
{
    void *block = calloc(count > 0 ? count : 1, size);
    if (block == NULL) *ok = false;
    return block;
}

/* The state of a run of plan p (zeroed; the clocks' schedules and the instances' times are
 * Python's to fill in before the first rg_engine_run), or NULL when memory runs out. */
RG_EXPORT rg_engine *rg_engine_new(const rg_plan *p)
{
    size_t n = (size_t)p->n_instances, clocks = (size_t)p->clock_first[p->n_instances];
    size_t outs = (size_t)p->out_first[p->n_instances], cells = (size_t)p->n_cells, widest = 1, k;
    bool ok = true;
    rg_engine *r = (rg_engine *)zeroed(1, sizeof(rg_engine), &ok);
    if (r == NULL) return NULL;
    r->p = p;
    r->n_links = p->n_links;
    r->n_reads = p->n_reads;
    r->term_who = -1;
    r->range_link = -1;
    r->next_time = INFINITY;
    for (k = 0; k < (size_t)p->n_sets; k++)
        if ((size_t)p->set_count[k] > widest) widest = (size_t)p->set_count[k];
    r->time = (double *)zeroed(n, sizeof(double), &ok);
    r->has_next = (bool *)zeroed(n, sizeof(bool), &ok);
    r->next_event = (double *)zeroed(n, sizeof(double), &ok);
    r->needs = (bool *)zeroed(n, sizeof(bool), &ok);
    r->p_k = (int64_t *)zeroed((size_t)p->n_periodic, sizeof(int64_t), &ok);
    r->a_next = (double *)zeroed((size_t)p->n_aperiodic, sizeof(double), &ok);
    r->a_ticked = (bool *)zeroed((size_t)p->n_aperiodic, sizeof(bool), &ok);
    r->ticked = (bool *)zeroed(clocks, sizeof(bool), &ok);
    r->woke = (long *)zeroed((size_t)p->n_edges, sizeof(long), &ok);
    r->last = (rg_value *)zeroed((size_t)p->n_links, sizeof(rg_value), &ok);
    r->last_valid = (bool *)zeroed((size_t)p->n_links, sizeof(bool), &ok);
    r->last_bytes = (char **)zeroed((size_t)p->n_links, sizeof(char *), &ok);
    r->last_size = (size_t *)zeroed((size_t)p->n_links, sizeof(size_t), &ok);
    r->flags = (bool *)zeroed(4 * n, sizeof(bool), &ok);
    r->last_time = (double *)zeroed(n, sizeof(double), &ok);
    r->copies = (uint64_t **)zeroed((size_t)p->n_reads, sizeof(uint64_t *), &ok);
    for (k = 0; ok && k < (size_t)p->n_reads; k++)
        if (is_bytes(p->kind[k])) r->copies[k] = (uint64_t *)zeroed(p->count[k], sizeof(uint64_t), &ok);
    r->set_vrs = (uint32_t *)zeroed(widest, sizeof(uint32_t), &ok);
    r->set_values = (rg_value *)zeroed(widest, sizeof(rg_value), &ok);
    r->set_pointers = (const uint8_t **)zeroed(widest, sizeof(uint8_t *), &ok);
    r->set_sizes = (size_t *)zeroed(widest, sizeof(size_t), &ok);
    r->active = (bool *)zeroed(clocks, sizeof(bool), &ok);
    r->out_on = (bool *)zeroed(outs, sizeof(bool), &ok);
    r->out_fresh = (bool *)zeroed(outs, sizeof(bool), &ok);
    r->forwarded = (bool *)zeroed(outs, sizeof(bool), &ok);
    r->clock_forwarded = (bool *)zeroed(clocks, sizeof(bool), &ok);
    r->clock_scratch = (uint32_t *)zeroed(clocks, sizeof(uint32_t), &ok);
    r->cell_raw = (uint64_t *)zeroed(cells, sizeof(uint64_t), &ok);
    r->cell_fresh = (bool *)zeroed(cells, sizeof(bool), &ok);
    r->cell_live = (bool *)zeroed(cells, sizeof(bool), &ok);
    r->cell_need = (bool *)zeroed(cells, sizeof(bool), &ok);
    r->get_vrs = (uint32_t *)zeroed(cells, sizeof(uint32_t), &ok);
    r->get_buffer = (uint64_t *)zeroed(cells, sizeof(uint64_t), &ok);
    r->get_sizes = (size_t *)zeroed(cells, sizeof(size_t), &ok);
    r->get_cells = (int *)zeroed(cells, sizeof(int), &ok);
    r->route_scratch = (int *)zeroed(cells, sizeof(int), &ok);
    r->set_scratch = (uint64_t *)zeroed(cells, sizeof(uint64_t), &ok);
    r->queued = (bool *)zeroed(n, sizeof(bool), &ok);
    r->woken = (bool *)zeroed(n, sizeof(bool), &ok);
    r->woken_edge = (int *)zeroed(n, sizeof(int), &ok);
    if (ok && !grow_rows(&r->rows, p->n_columns)) ok = false;
    if (!ok) {
        rg_engine_free(r);
        return NULL;
    }
    return r;
}

RG_EXPORT void rg_engine_free(rg_engine *r)
{
    int k;
    if (r == NULL) return;
    for (k = 0; k < r->n_links; k++)
        if (r->last_bytes != NULL) free(r->last_bytes[k]);
    for (k = 0; k < r->n_reads; k++)
        if (r->copies != NULL) free(r->copies[k]);
    free(r->time); free(r->has_next); free(r->next_event); free(r->needs); free(r->p_k); free(r->a_next);
    free(r->a_ticked); free(r->ticked); free(r->woke); free(r->last); free(r->last_valid); free(r->last_bytes);
    free(r->last_size); free(r->flags); free(r->last_time); free(r->copies); free(r->set_vrs); free(r->set_values);
    free((void *)r->set_pointers); free(r->set_sizes); free(r->active); free(r->out_on); free(r->out_fresh);
    free(r->forwarded); free(r->clock_forwarded); free(r->clock_scratch); free(r->cell_raw); free(r->cell_fresh); free(r->cell_live);
    free(r->cell_need); free(r->get_vrs); free(r->get_buffer); free(r->get_sizes); free(r->get_cells);
    free(r->route_scratch); free(r->set_scratch); free(r->queued); free(r->woken); free(r->woken_edge);
    free(r->rows.times); free(r->rows.index); free(r->rows.event); free(r->rows.slots); free(r->rows.present);
    free(r->arena.data); free(r->text.data); free(r->events.data);
    free(r);
}
