/* Event Mode in the master's whole run in C (runloop.c describes it): the instants of an event
 * iteration, and the events log. Compiled as one unit after stepper.c and runloop.c.
 *
 * An instant forwards clocks and values through a worklist in dependency order: an FMU's watched
 * output clocks read with one fmi3GetClock, each active one forwarded once along its connections
 * (the target clock set, the clocked values it carries read with one Get call per type and set
 * with one Set call per target and type); the connected values read and set as in the stretch.
 * An output read in the instant is not read again unless a Set it depends on came since (its
 * ModelStructure dependencies). */

static void new_instant(rg_run *r, int u)
{
    int c;
    for (c = r->out_first[u]; c < r->out_first[u] + r->out_count[u]; c++) r->out_fresh[c] = false;
    for (c = 0; c < r->n_cells; c++)
        if (r->cell_instance[c] == u) r->cell_fresh[c] = false;
}

static double next_tick(const rg_run *r, int p)
{
    return r->p_start[p] + r->p_shift[p] + (double)r->p_k[p] * r->p_interval[p];
}

/* Every periodic input clock due by `limit` (the first instant at t): one fmi3SetClock per FMU,
 * the clocks sorted; each moves past t. 0 or the failing status. */
static int activate_due_clocks(rg_run *r, double t, double limit)
{
    int u, p, n, i, st;
    for (u = 0; u < r->s->n_instances; u++) {
        for (n = 0, p = 0; p < r->n_periodic; p++) {
            if (r->p_instance[p] != u || next_tick(r, p) > limit) continue;
            for (i = n++; i > 0 && r->clock_scratch[i - 1] > r->clock_vr[r->p_clock[p]]; i--)
                r->clock_scratch[i] = r->clock_scratch[i - 1];
            r->clock_scratch[i] = r->clock_vr[r->p_clock[p]];
        }
        if (n == 0) continue;
        *r->s->note_call = r->set_clock_note[u];
        st = r->set_clock[u](r->s->instance[u], r->clock_scratch, (size_t)n, r->on);
        if (st > 1) return st;
        new_instant(r, u); /* nothing read yet in this instant: nothing to forget but this */
        for (p = 0; p < r->n_periodic; p++) {
            int64_t k;
            if (r->p_instance[p] != u || next_tick(r, p) > limit) continue;
            r->active[r->p_clock[p]] = true;
            k = grid_index(t - r->p_start[p] - r->p_shift[p], r->p_interval[p]) + 1;
            r->p_k[p] = r->p_k[p] + 1 > k ? r->p_k[p] + 1 : k;
        }
    }
    return 0;
}

/* Instance u's watched output clocks, active noted: one fmi3GetClock, unless every one was read
 * in this instant and nothing it depends on was set since. 0 or the failing status. */
static int read_clocks(rg_run *r, int u)
{
    int first = r->out_first[u], n = r->out_count[u], j, st;
    bool fresh = true;
    for (j = first; j < first + n; j++) fresh = fresh && r->out_fresh[j];
    if (!fresh) {
        *r->s->note_call = r->get_clock_note[u];
        st = r->get_clock[u](r->s->instance[u], r->out_vr + first, (size_t)n, r->out_on + first);
        if (st > 1) return st;
        for (j = first; j < first + n; j++) r->out_fresh[j] = true;
    }
    for (j = first; j < first + n; j++)
        if (r->out_on[j]) r->active[r->out_clock[j]] = true;
    return 0;
}

/* Whether an output with these dependencies may have changed by a Set of vrs. */
static bool depends(const rg_run *r, int first, int count, const uint32_t *vrs, int n)
{
    int i, j;
    if (count < 0) return true;
    for (i = first; i < first + count; i++)
        for (j = 0; j < n; j++)
            if (r->dep_vr[i] == vrs[j]) return true;
    return false;
}

/* A Set (or SetClock) of vrs on instance w: what it read in this instant that depends on them is
 * read again. */
static void inputs_changed(rg_run *r, int w, const uint32_t *vrs, int n)
{
    int j, c;
    for (j = r->out_first[w]; j < r->out_first[w] + r->out_count[w]; j++)
        if (r->out_fresh[j] && depends(r, r->out_dep_first[j], r->out_dep_count[j], vrs, n)) r->out_fresh[j] = false;
    for (c = 0; c < r->n_cells; c++)
        if (r->cell_instance[c] == w && r->cell_fresh[c] && depends(r, r->cell_dep_first[c], r->cell_dep_count[c], vrs, n))
            r->cell_fresh[c] = false;
}

static void wake(rg_run *r, int w, int edge)
{
    r->woken[w] = true;
    r->woken_edge[w] = edge;
}

/* Route q of an active output clock: its target clock (unless active already), then the clocked
 * values it carries, one Set call per type. */
