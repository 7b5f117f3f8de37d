/* The values of an adapted FMU (adapt.c describes the adapters), and its FMU state.
 *
 * FMI 3.0 FMUs (Model Exchange, Scheduled Execution): every Get and Set is the FMU's own.
 * FMI 2.0 FMUs: FMI 2.0's types as FMI 3.0's (robogen.fmu.modeldesc reads them so): Real as
 * Float64, Integer as Int32, Enumeration as Int64 (fmi2GetInteger widened; fmi3SetInt64 narrowed,
 * refused out of Integer's range), Boolean as Boolean (fmi2Boolean is an int), String as String.
 * An FMI 2.0 FMU has no other type: their accessors return fmi3Error with a message. */

/* Room for n values of `size` bytes in the adapter's scratch; NULL when memory runs out. */
static void *scratch(rga *a, size_t n, size_t size)
{
    size_t need = (n > 0 ? n : 1) * size;
    if (need > a->scratch_size) {
        void *grown = realloc(a->scratch, need);
        if (grown == NULL) return NULL;
        a->scratch = grown;
        a->scratch_size = need;
    }
    return a->scratch;
}

static fmi3Status no_type(rga *a, const char *function)
{
    say(a, fmi3Error, "%s: an FMI 2.0 FMU has no variable of this type", function);
    return fmi3Error;
}

/* One Get of type t: the FMU's own (FMI 3.0), after the partitions due have run. */
static fmi3Status get3(rga *a, int t, const char *function, const fmi3ValueReference vrs[], size_t n, void *values,
                       size_t n_values)
{
    fmi3Status status;
    if (a->f3.get[t] == NULL) {
        say(a, fmi3Error, "%s: the FMU does not export it", function);
        return fmi3Error;
    }
    if ((status = settle(a)) > fmi3Warning) return status;
    return a->f3.get[t](a->inner, vrs, n, values, n_values);
}

static fmi3Status set3(rga *a, int t, const char *function, const fmi3ValueReference vrs[], size_t n, const void *values,
                       size_t n_values)
{
    fmi3Status status;
    if (a->f3.set[t] == NULL) {
        say(a, fmi3Error, "%s: the FMU does not export it", function);
        return fmi3Error;
    }
    status = a->f3.set[t](a->inner, vrs, n, values, n_values);
    if (is_me(a)) me_restart_later(a); /* an input changed: the integrator starts afresh from here */
    return status;
}

/* The types only FMI 3.0 has: the FMU's own accessor, or an error for an FMI 2.0 FMU. */
#define ONLY3(T, CTYPE, t)                                                                                            \
    FMI3_Export fmi3Status fmi3Get##T(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, CTYPE values[], \
                                      size_t n_values)                                                                \
    {                                                                                                                 \
        rga *a = (rga *)instance;                                                                                     \
        return is_fmi2(a) ? no_type(a, "fmi3Get" #T) : get3(a, t, "fmi3Get" #T, vrs, n, values, n_values);            \
    }                                                                                                                 \
    FMI3_Export fmi3Status fmi3Set##T(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n,                \
                                      const CTYPE values[], size_t n_values)                                          \
    {                                                                                                                 \
        rga *a = (rga *)instance;                                                                                     \
        return is_fmi2(a) ? no_type(a, "fmi3Set" #T) : set3(a, t, "fmi3Set" #T, vrs, n, values, n_values);            \
    }

ONLY3(Float32, fmi3Float32, T_F32)
ONLY3(Int8, fmi3Int8, T_I8)
ONLY3(UInt8, fmi3UInt8, T_U8)
ONLY3(Int16, fmi3Int16, T_I16)
ONLY3(UInt16, fmi3UInt16, T_U16)
ONLY3(UInt32, fmi3UInt32, T_U32)
ONLY3(UInt64, fmi3UInt64, T_U64)

FMI3_Export fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, fmi3Float64 values[],
                                      size_t n_values)
{
    rga *a = (rga *)instance;
    if (!is_fmi2(a)) return get3(a, T_F64, "fmi3GetFloat64", vrs, n, values, n_values);
    return (fmi3Status)a->f2.get_real(a->inner, vrs, n, values);
}

