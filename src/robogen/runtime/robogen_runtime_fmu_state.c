/* robogen runtime, part of robogen_runtime.c: fmi3Get/Set/FreeFMUState and the serialization
 * functions.
 *
 * Included at the end of robogen_runtime.c, never compiled on its own: it uses the helpers defined
 * there (rg_enter, rg_fail, rg_log, the tables, rg_prepare_instant). See the design note there.
 */
#ifndef ROBOGEN_RUNTIME_PARTS
#error "robogen_runtime_fmu_state.c is part of robogen_runtime.c; compile robogen_runtime.c (through the FMU's unity file)"
#endif

/* Serialized FMU state: header layout (native byte order; a state only travels between
 * instances of the same binary, which the token hash and the payload size check). */
#define RG_STATE_MAGIC "RGSTATE1"
#define RG_STATE_MAGIC_SIZE 8
#define RG_STATE_HEADER_SIZE 32 /* magic, token hash, payload size, payload checksum */

/* ============================================================================================
 * Getting and setting the complete FMU state
 * ============================================================================================ */

static bool rg_owns_state(const rg_instance *inst, const rg_fmu_state *state)
{
    const rg_fmu_state *node;
    for (node = inst->states; node != NULL; node = node->next) {
        if (node == state) return true;
    }
    return false;
}

/* *FMUState if it is one of ours, a new state if it is NULL; NULL after failing the call. */
static rg_fmu_state *rg_state_for_writing(rg_instance *inst, const char *fn, fmi3FMUState *FMUState)
{
    rg_fmu_state *state;
    if (FMUState == NULL) {
        rg_fail(inst, fn, "FMUState is NULL");
        return NULL;
    }
    if (*FMUState != NULL) { /* the standard: overwrite a state the importer no longer needs */
        if (!rg_owns_state(inst, (const rg_fmu_state *)*FMUState)) {
            rg_fail(inst, fn, "*FMUState is neither NULL nor a live FMU state of this instance");
            return NULL;
        }
        return (rg_fmu_state *)*FMUState;
    }
    state = (rg_fmu_state *)calloc(1, sizeof *state);
    if (state == NULL) {
        rg_fail(inst, fn, "out of memory");
        return NULL;
    }
    state->next = inst->states;
    inst->states = state;
    *FMUState = state;
    return state;
}

/* An FMU state argument that must be one of ours; NULL after failing the call. */
static const rg_fmu_state *rg_state_argument(rg_instance *inst, const char *fn, fmi3FMUState FMUState)
{
    if (FMUState == NULL) {
        rg_fail(inst, fn, "FMUState is NULL");
        return NULL;
    }
    if (!rg_owns_state(inst, (const rg_fmu_state *)FMUState)) {
        rg_fail(inst, fn, "FMUState is not a live FMU state of this instance (freed, or from another instance)");
        return NULL;
    }
    return (const rg_fmu_state *)FMUState;
}

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *FMUState)
{
    static const char *const fn = "fmi3GetFMUState";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_FMU_STATE);
    rg_fmu_state *state;
    if (inst == NULL) return fmi3Error;
    state = rg_state_for_writing(inst, fn, FMUState);
    if (state == NULL) return fmi3Error;
    state->s = inst->s;
    return fmi3OK;
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState)
{
    static const char *const fn = "fmi3SetFMUState";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_FMU_STATE);
    const rg_fmu_state *state;
    if (inst == NULL) return fmi3Error;
    state = rg_state_argument(inst, fn, FMUState);
    if (state == NULL) return fmi3Error;
    if (state->s.mode == RG_EVENT_MODE && !inst->event_mode_used) {
        return rg_fail(inst, fn, "the state is in Event Mode, but this instance was created with eventModeUsed=false");
    }
    inst->s = state->s;
    rg_log(inst, RG_LOG_EVENTS, fmi3OK, "%s: restored %s at t=%.17g (instant %" PRIu64 ")", fn,
           rg_mode_name(inst->s.mode), inst->s.time, inst->s.superdense);
    return fmi3OK;
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *FMUState)
{
    static const char *const fn = "fmi3FreeFMUState";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_FMU_STATE);
    rg_fmu_state **link;
    if (inst == NULL) return fmi3Error;
    if (FMUState == NULL || *FMUState == NULL) return fmi3OK; /* the standard: a NULL state is ignored */
    for (link = &inst->states; *link != NULL; link = &(*link)->next) {
        if ((void *)*link == *FMUState) {
            rg_fmu_state *found = *link;
            *link = found->next;
            free(found);
            *FMUState = NULL;
            return fmi3OK;
        }
    }
    return rg_fail(inst, fn, "*FMUState is not a live FMU state of this instance (already freed?)");
}

