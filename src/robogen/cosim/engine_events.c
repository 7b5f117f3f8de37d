/* Event Mode in the engine (engine_run.c describes the run): the instants of an event iteration,
 * and the events log. Compiled as one unit after engine_values.c and engine_run.c.
 *
 * An instant forwards clocks and values through a worklist in dependency order: an FMU's watched
 * output clocks read with one fmi3GetClock, each active one forwarded once along its connections
 * (the target clock set, the clocked values it carries read with one Get call per type and set
 * with one Set call per target and type); the connected values read and set as after a step.
 * An output read in the instant is not read again unless a Set it depends on came since (its
 * ModelStructure dependencies). */

static void new_instant(rg_engine *r, int u)
{
    int c;
    for (c = r->p->out_first[u]; c < r->p->out_first[u] + r->p->out_count[u]; c++) r->out_fresh[c] = false;
    for (c = 0; c < r->p->n_cells; c++)
        if (r->p->cell_instance[c] == u) r->cell_fresh[c] = false;
}

static double next_tick(const rg_engine *r, int p)
{
    return r->p->p_start[p] + r->p->p_shift[p] + (double)r->p_k[p] * r->p->p_interval[p];
}

/* Whether time-based input clock q of instance u is due by `limit`: a periodic one (q <
 * n_periodic) or an aperiodic one (q - n_periodic), and its clock. */
static bool due(const rg_engine *r, int u, int q, double limit, int *clock)
{
    const rg_plan *p = r->p;
    if (q < p->n_periodic) {
        *clock = p->p_clock[q];
        return p->p_instance[q] == u && next_tick(r, q) <= limit;
    }
    q -= p->n_periodic;
    *clock = p->a_clock[q];
    return p->a_instance[q] == u && r->a_next[q] <= limit;
}

/* Every time-based input clock due by `limit` (the first instant at t): one fmi3SetClock per FMU,
 * the clocks sorted; each moves past t (a periodic one to its first tick after t; an aperiodic
 * one to unknown, until its FMU announces the next). 0 or the failing status. */
static int activate_due_clocks(rg_engine *r, double t, double limit)
{
    const rg_plan *p = r->p;
    int u, q, n, i, st, clock, timed = p->n_periodic + p->n_aperiodic;
    for (u = 0; u < p->n_instances; u++) {
        for (n = 0, q = 0; q < timed; q++) {
            if (!due(r, u, q, limit, &clock)) continue;
            for (i = n++; i > 0 && r->clock_scratch[i - 1] > p->clock_vr[clock]; i--)
                r->clock_scratch[i] = r->clock_scratch[i - 1];
            r->clock_scratch[i] = p->clock_vr[clock];
        }
        if (n == 0) continue;
        *p->note_call = p->set_clock_note[u];
        st = p->set_clock[u](p->instance[u], r->clock_scratch, (size_t)n, p->on);
        if (st > 1) return st;
        new_instant(r, u); /* nothing read yet in this instant: nothing to forget but this */
        for (q = 0; q < timed; q++) {
            int64_t k;
            if (!due(r, u, q, limit, &clock)) continue;
            r->active[clock] = true;
            if (q >= p->n_periodic) {
                r->a_next[q - p->n_periodic] = INFINITY;
                continue;
            }
            k = grid_index(r, p->p_start[q] + p->p_shift[q], p->p_interval[q], t) + 1;
            r->p_k[q] = r->p_k[q] + 1 > k ? r->p_k[q] + 1 : k;
        }
    }
    return 0;
}

/* After the instants at t: the next tick of each countdown clock, and of each changing clock that
 * ticked, as its FMU announces it (fmi3GetIntervalDecimal). 0 or the failing status. */
static int read_intervals(rg_engine *r, double t)
{
    const rg_plan *p = r->p;
    int a, st, qualifier;
    for (a = 0; a < p->n_aperiodic; a++) {
        int u = p->a_instance[a];
        uint32_t vr = p->clock_vr[p->a_clock[a]];
        double interval = 0.0;
        if (!p->a_countdown[a] && !r->a_ticked[a]) continue;
        qualifier = INTERVAL_NOT_YET_KNOWN;
        *p->note_call = p->get_interval_note[u];
        if ((st = p->get_interval[u](p->instance[u], &vr, 1, &interval, &qualifier)) > 1) return st;
        if (qualifier == INTERVAL_CHANGED || (qualifier != INTERVAL_NOT_YET_KNOWN && isinf(r->a_next[a])))
            r->a_next[a] = t + interval;
    }
    return 0;
}

