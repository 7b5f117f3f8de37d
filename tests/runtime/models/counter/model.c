/* Hand-written test model "counter": tables and hooks against robogen_runtime.h. */

enum { CLOCK_CYCLE = 0, CLOCK_COMMAND = 1, CLOCK_TICK = 2 };

/* Value -999 on `command` makes the next evaluation fail (tests the model-error path). */
#define COUNTER_POISON (-999)

static const rg_clock rg_clocks[RG_NUM_CLOCKS] = {
    {1, "cycle", RG_CLOCK_INPUT_CONSTANT, 0.1, 0.0},
    {2, "command", RG_CLOCK_INPUT_TRIGGERED, 0.0, 0.0},
    {4, "tick", RG_CLOCK_OUTPUT_TRIGGERED, 0.0, 0.0},
};

#define VAR(vr, name, type, causality, variability, clock, field, count, init) \
    {vr, name, type, causality, variability, clock, offsetof(rg_model_data, field), count, init}

static const rg_variable rg_variables[RG_NUM_VARIABLES] = {
    {1, "cycle", RG_CLOCK, RG_INPUT, RG_DISCRETE, -1, 0, 1, false},
    {2, "command", RG_CLOCK, RG_INPUT, RG_DISCRETE, -1, 0, 1, false},
    VAR(3, "command.value", RG_INT64, RG_INPUT, RG_DISCRETE, CLOCK_COMMAND, command_value, 1, true),
    {4, "tick", RG_CLOCK, RG_OUTPUT, RG_DISCRETE, -1, 0, 1, false},
    VAR(5, "tick.value", RG_FLOAT64, RG_OUTPUT, RG_DISCRETE, CLOCK_TICK, tick_value, 1, false),
    VAR(6, "count", RG_UINT64, RG_OUTPUT, RG_DISCRETE, -1, count, 1, false),
    VAR(7, "flag", RG_BOOLEAN, RG_OUTPUT, RG_DISCRETE, -1, flag, 1, false),
    VAR(8, "gains", RG_FLOAT64, RG_PARAMETER, RG_FIXED, -1, gains, 3, true),
    VAR(9, "offset", RG_FLOAT64, RG_PARAMETER, RG_TUNABLE, -1, offset, 1, true),
    VAR(10, "level", RG_FLOAT64, RG_INPUT, RG_DISCRETE, -1, level, 1, true),
    VAR(11, "early_at", RG_FLOAT64, RG_PARAMETER, RG_FIXED, -1, early_at, 1, true),
    VAR(12, "last_command", RG_INT64, RG_OUTPUT, RG_DISCRETE, -1, last_command, 1, false),
    VAR(13, "evaluations", RG_UINT64, RG_OUTPUT, RG_DISCRETE, -1, evaluations, 1, false),
    VAR(14, "latches", RG_UINT64, RG_OUTPUT, RG_DISCRETE, -1, latches, 1, false),
    VAR(15, "limit", RG_INT32, RG_PARAMETER, RG_TUNABLE, -1, limit, 1, true),
};

static void rg_model_reset(rg_instance *inst)
{
    rg_model_data *d = &inst->s.data;
    d->gains[0] = 1.0;
    d->gains[1] = 2.0;
    d->gains[2] = 3.0;
    d->offset = 0.5;
    d->early_at = -1.0;
    d->limit = 1000;
}

static fmi3Status rg_model_exit_initialization(rg_instance *inst)
{
    if (inst->s.data.gains[0] < 0.0) {
        rg_log(inst, RG_LOG_ERROR, fmi3Error, "gains[0] must not be negative (is %g)", inst->s.data.gains[0]);
        return fmi3Error;
    }
    return fmi3OK;
}

static void rg_model_latch(rg_instance *inst, int clock_index)
{
    rg_model_data *d = &inst->s.data;
    d->latches += 1;
    if (clock_index == CLOCK_COMMAND) {
        d->command_pending = true;
        d->command_register = d->command_value;
    }
}

static fmi3Status rg_model_evaluate(rg_instance *inst)
{
    rg_model_data *d = &inst->s.data;
    d->evaluations += 1;
    if (!inst->s.clock_active[CLOCK_CYCLE]) return fmi3OK;
    d->count += 1;
    d->flag = d->count % 2 == 1;
    rg_log(inst, RG_LOG_TRANSITIONS, fmi3OK, "cycle %llu", (unsigned long long)d->count);
    if (d->command_pending) {
        if (d->command_register == COUNTER_POISON) {
            rg_log(inst, RG_LOG_ERROR, fmi3Error, "poisoned command");
            return fmi3Error;
        }
        d->command_pending = false;
        d->last_command = d->command_register;
        d->tick_value = (double)d->command_register * d->gains[1] + d->offset + d->level;
        rg_activate_output_clock(inst, CLOCK_TICK);
    }
    return fmi3OK;
}

static fmi3Status rg_model_update(rg_instance *inst, bool *discrete_states_need_update, bool *terminate_simulation,
                                  bool *next_event_time_defined, double *next_event_time)
{
    rg_model_data *d = &inst->s.data;
    *discrete_states_need_update = false;
    *terminate_simulation = d->count > (uint64_t)(d->limit < 0 ? 0 : d->limit);
    *next_event_time_defined = d->early_at > inst->s.time;
    *next_event_time = d->early_at;
    return fmi3OK;
}

static fmi3Status rg_model_do_step(rg_instance *inst, double t_end, bool *event_handling_needed,
                                   bool *terminate_simulation, double *last_successful_time)
{
    rg_model_data *d = &inst->s.data;
    (void)terminate_simulation;
    if (d->early_at > inst->s.time && d->early_at < t_end) {
        /* an internal event raises `tick` inside the step */
        d->tick_value = d->early_at;
        rg_activate_output_clock(inst, CLOCK_TICK);
        *event_handling_needed = true;
        if (inst->early_return_allowed) *last_successful_time = d->early_at;
    }
    return fmi3OK;
}
