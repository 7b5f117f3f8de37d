/* Hand-written test model "plain" for the robogen runtime: no clocks, so it may be instantiated
 * with eventModeUsed=false. Integrates y' = u in DoStep, can raise an internal event at
 * `event_at`, and can be told to break the DoStep contract (`misbehave`) so that the runtime's
 * checks of the model are exercised. Parameters of every other numeric type test the typed
 * fmi3Get/Set functions. */
#ifndef PLAIN_CONFIG_H
#define PLAIN_CONFIG_H

#include <stdbool.h>
#include <stdint.h>

#define RG_MODEL_IDENTIFIER "plain"
#define RG_INSTANTIATION_TOKEN "{robogen-test-plain-4be2a907}"
#define RG_NUM_VARIABLES 11
#define RG_NUM_CLOCKS 0
#define RG_MIGHT_RETURN_EARLY 1

/* model.c implements rg_model_do_step; the runtime's defaults stand in for the other hooks */
#define RG_HAS_DO_STEP

/* misbehave: what the model's DoStep does wrong */
#define PLAIN_BEHAVE 0
#define PLAIN_EARLY_WITHOUT_PERMISSION 1
#define PLAIN_PAST_STEP_END 2
#define PLAIN_DISCARD 3

typedef struct {
    double u;        /* vr 1 */
    double y;        /* vr 2 */
    double event_at; /* vr 3 */
    int32_t misbehave; /* vr 4 */
    uint64_t steps;  /* vr 5 */
    float f32;       /* vr 6 */
    int8_t i8;       /* vr 7 */
    uint8_t u8;      /* vr 8 */
    int16_t i16;     /* vr 9 */
    uint16_t u16;    /* vr 10 */
    uint32_t u32;    /* vr 11 */
} rg_model_data;

#endif