/* Instance u's watched output clocks, active noted: one fmi3GetClock, unless every one was read
 * in this instant and nothing it depends on was set since. 0 or the failing status. */
static int read_clocks(rg_engine *r, int u)
{
    int first = r->p->out_first[u], n = r->p->out_count[u], j, st;
    bool fresh = true;
    for (j = first; j < first + n; j++) fresh = fresh && r->out_fresh[j];
    if (!fresh) {
        *r->p->note_call = r->p->get_clock_note[u];
        st = r->p->get_clock[u](r->p->instance[u], r->p->out_vr + first, (size_t)n, r->out_on + first);
        if (st > 1) return st;
        for (j = first; j < first + n; j++) r->out_fresh[j] = true;
    }
    for (j = first; j < first + n; j++)
        if (r->out_on[j]) r->active[r->p->out_clock[j]] = true;
    return 0;
}

/* Whether an output with these dependencies may have changed by a Set of vrs. */
static bool depends(const rg_engine *r, int first, int count, const uint32_t *vrs, int n)
{
    int i, j;
    if (count < 0) return true;
    for (i = first; i < first + count; i++)
        for (j = 0; j < n; j++)
            if (r->p->dep_vr[i] == vrs[j]) return true;
    return false;
}

/* A Set (or SetClock) of vrs on instance w: what it read in this instant that depends on them is
 * read again. */
static void inputs_changed(rg_engine *r, int w, const uint32_t *vrs, int n)
{
    int j, c;
    for (j = r->p->out_first[w]; j < r->p->out_first[w] + r->p->out_count[w]; j++)
        if (r->out_fresh[j] && depends(r, r->p->out_dep_first[j], r->p->out_dep_count[j], vrs, n)) r->out_fresh[j] = false;
    for (c = 0; c < r->p->n_cells; c++)
        if (r->p->cell_instance[c] == w && r->cell_fresh[c] && depends(r, r->p->cell_dep_first[c], r->p->cell_dep_count[c], vrs, n))
            r->cell_fresh[c] = false;
}

static void wake(rg_engine *r, int w, int edge)
{
    r->woken[w] = true;
    r->woken_edge[w] = edge;
}

/* Value `at` of the batches (its source cell's) as slot i of a Set call of kind `kind`: its own,
 * or converted in one step (the connection's factor and offset, then the input's type: between
 * clock domains, between FMI 2.0 and 3.0); 0, or -7 where it does not fit input vr of w. */
static int carried(rg_engine *r, int at, int kind, int i, int w, uint32_t vr)
{
    int c = r->p->batch_cell[at], from = r->p->cell_kind[c];
    uint64_t raw = r->cell_raw[c];
    rg_value value;
    if (is_bytes(kind)) { /* the copy's bytes (a C string) and size */
        ((const char **)r->set_scratch)[i] = r->arena.data + raw + sizeof(size_t);
        memcpy(&r->get_sizes[i], r->arena.data + raw, sizeof(size_t));
    } else if (kind == K_F64 || kind == K_F32) {
        double d = converted(r->p->batch_scaled, r->p->batch_factor, r->p->batch_offset, at, real_of(from, &raw, 0));
        float f = (float)d;
        if (kind == K_F32 && isfinite(d) && fabs(d) > FLT_MAX) {
            value.d = d;
            out_of_range(r, w, vr, from, value);
            return -7;
        }
        if (kind == K_F32) memcpy((char *)r->set_scratch + 4 * (size_t)i, &f, 4);
        else memcpy((char *)r->set_scratch + 8 * (size_t)i, &d, 8);
    } else {
        uint64_t v = integer_of(from, &raw, 0);
        if (!fits(from, kind, v)) {
            value.u = v;
            out_of_range(r, w, vr, from, value);
            return -7;
        }
        put_integer(r->set_scratch, kind, i, v);
    }
    return 0;
}

/* Route q of an active clock: its target clock (unless active already, or none: an input that is
 * not clocked), then the values it carries (read from the route's source), one Set call per type. */
