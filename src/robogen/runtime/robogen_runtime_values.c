/* robogen runtime, part of robogen_runtime.c: fmi3Get/Set{Type} with the access rules per mode, causality and clock.
 *
 * Included at the end of robogen_runtime.c, never compiled on its own: it uses the helpers defined
 * there (rg_enter, rg_fail, rg_log, the tables, rg_prepare_instant). See the design note there.
 */
#ifndef ROBOGEN_RUNTIME_PARTS
#error "robogen_runtime_values.c is part of robogen_runtime.c; compile robogen_runtime.c (through the FMU's unity file)"
#endif

/* ============================================================================================
 * Getting and setting variable values
 * ============================================================================================ */

/* Common argument checks of fmi3Get/Set{Type}: pointers, value references, type, element count. */
static bool rg_check_value_arguments(rg_instance *inst, const char *fn, rg_type type,
                                     const fmi3ValueReference vrs[], size_t nvr, const void *values, size_t nValues)
{
    size_t needed = 0;
    size_t i;
    if (nvr > 0 && vrs == NULL) {
        rg_fail(inst, fn, "valueReferences is NULL but nValueReferences is %zu", nvr);
        return false;
    }
    if (nValues > 0 && values == NULL) {
        rg_fail(inst, fn, "values is NULL but nValues is %zu", nValues);
        return false;
    }
    for (i = 0; i < nvr; ++i) {
        const rg_variable *v = rg_find_variable(vrs[i]);
        if (v == NULL) {
            rg_fail(inst, fn, "unknown value reference %u", (unsigned)vrs[i]);
            return false;
        }
        if (v->type != type) {
            if (v->type == RG_CLOCK) {
                rg_fail(inst, fn, "'%s' (vr %u) is a Clock: use fmi3GetClock/fmi3SetClock", v->name, (unsigned)v->vr);
            } else {
                rg_fail(inst, fn, "'%s' (vr %u) is a %s variable, not %s", v->name, (unsigned)v->vr,
                        rg_type_name(v->type), rg_type_name(type));
            }
            return false;
        }
        needed += v->count; /* counts are small (checked against sizeof(rg_model_data)) */
    }
    if (needed != nValues) {
        rg_fail(inst, fn, "nValues is %zu but the %zu value reference(s) hold %zu value(s)", nValues, nvr, needed);
        return false;
    }
    return true;
}

/* May v be read now? (Clocked variables: Initialization Mode, or Event Mode while active.) */
static bool rg_may_get(rg_instance *inst, const char *fn, const rg_variable *v)
{
    if (v->clock < 0 || inst->s.mode == RG_INITIALIZATION_MODE) return true;
    if (inst->s.mode == RG_EVENT_MODE) {
        if (inst->s.clock_active[v->clock]) return true;
        rg_fail(inst, fn, "'%s' is clocked by '%s', which is not active at t=%.17g (instant %" PRIu64 ")",
                v->name, rg_clocks[v->clock].name, inst->s.time, inst->s.superdense);
        return false;
    }
    rg_fail(inst, fn, "'%s' is clocked by '%s': clocked variables can be read only in Initialization Mode "
            "or in Event Mode while their clock is active, not in %s", v->name, rg_clocks[v->clock].name,
            rg_mode_name(inst->s.mode));
    return false;
}

/* May v be written now? */
static bool rg_may_set(rg_instance *inst, const char *fn, const rg_variable *v)
{
    bool input_like = v->causality == RG_INPUT || (v->causality == RG_PARAMETER && v->variability == RG_TUNABLE);
    if (v->variability == RG_CONSTANT) {
        rg_fail(inst, fn, "'%s' is a constant", v->name);
        return false;
    }
    switch (inst->s.mode) {
    case RG_INSTANTIATED:
        if (!v->settable_in_init) break;
        if (v->clock >= 0) {
            rg_fail(inst, fn, "'%s' is clocked: set it in Initialization Mode or while its clock is active", v->name);
            return false;
        }
        return true;
    case RG_INITIALIZATION_MODE:
        if (v->settable_in_init) return true;
        break;
    case RG_EVENT_MODE:
        if (!input_like) break;
        if (v->clock < 0) return true;
        if (!inst->s.clock_active[v->clock]) {
            rg_fail(inst, fn, "'%s' is clocked by '%s', which is not active: activate the clock with fmi3SetClock first",
                    v->name, rg_clocks[v->clock].name);
            return false;
        }
        if (inst->s.clock_latched[v->clock]) {
            rg_fail(inst, fn, "'%s': the activation of '%s' was already consumed by this instant's evaluation "
                    "(an fmi3Get* or fmi3GetClock came first); set clocked inputs right after fmi3SetClock",
                    v->name, rg_clocks[v->clock].name);
            return false;
        }
        return true;
    case RG_STEP_MODE:
        if (!input_like) break;
        if (v->clock >= 0) {
            rg_fail(inst, fn, "'%s' is clocked by '%s': clocked variables cannot be set in Step Mode",
                    v->name, rg_clocks[v->clock].name);
            return false;
        }
        return true;
    case RG_TERMINATED:
        break;
    }
    rg_fail(inst, fn, "'%s' (vr %u) cannot be set in %s (only %s)", v->name, (unsigned)v->vr, rg_mode_name(inst->s.mode),
            inst->s.mode == RG_EVENT_MODE || inst->s.mode == RG_STEP_MODE
                ? "inputs and tunable parameters"
                : "variables with initial=\"exact\" and inputs");
    return false;
}

