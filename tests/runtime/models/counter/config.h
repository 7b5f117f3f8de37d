/* Hand-written test model "counter" for the robogen runtime (what the generator would emit).
 *
 * A d-model in miniature: a constant periodic input clock `cycle` (0.1 s) runs one cycle per tick;
 * a triggered input clock `command` carries an Int64 payload that is latched and consumed by the
 * next cycle, which then raises the triggered output clock `tick` with a clocked Float64 value.
 */
#ifndef COUNTER_CONFIG_H
#define COUNTER_CONFIG_H

#include <stdbool.h>
#include <stdint.h>

#define RG_MODEL_IDENTIFIER "counter"
#define RG_INSTANTIATION_TOKEN "{robogen-test-counter-7d1c0e52}"
#define RG_NUM_VARIABLES 15
#define RG_NUM_CLOCKS 3
#define RG_MIGHT_RETURN_EARLY 1

/* model.c implements every hook */
#define RG_HAS_EXIT_INITIALIZATION
#define RG_HAS_LATCH
#define RG_HAS_EVALUATE
#define RG_HAS_UPDATE
#define RG_HAS_DO_STEP

typedef struct {
    /* variables */
    int64_t command_value;  /* vr 3, clocked by command */
    double tick_value;      /* vr 5, clocked by tick */
    uint64_t count;         /* vr 6: cycles run */
    bool flag;              /* vr 7: count is odd */
    double gains[3];        /* vr 8 */
    double offset;          /* vr 9 */
    double level;           /* vr 10 */
    double early_at;        /* vr 11 */
    int64_t last_command;   /* vr 12 */
    uint64_t evaluations;   /* vr 13: calls of rg_model_evaluate */
    uint64_t latches;       /* vr 14: calls of rg_model_latch */
    int32_t limit;          /* vr 15 */
    /* the machine's input register */
    bool command_pending;
    int64_t command_register;
} rg_model_data;

#endif