static int forward_route(rg_engine *r, int q)
{
    int w = r->p->route_target[q], u = r->p->route_source_instance[q], b, i, st;
    uint32_t vr;
    if (r->p->route_clock[q] >= 0 && !r->active[r->p->route_clock[q]]) {
        vr = r->p->clock_vr[r->p->route_clock[q]];
        *r->p->note_call = r->p->set_clock_note[w];
        if ((st = r->p->set_clock[w](r->p->instance[w], &vr, 1, r->p->on)) > 1) return st;
        r->active[r->p->route_clock[q]] = true;
        inputs_changed(r, w, &vr, 1);
    }
    if (r->p->route_source_count[q] > 0) {
        st = clocked_values(r, u, r->p->route_source + r->p->route_source_first[q], r->p->route_source_count[q]);
        if (st != 0) return st;
    }
    for (b = r->p->route_batch_first[q]; b < r->p->route_batch_first[q] + r->p->route_batch_count[q]; b++) {
        int n = r->p->batch_count[b], kind = r->p->batch_kind[b];
        const uint32_t *vrs = r->p->batch_vr + r->p->batch_first[b];
        for (i = 0; i < n; i++) {
            if ((st = carried(r, r->p->batch_first[b] + i, kind, i, w, vrs[i])) != 0) return st;
        }
        *r->p->note_call = r->p->batch_note[b];
        if (kind == K_BINARY)
            st = r->p->batch_set_binary[b](r->p->instance[w], vrs, (size_t)n, r->get_sizes,
                                        (const uint8_t *const *)r->set_scratch, (size_t)n);
        else
            st = r->p->batch_set[b](r->p->instance[w], vrs, (size_t)n, r->set_scratch, (size_t)n);
        if (st > 1) return st;
        inputs_changed(r, w, r->p->batch_vr + r->p->batch_first[b], n);
    }
    wake(r, w, r->p->route_edge[q]);
    return 0;
}

/* u's active output clocks, each forwarded once per instant along its routes (to instances in
 * Event Mode); then the routes between clock domains of u's active clocks, once per instant. */
static int forward_clocks(rg_engine *r, int u)
{
    int j, q, c, st;
    if ((st = read_clocks(r, u)) != 0) return st;
    for (j = r->p->out_first[u]; j < r->p->out_first[u] + r->p->out_count[u]; j++) {
        if (!r->out_on[j] || r->forwarded[j]) continue;
        r->forwarded[j] = true;
        for (q = r->p->route_first[j]; q < r->p->route_first[j] + r->p->route_count[j]; q++)
            if (r->p->event_mode[r->p->route_target[q]] && (st = forward_route(r, q)) != 0) return st;
    }
    for (c = r->p->clock_first[u]; c < r->p->clock_first[u] + r->p->clock_count[u]; c++) {
        if (!r->active[c] || r->clock_forwarded[c] || r->p->croute_count[c] == 0) continue;
        r->clock_forwarded[c] = true;
        for (q = r->p->croute_first[c]; q < r->p->croute_first[c] + r->p->croute_count[c]; q++)
            if ((st = forward_route(r, q)) != 0) return st;
    }
    return 0;
}

/* u's connected values: its reads, then each Set group whose inputs changed (*changed). */
static int forward_values(rg_engine *r, int u, bool *changed)
{
    int k, st, count;
    bool no_memory = false;
    for (k = r->p->op_first[u]; k < r->p->op_first[u] + r->p->op_count[u]; k++) {
        int op = r->p->op[k], g = -1 - op;
        if (op >= 0) {
            st = get_values(r, op, &no_memory);
            if (st != 0 || no_memory) return no_memory ? -1 : st;
            continue;
        }
        count = 0;
        if ((st = forward(r, g, &count)) != 0) return st;
        if (count == 0) continue;
        *changed = true;
        inputs_changed(r, r->p->set_target[g], r->set_vrs, count);
        wake(r, r->p->set_target[g], r->p->set_edge[g]);
    }
    return 0;
}

/* An instant's clocks and values, forwarded through a worklist in dependency order until nothing
 * new happens (without connections: each FMU's output clocks read). 0, the failing status, or -3
 * when the values do not settle (an algebraic loop: r->woke says where). */
static int propagate(rg_engine *r)
{
    int e, u, w, low = 0, st, n = r->p->n_instances;
    long budget = 50L * (long)(n + 1) * (long)(n + 1);
    bool changed = false;
    if (!r->p->connected) {
        for (e = 0; e < r->p->n_event; e++)
            if ((st = read_clocks(r, r->p->event_instance[e])) != 0) return st;
        return 0;
    }
    for (w = 0; w < r->p->out_first[n]; w++) r->forwarded[w] = false;
    for (w = 0; w < r->p->clock_first[n]; w++) r->clock_forwarded[w] = false;
    for (e = 0; e < r->p->n_edges; e++) r->woke[e] = 0;
    for (e = 0; e < r->p->n_event; e++) r->queued[r->p->event_instance[e]] = true;
    for (;;) {
        for (u = low; u < n && !r->queued[u]; u++) continue;
        if (u >= n) return 0;
        if (--budget < 0) return -3;
        r->queued[u] = false;
        low = u + 1;
        if ((st = forward_clocks(r, u)) != 0 || (st = forward_values(r, u, &changed)) != 0) return st;
        for (w = 0; w < n; w++) {
            if (!r->woken[w]) continue;
            r->woken[w] = false;
            r->woke[r->woken_edge[w]]++;
            if (!r->queued[w] && r->p->event_mode[w]) {
                r->queued[w] = true;
                if (w < low) low = w;
            }
        }
    }
}