/* The checks of fmi3Get{Type} before anything is read: NULL on failure (the reason logged), else the instance
 * with the instant prepared; *status the status of that preparation. */
static rg_instance *rg_begin_get(fmi3Instance instance, const char *fn, rg_type type, const fmi3ValueReference vrs[],
                                 size_t nvr, const void *values, size_t nValues, fmi3Status *status)
{
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_GET);
    size_t i;
    *status = fmi3OK;
    if (inst == NULL) return NULL;
    if (!rg_check_value_arguments(inst, fn, type, vrs, nvr, values, nValues)) return NULL;
    if (inst->s.mode == RG_STEP_MODE && inst->s.inputs_set_in_step_mode) {
        rg_fail(inst, fn, "a variable was set in Step Mode since the last fmi3DoStep; FMI 3.0 forbids "
                "fmi3Get* after fmi3Set* without an fmi3DoStep in between");
        return NULL;
    }
    if (inst->s.mode == RG_EVENT_MODE) {
        *status = rg_prepare_instant(inst, fn);
        if (*status > fmi3Warning) return NULL;
    }
    for (i = 0; i < nvr; ++i) {
        if (!rg_may_get(inst, fn, rg_find_variable(vrs[i]))) {
            *status = fmi3Error;
            return NULL;
        }
    }
    return inst;
}

static fmi3Status rg_get_values(fmi3Instance instance, const char *fn, rg_type type,
                                const fmi3ValueReference vrs[], size_t nvr, void *values, size_t nValues)
{
    fmi3Status status;
    rg_instance *inst = rg_begin_get(instance, fn, type, vrs, nvr, values, nValues, &status);
    size_t element_size = rg_type_size(type);
    size_t position = 0;
    size_t i;
    if (inst == NULL) return status > fmi3Warning ? status : fmi3Error;
    for (i = 0; i < nvr; ++i) {
        const rg_variable *v = rg_find_variable(vrs[i]);
        size_t bytes = v->count * element_size;
        memcpy((char *)values + position, (const char *)&inst->s.data + v->offset, bytes);
        position += bytes;
    }
    return status;
}

/* The checks of fmi3Set{Type} before anything is written: the instance, or NULL (the reason logged). */
static rg_instance *rg_begin_set(fmi3Instance instance, const char *fn, rg_type type, const fmi3ValueReference vrs[],
                                 size_t nvr, const void *values, size_t nValues)
{
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_SET);
    size_t i;
    if (inst == NULL) return NULL;
    if (!rg_check_value_arguments(inst, fn, type, vrs, nvr, values, nValues)) return NULL;
    for (i = 0; i < nvr; ++i) { /* check everything before writing anything */
        if (!rg_may_set(inst, fn, rg_find_variable(vrs[i]))) return NULL;
    }
    return inst;
}

static fmi3Status rg_set_values(fmi3Instance instance, const char *fn, rg_type type,
                                const fmi3ValueReference vrs[], size_t nvr, const void *values, size_t nValues)
{
    rg_instance *inst = rg_begin_set(instance, fn, type, vrs, nvr, values, nValues);
    size_t element_size = rg_type_size(type);
    size_t position = 0;
    size_t i, j;
    if (inst == NULL) return fmi3Error;
    for (i = 0; i < nvr; ++i) {
        const rg_variable *v = rg_find_variable(vrs[i]);
        char *target = (char *)&inst->s.data + v->offset;
        if (type == RG_BOOLEAN) {
            for (j = 0; j < v->count; ++j) {
                bool flag = rg_read_flag((const char *)values + position + j * element_size);
                memcpy(target + j * element_size, &flag, element_size);
            }
        } else {
            memcpy(target, (const char *)values + position, v->count * element_size);
        }
        position += v->count * element_size;
    }
    if (inst->s.mode == RG_STEP_MODE && nvr > 0) inst->s.inputs_set_in_step_mode = true;
    return fmi3OK;
}

