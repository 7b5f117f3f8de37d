/* robogen runtime, part of robogen_runtime.c: fmi3GetClock/SetClock (activation, periodic tick rules) and the
 * interval and shift functions.
 *
 * Included at the end of robogen_runtime.c, never compiled on its own: it uses the helpers defined
 * there (rg_enter, rg_fail, rg_log, the tables, rg_prepare_instant). See the design note there.
 */
#ifndef ROBOGEN_RUNTIME_PARTS
#error "robogen_runtime_clocks.c is part of robogen_runtime.c; compile robogen_runtime.c (through the FMU's unity file)"
#endif

/* ============================================================================================
 * Time resolution
 * ============================================================================================ */

/* x > 0 as the decimal it was written as, n / 10^d with the fewest digits d <= 15 that read back
 * as x (robogen.fmu.fmi.decimal_fraction); false where there is none (or n would not be exact). */
static bool rg_decimal(double x, int64_t *n, int *d)
{
    double scale = 1.0;
    for (*d = 0; *d <= 15; ++*d, scale *= 10.0) {
        double scaled = floor(x * scale + 0.5);
        if (scaled > 9007199254740992.0) return false;
        if (scaled / scale == x) {
            *n = (int64_t)scaled;
            return true;
        }
    }
    return false;
}

static int64_t rg_gcd(int64_t a, int64_t b)
{
    while (b != 0) {
        int64_t r = a % b;
        a = b;
        b = r;
    }
    return a;
}

/* The greatest common divisor of the constant clocks' intervals and shifts (robogen.fmu.fmi.
 * time_resolution), computed once; 0 without any (or where they are not decimals). */
static double rg_time_resolution(void)
{
    static double resolution = -1.0;
    int64_t g = 0, n;
    int c, k, d, digits = 0;
    double values[2];
    if (resolution >= 0.0) return resolution;
    for (c = 0; c < RG_NUM_CLOCKS; ++c) /* the most decimal digits first */
        for (k = 0, values[0] = rg_clocks[c].interval, values[1] = rg_clocks[c].shift; k < 2; ++k)
            if (rg_clocks[c].kind == RG_CLOCK_INPUT_CONSTANT && values[k] > 0.0 && rg_decimal(values[k], &n, &d) && d > digits)
                digits = d;
    for (c = 0; c < RG_NUM_CLOCKS; ++c)
        for (k = 0, values[0] = rg_clocks[c].interval, values[1] = rg_clocks[c].shift; k < 2; ++k) {
            if (rg_clocks[c].kind != RG_CLOCK_INPUT_CONSTANT || !(values[k] > 0.0)) continue;
            if (!rg_decimal(values[k], &n, &d)) return resolution = 0.0;
            for (; d < digits; ++d) n *= 10;
            g = rg_gcd(n, g);
        }
    return resolution = g > 0 ? (double)g / pow(10.0, digits) : 0.0;
}

/* ============================================================================================
 * Clocks
 * ============================================================================================ */

/* The rg_clocks index of a Clock value reference, or -1 after failing the call. */
static int rg_clock_argument(rg_instance *inst, const char *fn, fmi3ValueReference vr)
{
    const rg_variable *v = rg_find_variable(vr);
    if (v == NULL) {
        rg_fail(inst, fn, "unknown value reference %u", (unsigned)vr);
        return -1;
    }
    if (v->type != RG_CLOCK) {
        rg_fail(inst, fn, "'%s' (vr %u) is a %s variable, not a Clock", v->name, (unsigned)vr, rg_type_name(v->type));
        return -1;
    }
    if (rg_find_clock(vr) < 0) { /* excluded by rg_check_tables; kept so no index is ever -1 */
        rg_fail(inst, fn, "internal error: clock '%s' is missing from rg_clocks", v->name);
        return -1;
    }
    return rg_find_clock(vr);
}

/* GetClock: input and output clocks alike report their activation in the current instant (FMI
 * 3.0: clocks are read "just like any other variable"); all read inactive in Initialization Mode. */
fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                        fmi3Clock values[])
{
    static const char *const fn = "fmi3GetClock";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_GET_CLOCK);
    fmi3Status status = fmi3OK;
    size_t i;
    if (inst == NULL) return fmi3Error;
    if (nValueReferences > 0 && (valueReferences == NULL || values == NULL)) {
        return rg_fail(inst, fn, "valueReferences or values is NULL but nValueReferences is %zu", nValueReferences);
    }
    for (i = 0; i < nValueReferences; ++i) {
        if (rg_clock_argument(inst, fn, valueReferences[i]) < 0) return fmi3Error;
    }
    if (inst->s.mode == RG_EVENT_MODE) {
        status = rg_prepare_instant(inst, fn);
        if (status > fmi3Warning) return status;
    }
    for (i = 0; i < nValueReferences; ++i) {
        int c = rg_find_clock(valueReferences[i]); /* >= 0: checked above */
        values[i] = c >= 0 && inst->s.clock_active[c];
    }
    return status;
}

/* Check one activation request of SetClock without changing anything. */
static bool rg_check_set_clock(rg_instance *inst, const char *fn, int c, bool activate)
{
    const rg_clock *k = &rg_clocks[c];
    if (!rg_clock_is_input(c)) {
        rg_fail(inst, fn, "'%s' is an output clock: only the FMU activates it", k->name);
        return false;
    }
    if (!activate) {
        if (inst->s.clock_active[c]) {
            rg_fail(inst, fn, "'%s' cannot be deactivated (canBeDeactivated=\"false\")", k->name);
            return false;
        }
        return true; /* already inactive: nothing to do */
    }
    if (inst->s.clock_active[c] || k->kind == RG_CLOCK_INPUT_TRIGGERED) return true;
    { /* a constant clock: only its next tick, when due, before the instant is evaluated */
        uint64_t next = inst->s.clock_next_tick[c];
        double due = rg_tick_time(inst, c, next);
        if (!rg_time_equal(inst->s.time, due)) {
            if (next > 0 && rg_time_equal(inst->s.time, rg_tick_time(inst, c, next - 1))) {
                rg_fail(inst, fn, "'%s' already ticked at t=%.17g (tick %" PRIu64 "): a periodic clock is active "
                        "for at most one fmi3UpdateDiscreteStates per Event Mode", k->name, inst->s.time, next - 1);
            } else {
                rg_fail(inst, fn, "'%s' is not due at t=%.17g: its next tick (k=%" PRIu64 ") is at t=%.17g",
                        k->name, inst->s.time, next, due);
            }
            return false;
        }
        if (inst->s.evaluated) {
            rg_fail(inst, fn, "'%s': this instant was already evaluated by an fmi3Get*/fmi3GetClock; activate "
                    "time-based clocks before reading, or start a new instant with fmi3UpdateDiscreteStates", k->name);
            return false;
        }
    }
    return true;
}

fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                        const fmi3Clock values[])
{
    static const char *const fn = "fmi3SetClock";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_SET_CLOCK);
    size_t i;
    if (inst == NULL) return fmi3Error;
    if (nValueReferences > 0 && (valueReferences == NULL || values == NULL)) {
        return rg_fail(inst, fn, "valueReferences or values is NULL but nValueReferences is %zu", nValueReferences);
    }
    for (i = 0; i < nValueReferences; ++i) { /* check all before changing any */
        int c = rg_clock_argument(inst, fn, valueReferences[i]);
        if (c < 0 || !rg_check_set_clock(inst, fn, c, rg_read_flag(&values[i]))) return fmi3Error;
    }
    for (i = 0; i < nValueReferences; ++i) {
        int c = rg_find_clock(valueReferences[i]); /* >= 0: checked above */
        if (c < 0 || !rg_read_flag(&values[i]) || inst->s.clock_active[c]) continue;
        inst->s.clock_active[c] = true;
        inst->s.clock_latched[c] = false;
        if (rg_clocks[c].kind == RG_CLOCK_INPUT_CONSTANT) {
            inst->s.clock_next_tick[c] += 1;
            inst->s.clock_ever_activated[c] = true;
        }
        rg_log(inst, RG_LOG_EVENTS, fmi3OK, "%s: '%s' activated at t=%.17g (instant %" PRIu64 ")%s", fn,
               rg_clocks[c].name, inst->s.time, inst->s.superdense,
               inst->s.evaluated ? "; the model receives it at fmi3UpdateDiscreteStates" : "");
    }
    return fmi3OK;
}