/* After an instant's update: every connected value forwarded; *changed if an input changed. */
static int exchange(rg_engine *r, bool *changed)
{
    int u, w, st;
    for (u = 0; u < r->p->n_instances; u++)
        if ((st = forward_values(r, u, changed)) != 0) return st;
    for (w = 0; w < r->p->n_instances; w++) r->woken[w] = false;
    return 0;
}

/* fmi3UpdateDiscreteStates on every FMU in Event Mode; *needs if one asks for another instant. */
static int update_all(rg_engine *r, double t, bool *needs)
{
    int e, c, st;
    for (e = 0; e < r->p->n_event; e++) {
        int u = r->p->event_instance[e];
        bool b[5] = {false, false, false, false, false};
        double next = 0.0;
        *r->p->note_call = r->p->update_note[u];
        st = r->p->update[u](r->p->instance[u], b, b + 1, b + 2, b + 3, b + 4, &next);
        if (st > 1) return st;
        for (c = r->p->clock_first[u]; c < r->p->clock_first[u] + r->p->clock_count[u]; c++) r->active[c] = false;
        new_instant(r, u);
        r->has_next[u] = b[4];
        r->next_event[u] = next;
        r->needs[u] = b[0];
        if (b[0]) *needs = true;
        if (b[1]) terminated(r, u, BY_UPDATE, t);
    }
    return 0;
}

/* The earliest clock tick or nextEventTime after t. */
static void refresh_timing(rg_engine *r, double t)
{
    double limit = t + tol(r, t), earliest = INFINITY;
    int u, p, e;
    for (u = 0; u < r->p->n_instances; u++) { /* each instance's next tick, as the reference's next_tick */
        double tick = INFINITY;
        for (p = 0; p < r->p->n_periodic; p++)
            if (r->p->p_instance[p] == u && next_tick(r, p) < tick) tick = next_tick(r, p);
        for (p = 0; p < r->p->n_aperiodic; p++)
            if (r->p->a_instance[p] == u && r->a_next[p] < tick) tick = r->a_next[p];
        if (limit < tick && tick < earliest) earliest = tick;
    }
    for (e = 0; e < r->p->n_event; e++) {
        int u = r->p->event_instance[e];
        if (r->has_next[u] && limit < r->next_event[u] && r->next_event[u] < earliest) earliest = r->next_event[u];
    }
    r->next_time = earliest;
}

/* A number as JSON writes it (Python's json: repr, NaN, Infinity); false when memory runs out. */
static bool json_number(rg_bytes *b, int kind, const void *value)
{
    double d;
    if (kind != K_F64 && kind != K_F32) {
        if (kind != K_BOOL) return number_cell(b, kind, value, 0);
        if (!reserve(b, 5)) return false;
        if (integer_of(kind, value, 0)) put(b, "true", 4);
        else put(b, "false", 5);
        return true;
    }
    d = real_of(kind, value, 0);
    if (!reserve(b, 32)) return false;
    if (isnan(d)) put(b, "NaN", 3);
    else if (isinf(d)) put(b, d < 0 ? "-Infinity" : "Infinity", d < 0 ? 9 : 8);
    else b->used += rg_format_double(b->data + b->used, d);
    return true;
}

static bool put_text(rg_bytes *b, const char *text)
{
    size_t n = strlen(text);
    if (!reserve(b, n)) return false;
    put(b, text, n);
    return true;
}

/* A clocked value as the events log shows it: a number, a Boolean, a String (as Python's json
 * writes it: the plan's json_string), a Binary as the string 0x and its bytes in hexadecimal. */
static bool json_value(rg_engine *r, rg_bytes *b, int kind, uint64_t raw)
{
    const char *data, *text;
    size_t size, length;
    if (!is_bytes(kind)) return json_number(b, kind, &raw);
    memcpy(&size, r->arena.data + raw, sizeof size);
    data = r->arena.data + raw + sizeof size;
    if (kind == K_BINARY) {
        if (!reserve(b, 2)) return false;
        put(b, "\"", 1);
        if (!bytes_cell(b, K_BINARY, &r->arena, raw) || !reserve(b, 1)) return false;
        put(b, "\"", 1);
        return true;
    }
    if (r->p->json_string(data, size, &text, &length) != 0 || !reserve(b, length)) return false;
    put(b, text, length);
    return true;
}