/* fmi3Get/SetBinary, and String where the model has no string variables: explain what vr is. */
static fmi3Status rg_reject_type(fmi3Instance instance, const char *fn, unsigned allowed, const char *type_name,
                                 const fmi3ValueReference vrs[], size_t nvr, const void *values, size_t nValues)
{
    rg_instance *inst = rg_enter(instance, fn, allowed);
    const rg_variable *v;
    if (inst == NULL) return fmi3Error;
    if (nvr > 0 && vrs == NULL) return rg_fail(inst, fn, "valueReferences is NULL but nValueReferences is %zu", nvr);
    if (nValues > 0 && values == NULL) return rg_fail(inst, fn, "values is NULL but nValues is %zu", nValues);
    if (nvr == 0 && nValues == 0) return fmi3OK;
    if (nvr == 0) return rg_fail(inst, fn, "nValues is %zu but no value references were given", nValues);
    v = rg_find_variable(vrs[0]);
    if (v == NULL) return rg_fail(inst, fn, "unknown value reference %u", (unsigned)vrs[0]);
    return rg_fail(inst, fn, "'%s' (vr %u) is a %s variable, not %s (this FMU has no %s variables)",
                   v->name, (unsigned)v->vr, rg_type_name(v->type), type_name, type_name);
}

#define RG_DEFINE_GET_SET(TypeName, ctype, tag)                                                          \
    fmi3Status fmi3Get##TypeName(fmi3Instance instance, const fmi3ValueReference valueReferences[],      \
                                 size_t nValueReferences, ctype values[], size_t nValues)                 \
    {                                                                                                    \
        return rg_get_values(instance, "fmi3Get" #TypeName, tag, valueReferences, nValueReferences,       \
                             values, nValues);                                                           \
    }                                                                                                    \
    fmi3Status fmi3Set##TypeName(fmi3Instance instance, const fmi3ValueReference valueReferences[],      \
                                 size_t nValueReferences, const ctype values[], size_t nValues)           \
    {                                                                                                    \
        return rg_set_values(instance, "fmi3Set" #TypeName, tag, valueReferences, nValueReferences,       \
                             values, nValues);                                                           \
    }

RG_DEFINE_GET_SET(Float32, fmi3Float32, RG_FLOAT32)
RG_DEFINE_GET_SET(Float64, fmi3Float64, RG_FLOAT64)
RG_DEFINE_GET_SET(Int8, fmi3Int8, RG_INT8)
RG_DEFINE_GET_SET(UInt8, fmi3UInt8, RG_UINT8)
RG_DEFINE_GET_SET(Int16, fmi3Int16, RG_INT16)
RG_DEFINE_GET_SET(UInt16, fmi3UInt16, RG_UINT16)
RG_DEFINE_GET_SET(Int32, fmi3Int32, RG_INT32)
RG_DEFINE_GET_SET(UInt32, fmi3UInt32, RG_UINT32)
RG_DEFINE_GET_SET(Int64, fmi3Int64, RG_INT64)
RG_DEFINE_GET_SET(UInt64, fmi3UInt64, RG_UINT64)
RG_DEFINE_GET_SET(Boolean, fmi3Boolean, RG_BOOLEAN)

#ifdef RG_STRING_VARIABLES
/* String variables. RoboChart builds no strings: every string of the model is one of its literals,
 * and the model holds a string as its number among them (rg_strings, in model.c). An importer may
 * set a text that is none of them: the instance keeps it in rg_model_data.foreign (so an FMU state
 * holds it too) under the next number after the literals, the same text always under the same
 * number, so that equality stays the equality of numbers. At most RG_FOREIGN_STRINGS of them,
 * each shorter than RG_STRING_BYTES bytes. */

static const char *rg_string_text(const rg_instance *inst, int64_t number)
{
    if (number >= 0 && number < RG_NUM_STRINGS) return rg_strings[number];
    number -= RG_NUM_STRINGS;
    if (number >= 0 && (uint64_t)number < inst->s.data.n_foreign) return inst->s.data.foreign[number];
    return ""; /* unreachable: every stored number comes from a literal or from rg_string_number */
}