FMI3_Export fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n,
                                      const fmi3Float64 values[], size_t n_values)
{
    rga *a = (rga *)instance;
    if (!is_fmi2(a)) return set3(a, T_F64, "fmi3SetFloat64", vrs, n, values, n_values);
    if (is_me(a)) me_restart_later(a);
    return (fmi3Status)a->f2.set_real(a->inner, vrs, n, values);
}

FMI3_Export fmi3Status fmi3GetInt32(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, fmi3Int32 values[],
                                    size_t n_values)
{
    rga *a = (rga *)instance;
    if (!is_fmi2(a)) return get3(a, T_I32, "fmi3GetInt32", vrs, n, values, n_values);
    return (fmi3Status)a->f2.get_integer(a->inner, vrs, n, values);
}

FMI3_Export fmi3Status fmi3SetInt32(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n,
                                    const fmi3Int32 values[], size_t n_values)
{
    rga *a = (rga *)instance;
    if (!is_fmi2(a)) return set3(a, T_I32, "fmi3SetInt32", vrs, n, values, n_values);
    if (is_me(a)) me_restart_later(a);
    return (fmi3Status)a->f2.set_integer(a->inner, vrs, n, values);
}

/* FMI 2.0 Enumerations travel as Int64, as FMI 3.0's do. */
FMI3_Export fmi3Status fmi3GetInt64(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, fmi3Int64 values[],
                                    size_t n_values)
{
    rga *a = (rga *)instance;
    fmi2Integer *got;
    fmi2Status status;
    size_t i;
    if (!is_fmi2(a)) return get3(a, T_I64, "fmi3GetInt64", vrs, n, values, n_values);
    if ((got = (fmi2Integer *)scratch(a, n, sizeof(fmi2Integer))) == NULL) return fmi3Error;
    status = a->f2.get_integer(a->inner, vrs, n, got);
    for (i = 0; status <= fmi2Warning && i < n; i++) values[i] = got[i];
    return (fmi3Status)status;
}

FMI3_Export fmi3Status fmi3SetInt64(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n,
                                    const fmi3Int64 values[], size_t n_values)
{
    rga *a = (rga *)instance;
    fmi2Integer *put;
    size_t i;
    if (!is_fmi2(a)) return set3(a, T_I64, "fmi3SetInt64", vrs, n, values, n_values);
    if ((put = (fmi2Integer *)scratch(a, n, sizeof(fmi2Integer))) == NULL) return fmi3Error;
    for (i = 0; i < n; i++) {
        if (values[i] < INT32_MIN || values[i] > INT32_MAX) {
            say(a, fmi3Error, "fmi2SetInteger: %lld is out of the range of an FMI 2.0 Integer (value reference %u)",
                (long long)values[i], (unsigned)vrs[i]);
            return fmi3Error;
        }
        put[i] = (fmi2Integer)values[i];
    }
    if (is_me(a)) me_restart_later(a);
    return (fmi3Status)a->f2.set_integer(a->inner, vrs, n, put);
}

FMI3_Export fmi3Status fmi3GetBoolean(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, fmi3Boolean values[],
                                      size_t n_values)
{
    rga *a = (rga *)instance;
    fmi2Boolean *got;
    fmi2Status status;
    size_t i;
    if (!is_fmi2(a)) return get3(a, T_BOOL, "fmi3GetBoolean", vrs, n, values, n_values);
    if ((got = (fmi2Boolean *)scratch(a, n, sizeof(fmi2Boolean))) == NULL) return fmi3Error;
    status = a->f2.get_boolean(a->inner, vrs, n, got);
    for (i = 0; status <= fmi2Warning && i < n; i++) values[i] = got[i] != fmi2False;
    return (fmi3Status)status;
}