/* One event of clock c (of instance u) at (t, k): its line of the events log, the clocked
 * variables it shows read as the Python loop reads them. 0, the failing status, or -1. */
static int log_event(rg_engine *r, int u, int c, double t, int k)
{
    rg_bytes *b = &r->events;
    int i, first = r->p->event_first[c], st;
    if ((st = clocked_values(r, u, r->p->event_cell + first, r->p->event_count[c])) != 0) return st;
    if (!reserve(b, 64)) return -1;
    put(b, "{\"time\": ", 9);
    if (!json_number(b, K_F64, &t) || !reserve(b, 32)) return -1;
    put(b, ", \"index\": ", 11);
    b->used += format_integer(b->data + b->used, (uint64_t)k, false); /* k >= 0 */
    if (!put_text(b, r->p->event_head[c])) return -1;
    for (i = first; i < first + r->p->event_count[c]; i++) {
        int cell = r->p->event_cell[i];
        if ((i > first && !put_text(b, ", ")) || !put_text(b, r->p->event_key[i])) return -1;
        if (!json_value(r, b, r->p->cell_kind[cell], r->cell_raw[cell])) return -1;
    }
    return put_text(b, "}}\n") ? 0 : -1;
}

/* The events of the instant (t, k): every active clock's, by instance and value reference. */
static int log_events(rg_engine *r, double t, int k)
{
    int u, c, st;
    for (u = 0; u < r->p->n_instances; u++)
        for (c = r->p->clock_first[u]; c < r->p->clock_first[u] + r->p->clock_count[u]; c++)
            if (r->active[c] && (st = log_event(r, u, c, t, k)) != 0) return st;
    return 0;
}

/* The instants at t, up to the last row; then Step Mode. 0, a failing status, -1 (no memory), -2
 * (it did not settle: r->zeno_k instants) or -3 (values that do not settle in an instant). */
static int event_iteration(rg_engine *r, rg_rows *out, double t)
{
    int k = 0, st, e, c;
    bool needs, changed;
    r->event_iterations++;
    *r->p->note_time = t;
    for (c = 0; c < r->p->n_aperiodic; c++) r->a_ticked[c] = false;
    if ((st = activate_due_clocks(r, t, t + tol(r, t))) != 0) return st;
    do {
        needs = changed = false;
        r->instants++;
        if (r->p->store == STORE_TEXT) r->arena.used = 0; /* the previous instant's copies are written out */
        if ((st = propagate(r)) != 0 || (st = record(r, out, t, k, true)) != 0) return st;
        if (r->p->events_fd >= 0 && (st = log_events(r, t, k)) != 0) return st;
        for (c = 0; c < r->p->n_aperiodic; c++)
            if (r->active[r->p->a_clock[c]]) r->a_ticked[c] = true;
        if (k >= r->p->max_iterations - 1)
            for (c = 0; c < r->p->clock_first[r->p->n_instances]; c++) r->ticked[c] = r->active[c];
        if ((st = update_all(r, t, &needs)) != 0) return st;
        k++;
        if (!needs && r->p->connected && (st = exchange(r, &changed)) != 0) return st;
        if ((needs || changed) && k >= r->p->max_iterations) {
            r->zeno_k = k;
            return -2;
        }
    } while (needs || changed);
    if ((st = read_intervals(r, t)) != 0 || (st = record(r, out, t, k, true)) != 0) return st;
    for (e = 0; e < r->p->n_event; e++) {
        int u = r->p->event_instance[e];
        *r->p->note_call = r->p->enter_step_note[u];
        if ((st = r->p->enter_step[u](r->p->instance[u])) > 1) return st;
    }
    refresh_timing(r, t);
    r->event_ended = true;
    if (write_events(r) != 0) return -4;
    return r->p->fd >= 0 ? write_text(r) : 0;
}

static int event_mode(rg_engine *r, rg_rows *out, double t)
{
    int e, st;
    for (e = 0; e < r->p->n_event; e++) {
        int u = r->p->event_instance[e];
        *r->p->note_call = r->p->enter_event_note[u];
        if ((st = r->p->enter_event[u](r->p->instance[u])) > 1) return st;
        new_instant(r, u);
    }
    return event_iteration(r, out, t);
}