static int forward_route(rg_run *r, int u, int q)
{
    int w = r->route_target[q], b, i, st;
    uint32_t vr;
    if (!r->s->event_mode[w]) return 0;
    if (!r->active[r->route_clock[q]]) {
        vr = r->clock_vr[r->route_clock[q]];
        *r->s->note_call = r->set_clock_note[w];
        if ((st = r->set_clock[w](r->s->instance[w], &vr, 1, r->on)) > 1) return st;
        r->active[r->route_clock[q]] = true;
        inputs_changed(r, w, &vr, 1);
    }
    if (r->route_source_count[q] > 0) {
        st = clocked_values(r, u, r->route_source + r->route_source_first[q], r->route_source_count[q]);
        if (st != 0) return st;
    }
    for (b = r->route_batch_first[q]; b < r->route_batch_first[q] + r->route_batch_count[q]; b++) {
        int n = r->batch_count[b], kind = r->batch_kind[b], width = value_width(kind);
        const uint32_t *vrs = r->batch_vr + r->batch_first[b];
        for (i = 0; i < n; i++) {
            uint64_t raw = r->cell_raw[r->batch_cell[r->batch_first[b] + i]];
            if (is_bytes(kind)) { /* the copy's bytes (a C string) and size */
                ((const char **)r->set_scratch)[i] = r->s->arena.data + raw + sizeof(size_t);
                memcpy(&r->get_sizes[i], r->s->arena.data + raw, sizeof(size_t));
            } else {
                memcpy((char *)r->set_scratch + (size_t)width * (size_t)i, &raw, (size_t)width);
            }
        }
        *r->s->note_call = r->batch_note[b];
        if (kind == K_BINARY)
            st = r->batch_set_binary[b](r->s->instance[w], vrs, (size_t)n, r->get_sizes,
                                        (const uint8_t *const *)r->set_scratch, (size_t)n);
        else
            st = r->batch_set[b](r->s->instance[w], vrs, (size_t)n, r->set_scratch, (size_t)n);
        if (st > 1) return st;
        inputs_changed(r, w, r->batch_vr + r->batch_first[b], n);
    }
    wake(r, w, r->route_edge[q]);
    return 0;
}

/* u's active output clocks, each forwarded once per instant along its routes. */
static int forward_clocks(rg_run *r, int u)
{
    int j, q, st;
    if ((st = read_clocks(r, u)) != 0) return st;
    for (j = r->out_first[u]; j < r->out_first[u] + r->out_count[u]; j++) {
        if (!r->out_on[j] || r->forwarded[j]) continue;
        r->forwarded[j] = true;
        for (q = r->route_first[j]; q < r->route_first[j] + r->route_count[j]; q++)
            if ((st = forward_route(r, u, q)) != 0) return st;
    }
    return 0;
}

/* u's connected values: its reads, then each Set group whose inputs changed (*changed). */
static int forward_values(rg_run *r, int u, bool *changed)
{
    rg_stretch *s = r->s;
    int k, st, count;
    bool no_memory = false;
    for (k = r->op_first[u]; k < r->op_first[u] + r->op_count[u]; k++) {
        int op = s->op[k], g = -1 - op;
        if (op >= 0) {
            st = get_values(s, op, &no_memory);
            if (st != 0 || no_memory) return no_memory ? -1 : st;
            continue;
        }
        count = 0;
        if ((st = forward(s, g, &count)) != 0) return st;
        if (count == 0) continue;
        *changed = true;
        inputs_changed(r, r->set_target[g], s->set_vrs, count);
        wake(r, r->set_target[g], r->set_edge[g]);
    }
    return 0;
}

/* An instant's clocks and values, forwarded through a worklist in dependency order until nothing
 * new happens (without connections: each FMU's output clocks read). 0, the failing status, or -3
 * when the values do not settle (an algebraic loop: r->woke says where). */
static int propagate(rg_run *r)
{
    int e, u, w, low = 0, st, n = r->s->n_instances;
    long budget = 50L * (long)(n + 1) * (long)(n + 1);
    bool changed = false;
    if (!r->connected) {
        for (e = 0; e < r->n_event; e++)
            if ((st = read_clocks(r, r->event_instance[e])) != 0) return st;
        return 0;
    }
    for (w = 0; w < r->out_first[n]; w++) r->forwarded[w] = false;
    for (e = 0; e < r->n_edges; e++) r->woke[e] = 0;
    for (e = 0; e < r->n_event; e++) r->queued[r->event_instance[e]] = true;
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
            if (!r->queued[w] && r->s->event_mode[w]) {
                r->queued[w] = true;
                if (w < low) low = w;
            }
        }
    }
}

/* After an instant's update: every connected value forwarded; *changed if an input changed. */
static int exchange(rg_run *r, bool *changed)
{
    int u, w, st;
    for (u = 0; u < r->s->n_instances; u++)
        if ((st = forward_values(r, u, changed)) != 0) return st;
    for (w = 0; w < r->s->n_instances; w++) r->woken[w] = false;
    return 0;
}

