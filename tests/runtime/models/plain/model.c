/* Hand-written test model "plain": tables and hooks against robogen_runtime.h. */

static const rg_clock rg_clocks[1] = {{0}};

#define VAR(vr, name, type, causality, variability, field, init) \
    {vr, name, type, causality, variability, -1, offsetof(rg_model_data, field), 1, init}

static const rg_variable rg_variables[RG_NUM_VARIABLES] = {
    VAR(1, "u", RG_FLOAT64, RG_INPUT, RG_CONTINUOUS, u, true),
    VAR(2, "y", RG_FLOAT64, RG_OUTPUT, RG_CONTINUOUS, y, false),
    VAR(3, "event_at", RG_FLOAT64, RG_PARAMETER, RG_FIXED, event_at, true),
    VAR(4, "misbehave", RG_INT32, RG_PARAMETER, RG_TUNABLE, misbehave, true),
    VAR(5, "steps", RG_UINT64, RG_OUTPUT, RG_DISCRETE, steps, false),
    VAR(6, "f32", RG_FLOAT32, RG_PARAMETER, RG_TUNABLE, f32, true),
    VAR(7, "i8", RG_INT8, RG_PARAMETER, RG_TUNABLE, i8, true),
    VAR(8, "u8", RG_UINT8, RG_PARAMETER, RG_TUNABLE, u8, true),
    VAR(9, "i16", RG_INT16, RG_PARAMETER, RG_TUNABLE, i16, true),
    VAR(10, "u16", RG_UINT16, RG_PARAMETER, RG_TUNABLE, u16, true),
    VAR(11, "u32", RG_UINT32, RG_PARAMETER, RG_TUNABLE, u32, true),
};

static void rg_model_reset(rg_instance *inst)
{
    rg_model_data *d = &inst->s.data;
    d->u = 1.0;
    d->event_at = -1.0;
    d->f32 = 1.5f;
    d->i8 = -8;
    d->u8 = 8;
    d->i16 = -16;
    d->u16 = 16;
    d->u32 = 32;
}

static fmi3Status rg_model_do_step(rg_instance *inst, double t_end, bool *event_handling_needed,
                                   bool *terminate_simulation, double *last_successful_time)
{
    rg_model_data *d = &inst->s.data;
    double t = inst->s.time;
    double stop = t_end;
    (void)terminate_simulation;
    d->steps += 1;
    switch (d->misbehave) {
    case PLAIN_EARLY_WITHOUT_PERMISSION:
        *last_successful_time = t + (t_end - t) / 2.0;
        return fmi3OK;
    case PLAIN_PAST_STEP_END:
        *last_successful_time = t_end + 1.0;
        return fmi3OK;
    case PLAIN_DISCARD:
        d->y = -1.0e9; /* the runtime must undo this */
        return fmi3Discard;
    default:
        break;
    }
    if (d->event_at > t && d->event_at < t_end) {
        *event_handling_needed = true;
        if (inst->early_return_allowed) stop = d->event_at;
    }
    d->y += d->u * (stop - t);
    *last_successful_time = stop;
    return fmi3OK;
}
