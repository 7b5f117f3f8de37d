/* Implementations of the user functions of userfun.rst (robogen --functions). */
static double rg_user_sat(double x, double hi) { return x > hi ? hi : x; }
static bool rg_user_even(int64_t n) { return n % 2 == 0; }