/* fmi3UpdateDiscreteStates on every FMU in Event Mode; *needs if one asks for another instant. */
static int update_all(rg_run *r, double t, bool *needs)
{
    int e, c, st;
    for (e = 0; e < r->n_event; e++) {
        int u = r->event_instance[e];
        bool b[5] = {false, false, false, false, false};
        double next = 0.0;
        *r->s->note_call = r->update_note[u];
        st = r->update[u](r->s->instance[u], b, b + 1, b + 2, b + 3, b + 4, &next);
        if (st > 1) return st;
        for (c = r->clock_first[u]; c < r->clock_first[u] + r->clock_count[u]; c++) r->active[c] = false;
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
static void refresh_timing(rg_run *r, double t)
{
    double limit = t + tol(t), earliest = INFINITY;
    int u, p, e;
    for (u = 0; u < r->s->n_instances; u++) {
        double tick = INFINITY;
        for (p = 0; p < r->n_periodic; p++)
            if (r->p_instance[p] == u && next_tick(r, p) < tick) tick = next_tick(r, p);
        if (limit < tick && tick < earliest) earliest = tick;
    }
    for (e = 0; e < r->n_event; e++) {
        int u = r->event_instance[e];
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

/* One event of clock c (of instance u) at (t, k): its line of the events log, the clocked
 * variables it shows read as the Python loop reads them. 0, the failing status, or -1. */
static int log_event(rg_run *r, int u, int c, double t, int k)
{
    rg_bytes *b = &r->events;
    int i, first = r->event_first[c], st;
    if ((st = clocked_values(r, u, r->event_cell + first, r->event_count[c])) != 0) return st;
    if (!reserve(b, 64)) return -1;
    put(b, "{\"time\": ", 9);
    if (!json_number(b, K_F64, &t) || !reserve(b, 32)) return -1;
    b->used += (size_t)sprintf(b->data + b->used, ", \"index\": %d", k);
    if (!put_text(b, r->event_head[c])) return -1;
    for (i = first; i < first + r->event_count[c]; i++) {
        int cell = r->event_cell[i];
        if ((i > first && !put_text(b, ", ")) || !put_text(b, r->event_key[i])) return -1;
        if (!json_number(b, r->cell_kind[cell], &r->cell_raw[cell])) return -1;
    }
    return put_text(b, "}}\n") ? 0 : -1;
}

/* The events of the instant (t, k): every active clock's, by instance and value reference. */
static int log_events(rg_run *r, double t, int k)
{
    int u, c, st;
    for (u = 0; u < r->s->n_instances; u++)
        for (c = r->clock_first[u]; c < r->clock_first[u] + r->clock_count[u]; c++)
            if (r->active[c] && (st = log_event(r, u, c, t, k)) != 0) return st;
    return 0;
}

/* The instants at t, up to the last row; then Step Mode. 0, a failing status, -1 (no memory), -2
 * (it did not settle: r->zeno_k instants) or -3 (values that do not settle in an instant). */
static int event_iteration(rg_run *r, rg_rows *out, double t)
{
    int k = 0, st, e, c;
    bool needs, changed;
    r->event_iterations++;
    *r->s->note_time = t;
    if ((st = activate_due_clocks(r, t, t + tol(t))) != 0) return st;
    do {
        needs = changed = false;
        r->instants++;
        if (r->s->mode == MODE_TEXT) r->s->arena.used = 0; /* the previous instant's copies are written out */
        if ((st = propagate(r)) != 0 || (st = record(r, out, t, k, true)) != 0) return st;
        if (r->events_fd >= 0 && (st = log_events(r, t, k)) != 0) return st;
        if (k >= r->max_iterations - 1)
            for (c = 0; c < r->clock_first[r->s->n_instances]; c++) r->ticked[c] = r->active[c];
        if ((st = update_all(r, t, &needs)) != 0) return st;
        k++;
        if (!needs && r->connected && (st = exchange(r, &changed)) != 0) return st;
        if ((needs || changed) && k >= r->max_iterations) {
            r->zeno_k = k;
            return -2;
        }
    } while (needs || changed);
    if ((st = record(r, out, t, k, true)) != 0) return st;
    for (e = 0; e < r->n_event; e++) {
        int u = r->event_instance[e];
        *r->s->note_call = r->enter_step_note[u];
        if ((st = r->enter_step[u](r->s->instance[u])) > 1) return st;
    }
    refresh_timing(r, t);
    r->event_ended = true;
    if (write_events(r) != 0) return -4;
    return r->fd >= 0 ? write_text(r) : 0;
}

static int event_mode(rg_run *r, rg_rows *out, double t)
{
    int e, st;
    for (e = 0; e < r->n_event; e++) {
        int u = r->event_instance[e];
        *r->s->note_call = r->enter_event_note[u];
        if ((st = r->enter_event[u](r->s->instance[u])) > 1) return st;
        new_instant(r, u);
    }
    return event_iteration(r, out, t);
}