/* The constant clock behind an interval/shift value reference, or -1 after failing the call. */
static int rg_time_based_clock_argument(rg_instance *inst, const char *fn, fmi3ValueReference vr)
{
    int c = rg_clock_argument(inst, fn, vr);
    if (c < 0) return -1;
    if (rg_clocks[c].kind != RG_CLOCK_INPUT_CONSTANT) {
        rg_fail(inst, fn, "'%s' is a %s clock: only time-based clocks have an interval and a shift",
                rg_clocks[c].name, rg_clock_kind_name(rg_clocks[c].kind));
        return -1;
    }
    return c;
}

fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[])
{
    static const char *const fn = "fmi3GetIntervalDecimal";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_GET_INTERVAL);
    size_t i;
    if (inst == NULL) return fmi3Error;
    if (nValueReferences > 0 && (valueReferences == NULL || intervals == NULL || qualifiers == NULL)) {
        return rg_fail(inst, fn, "valueReferences, intervals or qualifiers is NULL but nValueReferences is %zu",
                       nValueReferences);
    }
    for (i = 0; i < nValueReferences; ++i) {
        if (rg_time_based_clock_argument(inst, fn, valueReferences[i]) < 0) return fmi3Error;
    }
    for (i = 0; i < nValueReferences; ++i) {
        int c = rg_find_clock(valueReferences[i]); /* >= 0: checked above */
        if (c < 0) continue;
        intervals[i] = rg_clocks[c].interval;
        qualifiers[i] = fmi3IntervalUnchanged; /* the only qualifier of a constant clock */
    }
    return fmi3OK;
}

fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                               size_t nValueReferences, fmi3Float64 shifts[])
{
    static const char *const fn = "fmi3GetShiftDecimal";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_GET_SHIFT);
    size_t i;
    if (inst == NULL) return fmi3Error;
    if (nValueReferences > 0 && (valueReferences == NULL || shifts == NULL)) {
        return rg_fail(inst, fn, "valueReferences or shifts is NULL but nValueReferences is %zu", nValueReferences);
    }
    for (i = 0; i < nValueReferences; ++i) {
        if (rg_time_based_clock_argument(inst, fn, valueReferences[i]) < 0) return fmi3Error;
    }
    for (i = 0; i < nValueReferences; ++i) {
        int c = rg_find_clock(valueReferences[i]); /* >= 0: checked above */
        if (c >= 0) shifts[i] = rg_clocks[c].shift;
    }
    return fmi3OK;
}

/* SetInterval/SetShift: robogen's time-based clocks are all constant (fixed by the XML). */
static fmi3Status rg_reject_timing(fmi3Instance instance, const char *fn, unsigned allowed, const char *what,
                                   const fmi3ValueReference valueReferences[], size_t nValueReferences,
                                   const void *values)
{
    rg_instance *inst = rg_enter(instance, fn, allowed);
    int first = -1;
    size_t i;
    if (inst == NULL) return fmi3Error;
    if (nValueReferences > 0 && (valueReferences == NULL || values == NULL)) {
        return rg_fail(inst, fn, "valueReferences or the %ss are NULL but nValueReferences is %zu", what, nValueReferences);
    }
    for (i = 0; i < nValueReferences; ++i) {
        int c = rg_time_based_clock_argument(inst, fn, valueReferences[i]);
        if (c < 0) return fmi3Error;
        if (first < 0) first = c;
    }
    if (first < 0) return fmi3OK; /* nothing to set */
    return rg_fail(inst, fn, "'%s' is a constant clock: its %s is fixed by modelDescription.xml",
                   rg_clocks[first].name, what);
}

fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, const fmi3Float64 intervals[])
{
    return rg_reject_timing(instance, "fmi3SetIntervalDecimal", RG_ALLOWED_SET_INTERVAL, "interval", valueReferences,
                            nValueReferences, intervals);
}

fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                               size_t nValueReferences, const fmi3Float64 shifts[])
{
    return rg_reject_timing(instance, "fmi3SetShiftDecimal", RG_ALLOWED_SET_SHIFT, "shift", valueReferences,
                            nValueReferences, shifts);
}