/* The number of text as a string of the model, or -1 after logging why there is none. */
static int64_t rg_string_number(rg_instance *inst, const char *fn, const rg_variable *v, const char *text)
{
    rg_model_data *d = &inst->s.data;
    size_t length;
    uint64_t i;
    int64_t n;
    if (text == NULL) {
        rg_fail(inst, fn, "'%s': the value is NULL, not a string", v->name);
        return -1;
    }
    for (n = 0; n < RG_NUM_STRINGS; ++n) {
        if (strcmp(rg_strings[n], text) == 0) return n;
    }
    for (i = 0; i < d->n_foreign; ++i) {
        if (strcmp(d->foreign[i], text) == 0) return RG_NUM_STRINGS + (int64_t)i;
    }
    length = strlen(text);
    if (length >= RG_STRING_BYTES) {
        rg_fail(inst, fn, "'%s': a string of %zu bytes, longer than the %d bytes this FMU holds", v->name, length,
                RG_STRING_BYTES - 1);
        return -1;
    }
    if (d->n_foreign >= RG_FOREIGN_STRINGS) {
        rg_fail(inst, fn, "'%s': \"%.40s\" would be the %d-th string that is none of the model's literals; this FMU "
                "holds %d (the capacity, robogen package --capacity)", v->name, text, RG_FOREIGN_STRINGS + 1,
                RG_FOREIGN_STRINGS);
        return -1;
    }
    memcpy(d->foreign[d->n_foreign], text, length + 1);
    return RG_NUM_STRINGS + (int64_t)d->n_foreign++;
}

fmi3Status fmi3GetString(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                         fmi3String values[], size_t nValues)
{
    fmi3Status status;
    rg_instance *inst = rg_begin_get(instance, "fmi3GetString", RG_STRING, valueReferences, nValueReferences, values,
                                     nValues, &status);
    size_t i, j, position = 0;
    if (inst == NULL) return status > fmi3Warning ? status : fmi3Error;
    for (i = 0; i < nValueReferences; ++i) {
        const rg_variable *v = rg_find_variable(valueReferences[i]);
        const int64_t *numbers = (const int64_t *)(const void *)((const char *)&inst->s.data + v->offset);
        for (j = 0; j < v->count; ++j) values[position++] = rg_string_text(inst, numbers[j]);
    }
    return status;
}

fmi3Status fmi3SetString(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                         const fmi3String values[], size_t nValues)
{
    rg_instance *inst = rg_begin_set(instance, "fmi3SetString", RG_STRING, valueReferences, nValueReferences, values,
                                     nValues);
    size_t i, j, position = 0;
    if (inst == NULL) return fmi3Error;
    for (i = 0; i < nValueReferences; ++i) {
        const rg_variable *v = rg_find_variable(valueReferences[i]);
        int64_t *numbers = (int64_t *)(void *)((char *)&inst->s.data + v->offset);
        for (j = 0; j < v->count; ++j) {
            int64_t n = rg_string_number(inst, "fmi3SetString", v, values[position++]);
            if (n < 0) return fmi3Error;
            numbers[j] = n;
        }
    }
    if (inst->s.mode == RG_STEP_MODE && nValueReferences > 0) inst->s.inputs_set_in_step_mode = true;
    return fmi3OK;
}
#else
fmi3Status fmi3GetString(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                         fmi3String values[], size_t nValues)
{
    return rg_reject_type(instance, "fmi3GetString", RG_ALLOWED_GET, "String", valueReferences, nValueReferences,
                          values, nValues);
}

fmi3Status fmi3SetString(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                         const fmi3String values[], size_t nValues)
{
    return rg_reject_type(instance, "fmi3SetString", RG_ALLOWED_SET, "String", valueReferences, nValueReferences,
                          values, nValues);
}
#endif

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                         size_t valueSizes[], fmi3Binary values[], size_t nValues)
{
    (void)valueSizes;
    return rg_reject_type(instance, "fmi3GetBinary", RG_ALLOWED_GET, "Binary", valueReferences, nValueReferences,
                          values, nValues);
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                         const size_t valueSizes[], const fmi3Binary values[], size_t nValues)
{
    (void)valueSizes;
    return rg_reject_type(instance, "fmi3SetBinary", RG_ALLOWED_SET, "Binary", valueReferences, nValueReferences,
                          values, nValues);
}
