/* The user functions of the RoboStar Alpha Algorithm's RoboSim Movement machine, for
 * `robogen package ... --functions examples/alpha/maths.c` (see the README).
 *
 * robogen calls each function the model declares without a body as a static C function named
 * rg_user_<name>, with the C types of its parameters and result (nat: uint64_t, real: double).
 * This file is included in the FMU's unity translation unit after the generated declarations.
 *
 * random() is a real in [0, 1) from a xorshift64* generator seeded with a fixed value, so runs
 * are reproducible; its state is per process (every instance of the FMU in one process draws
 * from the same sequence).
 */
#include <math.h>
#include <stdint.h>

static uint64_t rg_user_floor(double x)
{
    return x <= 0.0 ? 0u : (uint64_t)floor(x);
}

static double rg_user_random(void)
{
    static uint64_t state = 0x9E3779B97F4A7C15u;
    state ^= state >> 12;
    state ^= state << 25;
    state ^= state >> 27;
    return (double)((state * 0x2545F4914F6CDD1Du) >> 11) / 9007199254740992.0; /* 53 bits / 2^53 */
}