FMI3_Export fmi3Status fmi3SetBoolean(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n,
                                      const fmi3Boolean values[], size_t n_values)
{
    rga *a = (rga *)instance;
    fmi2Boolean *put;
    size_t i;
    if (!is_fmi2(a)) return set3(a, T_BOOL, "fmi3SetBoolean", vrs, n, values, n_values);
    if ((put = (fmi2Boolean *)scratch(a, n, sizeof(fmi2Boolean))) == NULL) return fmi3Error;
    for (i = 0; i < n; i++) put[i] = values[i] ? fmi2True : fmi2False;
    if (is_me(a)) me_restart_later(a);
    return (fmi3Status)a->f2.set_boolean(a->inner, vrs, n, put);
}

FMI3_Export fmi3Status fmi3GetString(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, fmi3String values[],
                                     size_t n_values)
{
    rga *a = (rga *)instance;
    if (!is_fmi2(a)) return get3(a, T_STRING, "fmi3GetString", vrs, n, (void *)values, n_values);
    return (fmi3Status)a->f2.get_string(a->inner, vrs, n, values);
}

FMI3_Export fmi3Status fmi3SetString(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n,
                                     const fmi3String values[], size_t n_values)
{
    rga *a = (rga *)instance;
    if (!is_fmi2(a)) return set3(a, T_STRING, "fmi3SetString", vrs, n, (const void *)values, n_values);
    if (is_me(a)) me_restart_later(a);
    return (fmi3Status)a->f2.set_string(a->inner, vrs, n, values);
}

FMI3_Export fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, size_t sizes[],
                                     fmi3Binary values[], size_t n_values)
{
    rga *a = (rga *)instance;
    fmi3Status status;
    if (is_fmi2(a) || a->f3.get_binary == NULL) return no_type(a, "fmi3GetBinary");
    if ((status = settle(a)) > fmi3Warning) return status;
    return a->f3.get_binary(a->inner, vrs, n, sizes, values, n_values);
}

FMI3_Export fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, const size_t sizes[],
                                     const fmi3Binary values[], size_t n_values)
{
    rga *a = (rga *)instance;
    if (is_fmi2(a) || a->f3.set_binary == NULL) return no_type(a, "fmi3SetBinary");
    if (is_me(a)) me_restart_later(a);
    return a->f3.set_binary(a->inner, vrs, n, sizes, values, n_values);
}

/* ---------------------------------------------------------------------------------------------
 * FMU state: the FMU's own; after fmi3SetFMUState the integrator starts afresh. */

FMI3_Export fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *state)
{
    rga *a = (rga *)instance;
    if (is_fmi2(a) ? a->f2.get_state == NULL : a->f3.get_state == NULL) {
        say(a, fmi3Error, "fmi3GetFMUState: the FMU cannot get its state");
        return fmi3Error;
    }
    return is_fmi2(a) ? (fmi3Status)a->f2.get_state(a->inner, state) : a->f3.get_state(a->inner, state);
}

FMI3_Export fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState state)
{
    rga *a = (rga *)instance;
    if (is_fmi2(a) ? a->f2.set_state == NULL : a->f3.set_state == NULL) {
        say(a, fmi3Error, "fmi3SetFMUState: the FMU cannot set its state");
        return fmi3Error;
    }
    if (is_me(a)) me_restart_later(a);
    return is_fmi2(a) ? (fmi3Status)a->f2.set_state(a->inner, state) : a->f3.set_state(a->inner, state);
}

FMI3_Export fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *state)
{
    rga *a = (rga *)instance;
    if (is_fmi2(a) ? a->f2.free_state == NULL : a->f3.free_state == NULL) return fmi3Error;
    return is_fmi2(a) ? (fmi3Status)a->f2.free_state(a->inner, state) : a->f3.free_state(a->inner, state);
}