static size_t rg_serialized_size(void)
{
    return RG_STATE_HEADER_SIZE + sizeof(rg_snapshot_part);
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t *size)
{
    static const char *const fn = "fmi3SerializedFMUStateSize";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_FMU_STATE);
    if (inst == NULL) return fmi3Error;
    if (size == NULL) return rg_fail(inst, fn, "size is NULL");
    if (rg_state_argument(inst, fn, FMUState) == NULL) return fmi3Error;
    *size = rg_serialized_size();
    return fmi3OK;
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState, fmi3Byte serializedState[], size_t size)
{
    static const char *const fn = "fmi3SerializeFMUState";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_FMU_STATE);
    const rg_fmu_state *state;
    uint64_t token_hash = rg_fnv1a(RG_INSTANTIATION_TOKEN, strlen(RG_INSTANTIATION_TOKEN));
    uint64_t payload_size = sizeof(rg_snapshot_part);
    uint64_t checksum;
    if (inst == NULL) return fmi3Error;
    state = rg_state_argument(inst, fn, FMUState);
    if (state == NULL) return fmi3Error;
    if (serializedState == NULL) return rg_fail(inst, fn, "serializedState is NULL");
    if (size != rg_serialized_size()) {
        return rg_fail(inst, fn, "size is %zu but a serialized state takes %zu bytes (fmi3SerializedFMUStateSize)",
                       size, rg_serialized_size());
    }
    memcpy(serializedState + RG_STATE_HEADER_SIZE, &state->s, sizeof state->s);
    checksum = rg_fnv1a(serializedState + RG_STATE_HEADER_SIZE, sizeof state->s);
    memcpy(serializedState, RG_STATE_MAGIC, RG_STATE_MAGIC_SIZE);
    memcpy(serializedState + 8, &token_hash, 8);
    memcpy(serializedState + 16, &payload_size, 8);
    memcpy(serializedState + 24, &checksum, 8);
    return fmi3OK;
}

/* A byte of a serialized snapshot that will become a C bool must be 0 or 1. */
static bool rg_serialized_flags_valid(const fmi3Byte *payload, size_t offset, size_t count)
{
    size_t i;
    for (i = 0; i < count; ++i) {
        if (payload[offset + i] > 1) return false;
    }
    return true;
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[], size_t size,
                                   fmi3FMUState *FMUState)
{
    static const char *const fn = "fmi3DeserializeFMUState";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_FMU_STATE);
    const fmi3Byte *payload;
    uint64_t token_hash, payload_size, checksum;
    rg_snapshot_part snapshot;
    rg_fmu_state *state;
    if (inst == NULL) return fmi3Error;
    if (serializedState == NULL) return rg_fail(inst, fn, "serializedState is NULL");
    if (size < RG_STATE_HEADER_SIZE || memcmp(serializedState, RG_STATE_MAGIC, RG_STATE_MAGIC_SIZE) != 0) {
        return rg_fail(inst, fn, "the %zu bytes are not a serialized robogen FMU state", size);
    }
    memcpy(&token_hash, serializedState + 8, 8);
    memcpy(&payload_size, serializedState + 16, 8);
    memcpy(&checksum, serializedState + 24, 8);
    if (token_hash != rg_fnv1a(RG_INSTANTIATION_TOKEN, strlen(RG_INSTANTIATION_TOKEN))) {
        return rg_fail(inst, fn, "the state was serialized by another FMU (instantiation token differs)");
    }
    if (payload_size != sizeof(rg_snapshot_part) || size != rg_serialized_size()) {
        return rg_fail(inst, fn, "truncated or mismatched state: %zu bytes given, %zu expected", size, rg_serialized_size());
    }
    payload = serializedState + RG_STATE_HEADER_SIZE;
    if (checksum != rg_fnv1a(payload, sizeof(rg_snapshot_part))) {
        return rg_fail(inst, fn, "corrupted state: checksum mismatch");
    }
    if (!rg_serialized_flags_valid(payload, offsetof(rg_snapshot_part, stop_time_defined), 1) ||
        !rg_serialized_flags_valid(payload, offsetof(rg_snapshot_part, clock_active), RG_CLOCK_ARRAY_SIZE) ||
        !rg_serialized_flags_valid(payload, offsetof(rg_snapshot_part, clock_latched), RG_CLOCK_ARRAY_SIZE) ||
        !rg_serialized_flags_valid(payload, offsetof(rg_snapshot_part, evaluated), 1) ||
        !rg_serialized_flags_valid(payload, offsetof(rg_snapshot_part, update_pending), 1) ||
        !rg_serialized_flags_valid(payload, offsetof(rg_snapshot_part, event_pending), 1) ||
        !rg_serialized_flags_valid(payload, offsetof(rg_snapshot_part, inputs_set_in_step_mode), 1)) {
        return rg_fail(inst, fn, "corrupted state: invalid flag bytes");
    }
    memcpy(&snapshot, payload, sizeof snapshot);
    if ((unsigned)snapshot.mode == 0 || ((unsigned)snapshot.mode & ~(unsigned)RG_ANY_STATE) != 0 ||
        ((unsigned)snapshot.mode & ((unsigned)snapshot.mode - 1u)) != 0) {
        return rg_fail(inst, fn, "corrupted state: invalid mode");
    }
    state = rg_state_for_writing(inst, fn, FMUState);
    if (state == NULL) return fmi3Error;
    state->s = snapshot;
    return fmi3OK;
}
