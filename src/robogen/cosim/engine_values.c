/* The engine's values and rows: the first of its three files, compiled as one unit with
 * engine_run.c (the run: stretches, general steps, rg_engine_run) and engine_events.c (Event Mode)
 * by robogen.cosim.engine, with the system C compiler, once per source (robogen.cosim.cbuild), and
 * called through cffi. The plan it reads (rg_plan) is defined by engine.h.
 *
 * Here: Python's repr of a double (rg_format_double); the values of a connection on their way
 * from an fmi3Get<Type> to an fmi3Set<Type> (converted, checked against the input's type, set only
 * when changed); the operations after a step in dependency order (a connected FMU's Get calls,
 * then the values it forwards, one Set call per target FMU and type; then the Gets of the
 * recorded FMUs that forward nothing); and the row of the recorded columns.
 *
 * A row is stored in one of three ways (rg_plan.store, enum rg_store):
 *   STORE_SLOTS  8-byte slots, one per recorded value (reals as doubles, signed integers as int64,
 *               unsigned ones as uint64, Booleans as 0/1, Strings and Binaries as the offset of a
 *               copy in the arena: a size_t length, then the bytes); Python builds the columns.
 *   STORE_TEXT   the CSV line the recorder would write (robogen.cosim.recorder): reals in the
 *               shortest form that reads back to the same double, as Python's repr; integers in
 *               decimal; True/False; Strings in double quotes, a quote doubled; Binaries as 0x
 *               and lowercase hexadecimal. No printf-family call on this path (see round_digits).
 *   STORE_NONE   nothing (the rows go nowhere).
 *
 * Before each FMI call the engine notes it (rg_plan.note_call/note_time, the master's
 * robogen.cosim.fmi3.CallNotes), so a crash inside an FMU can be reported by instance, function
 * and time. A chunk also ends at a wall-clock deadline, so the rows reach the results file at
 * least that often however slow the FMUs are. */
#define _POSIX_C_SOURCE 199309L
#define __STDC_WANT_IEC_60559_BFP_EXT__ 1 /* strfromd (ISO/IEC TS 18661-1), where the C library has it */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "engine.h"


#if defined(__GNUC__)
#define RG_EXPORT __attribute__((visibility("default")))
#else
#define RG_EXPORT
#endif

RG_EXPORT int rg_keep_last(rg_engine *s, int link, const char *data, size_t size);
RG_EXPORT size_t rg_format_double(char *out, double x);
RG_EXPORT void rg_release(rg_engine *s);

/* Room for `more` bytes after b->used; false when memory runs out. */
static bool reserve(rg_bytes *b, size_t more)
{
    size_t need = b->used + more;
    if (need > b->size) {
        size_t grown = b->size ? 2 * b->size : 65536;
        char *data;
        while (grown < need) grown *= 2;
        data = (char *)realloc(b->data, grown);
        if (data == NULL) return false;
        b->data = data;
        b->size = grown;
    }
    return true;
}

/* A copy of `size` bytes in the arena (a size_t length, then the bytes); its offset, or
 * UINT64_MAX when memory runs out. */
static uint64_t keep_bytes(rg_bytes *arena, const void *data, size_t size)
{
    uint64_t offset = arena->used;
    if (!reserve(arena, sizeof(size_t) + size + 1)) return UINT64_MAX;
    memcpy(arena->data + arena->used, &size, sizeof(size_t));
    if (size) memcpy(arena->data + arena->used + sizeof(size_t), data, size);
    arena->data[arena->used + sizeof(size_t) + size] = '\0'; /* a String's copy is a C string */
    arena->used += sizeof(size_t) + size + 1;
    return offset;
}

/* ---------------------------------------------------------------------------------------------
 * Python's repr of a double: the shortest decimal that reads back to it (the closest such when
 * there are several), in positional form for decimal exponents -4 <= e < 16 (with ".0" when it
 * is whole), else as d.ddde+XX with at least two exponent digits. */

/* glibc's printf family takes its slow path (printf_positional: about twice the work) in a process
 * where any library registered a printf handler, as libquadmath does when NumPy's OpenBLAS loads
 * it; strfromd formats one double without that machinery. */
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 25))
#define RG_STRFROMD 1
#endif

/* The decimal digits of an integer (a '-' first when `negative`, `magnitude` its absolute value)
 * into out (at least 21 bytes); their count. What "%lld" and "%llu" print, without printf (see
 * above): a CSV line has one in every row (the superdense index). */
static size_t format_integer(char *out, uint64_t magnitude, bool negative)
{
    char digits[20];
    size_t n = 0, k = 0;
    do {
        digits[k++] = (char)('0' + magnitude % 10);
        magnitude /= 10;
    } while (magnitude != 0);
    if (negative) out[n++] = '-';
    while (k > 0) out[n++] = digits[--k];
    return n;
}

/* The digits of |x| rounded to `precision` (1 to 17) significant digits, into `digits`
 * (NUL-terminated, trailing zeros kept), and the decimal exponent of the first. */
static int round_digits(double x, int precision, char *digits)
{
    char buffer[40];
    int i, k = 0;
#ifdef RG_STRFROMD
    char format[8] = "%.";
    size_t at = 2 + format_integer(format + 2, (uint64_t)(precision - 1), false);
    format[at] = 'e';
    format[at + 1] = '\0';
    strfromd(buffer, sizeof buffer, format, fabs(x));
#else
    snprintf(buffer, sizeof buffer, "%.*e", precision - 1, fabs(x));
#endif
    for (i = 0; buffer[i] != 'e'; i++)
        if (buffer[i] != '.') digits[k++] = buffer[i];
    digits[k] = '\0';
    return atoi(buffer + i + 1);
}

static void strip_zeros(char *digits)
{
    size_t k = strlen(digits);
    while (k > 1 && digits[k - 1] == '0') digits[--k] = '\0';
}

static double digits_value(const char *digits, int exponent)
{
    char buffer[48];
    size_t k = strlen(digits);
    buffer[0] = '0';
    buffer[1] = '.';
    memcpy(buffer + 2, digits, k);
    buffer[2 + k] = 'e';
    buffer[3 + k + format_integer(buffer + 3 + k, (uint64_t)(exponent + 1 < 0 ? -(exponent + 1) : exponent + 1),
                                  exponent + 1 < 0)] = '\0';
    return strtod(buffer, NULL);
}

/* The next decimal of as many digits away from zero; the exponent may change. */
static int step_up(char *digits, int exponent)
{
    int i = (int)strlen(digits) - 1;
    while (i >= 0 && digits[i] == '9') digits[i--] = '0';
    if (i >= 0) {
        digits[i]++;
        return exponent;
    }
    digits[0] = '1'; /* 99..9 -> 100..0: one digit more before the point */
    return exponent + 1;
}

/* The `precision` digits of |x| from its 17 (`d17`, exponent e17), rounded to nearest; where the
 * 17 digits end in a tie for that rounding (..5 or ..50), from x itself. */
static int shorter(double x, const char *d17, int e17, int precision, char *digits)
{
    const char *tail = d17 + precision;
    int cmp = tail[0] != '5' ? tail[0] - '5' : precision == 16 ? 0 : tail[1] - '0';
    if (cmp == 0) return round_digits(x, precision, digits);
    memcpy(digits, d17, (size_t)precision);
    digits[precision] = '\0';
    return cmp > 0 ? step_up(digits, e17) : e17;
}

/* Powers of ten exact in a long double (x86's 64-bit mantissa; elsewhere at least a double's,
 * and the checks below then only send more values to the exact path). */
static const long double P10[] = {1e0L, 1e1L, 1e2L, 1e3L, 1e4L, 1e5L, 1e6L, 1e7L, 1e8L, 1e9L, 1e10L, 1e11L,
                                  1e12L, 1e13L, 1e14L, 1e15L, 1e16L, 1e17L, 1e18L, 1e19L, 1e20L, 1e21L,
                                  1e22L, 1e23L, 1e24L, 1e25L, 1e26L, 1e27L};

/* v scaled by 10^k (|k| <= 27): one rounding. */
static long double scaled(long double v, int k) { return k >= 0 ? v * P10[k] : v / P10[-k]; }

/* The fast path of shortest_digits: |x| scaled to 17 digits in long double arithmetic, whose
 * error (a few units of 2^-64) is far below the margins it keeps; -1000 where a rounding or a
 * bound is too close to call (or |x| is out of its range), and the exact path decides. */
static int fast_shortest(double ax, char *digits)
{
    int e10 = (int)floor(log10(ax)), k, p, i;
    long double y, lo, hi, r = 0;
    uint64_t d;
    if (LDBL_MANT_DIG < 64 || e10 < -11 || e10 > 43) return -1000;
    k = 16 - e10;
    y = scaled(ax, k);
    if (y < 1e16L || y >= 1e17L) { /* log10 was off by one */
        e10 += y < 1e16L ? -1 : 1;
        k = 16 - e10;
        if (k < -27 || k > 27) return -1000;
        y = scaled(ax, k);
    }
    lo = scaled((long double)ax - 0.5L * ((long double)ax - nextafter(ax, 0)), k);
    hi = scaled((long double)ax + 0.5L * ((long double)nextafter(ax, INFINITY) - ax), k);
    for (p = 15; p <= 17; p++) {
        /* q rounded to an integer by the addition of 2^63 (a long double's units there are 1): no
         * switch of the x87 rounding mode, as floorl and integer casts make */
        long double unit = P10[17 - p], q = y / unit, c;
        int tries;
        r = (q + 0x1p63L) - 0x1p63L;
        if (fabsl(fabsl(q - r) - 0.5L) < 0.001L) return -1000;
        for (tries = 0; tries < (p == 16 ? 2 : 1); tries++) { /* 16 digits: the far neighbour too */
            c = r * unit;
            if (fabsl(c - lo) < 0.004L || fabsl(c - hi) < 0.004L) return -1000;
            if (lo < c && c < hi) goto found;
            r += c < y ? 1 : -1;
        }
    }
    return -1000;
found:
    d = (uint64_t)llrintl(r);
    if (d >= (uint64_t)llrintl(P10[p])) { /* 99..9 rounded up to 100..0 */
        d /= 10;
        e10++;
    }
    for (i = p - 1; i >= 0; i--) {
        digits[i] = (char)('0' + d % 10);
        d /= 10;
    }
    digits[p] = '\0';
    strip_zeros(digits);
    return e10;
}

/* The shortest digits of |x| (x finite, not 0), their decimal exponent as the result. Any decimal
 * of 15 digits reads back (DBL_DIG), so if one of at most 15 does, the rounding to 15 digits is
 * it; 17 digits always read back. */
static int shortest_digits(double x, char *digits)
{
    double ax = fabs(x);
    char d17[24], d16[24];
    int e17, e16, e15, precision;
    if ((e15 = fast_shortest(ax, digits)) != -1000) return e15;
    if (ax < 2.2250738585072014e-308) { /* subnormal: fewer digits are exact, try them all */
        for (precision = 1; precision < 17; precision++) {
            e15 = round_digits(x, precision, digits);
            if (digits_value(digits, e15) == ax) break;
        }
        e15 = round_digits(x, precision, digits);
        strip_zeros(digits);
        return e15;
    }
    e17 = round_digits(x, 17, d17);
    e16 = shorter(x, d17, e17, 16, d16);
    if (digits_value(d16, e16) != ax) {
        /* Where the double below is nearer than the one above (x a power of two), the correctly
         * rounded decimal may miss while its neighbour further from zero reads back. */
        if (digits_value(d16, e16) > ax || digits_value(d16, e16 = step_up(d16, e16)) != ax) {
            memcpy(digits, d17, sizeof d17);
            strip_zeros(digits);
            return e17;
        }
        memcpy(digits, d16, sizeof d16);
        strip_zeros(digits);
        return e16;
    }
    e15 = shorter(x, d17, e17, 15, digits);
    if (digits_value(digits, e15) != ax) {
        memcpy(digits, d16, sizeof d16);
        e15 = e16;
    }
    strip_zeros(digits);
    return e15;
}

/* A short constant text into out, NUL-terminated; its length. */
static size_t copy_text(char *out, const char *text)
{
    size_t n = strlen(text);
    memcpy(out, text, n + 1);
    return n;
}

/* repr(x) into out (at least 32 bytes); its length. */
RG_EXPORT size_t rg_format_double(char *out, double x)
{
    char digits[24];
    int exponent, k, i, n = 0;
    if (isnan(x)) return copy_text(out, "nan");
    if (isinf(x)) return copy_text(out, x < 0 ? "-inf" : "inf");
    if (x == 0) return copy_text(out, signbit(x) ? "-0.0" : "0.0");
    exponent = shortest_digits(x, digits);
    k = (int)strlen(digits);
    if (x < 0) out[n++] = '-';
    if (exponent < -4 || exponent >= 16) {
        out[n++] = digits[0];
        if (k > 1) {
            out[n++] = '.';
            memcpy(out + n, digits + 1, (size_t)(k - 1));
            n += k - 1;
        }
        out[n++] = 'e';
        out[n++] = exponent < 0 ? '-' : '+';
        if (abs(exponent) < 10) out[n++] = '0'; /* two exponent digits at least */
        n += (int)format_integer(out + n, (uint64_t)abs(exponent), false);
        out[n] = '\0';
        return (size_t)n;
    }
    if (exponent < 0) {
        out[n++] = '0';
        out[n++] = '.';
        for (i = -1; i > exponent; i--) out[n++] = '0';
        memcpy(out + n, digits, (size_t)k);
        n += k;
    } else {
        for (i = 0; i <= exponent || i < k; i++) {
            if (i == exponent + 1) out[n++] = '.';
            out[n++] = i < k ? digits[i] : '0';
        }
        if (k <= exponent + 1) {
            out[n++] = '.';
            out[n++] = '0';
        }
    }
    out[n] = '\0';
    return (size_t)n;
}

/* ---------------------------------------------------------------------------------------------
 * Values */

static double real_of(int kind, const void *buffer, size_t i)
{
    return kind == K_F32 ? (double)((const float *)buffer)[i] : ((const double *)buffer)[i];
}

/* An integer or Boolean value widened to 64 bits (signed kinds sign-extended). */
static uint64_t integer_of(int kind, const void *buffer, size_t i)
{
    switch (kind) {
    case K_I64: return (uint64_t)((const int64_t *)buffer)[i];
    case K_U64: return ((const uint64_t *)buffer)[i];
    case K_I32: return (uint64_t)(int64_t)((const int32_t *)buffer)[i];
    case K_U32: return ((const uint32_t *)buffer)[i];
    case K_I16: return (uint64_t)(int64_t)((const int16_t *)buffer)[i];
    case K_U16: return ((const uint16_t *)buffer)[i];
    case K_I8: return (uint64_t)(int64_t)((const int8_t *)buffer)[i];
    case K_U8: return ((const uint8_t *)buffer)[i];
    default: return ((const bool *)buffer)[i] ? 1u : 0u;
    }
}

/* The bytes of a String or Binary value of a read (NULL reads as empty). */
static const char *bytes_of(const rg_engine *s, int r, size_t i, size_t *size)
{
    const char *data = ((const char *const *)s->p->buffer[r])[i];
    if (data == NULL) {
        *size = 0;
        return "";
    }
    *size = s->p->kind[r] == K_STRING ? strlen(data) : s->p->sizes[r][i];
    return data;
}

static bool is_bytes(int kind) { return kind == K_STRING || kind == K_BINARY; }

/* One read's fmi3Get<Type> call; 0 or the failing status. Strings and Binaries are copied to the
 * arena at once: a later call on the same FMU may free the memory they point to. */
static int get_values(rg_engine *s, int r, bool *no_memory)
{
    size_t i, size;
    int st;
    *s->p->note_call = s->p->read_note[r];
    if (s->p->kind[r] == K_BINARY)
        st = s->p->get_binary[r](s->p->read_instance[r], s->p->vrs[r], s->p->count[r], s->p->sizes[r],
                              (const uint8_t **)s->p->buffer[r], s->p->count[r]);
    else
        st = s->p->get[r](s->p->read_instance[r], s->p->vrs[r], s->p->count[r], s->p->buffer[r], s->p->n_values[r]);
    if (st > 1 || !is_bytes(s->p->kind[r]) || s->p->store == STORE_NONE) return st > 1 ? st : 0;
    for (i = 0; i < s->p->count[r]; i++) {
        const char *data = bytes_of(s, r, i, &size);
        s->copies[r][i] = keep_bytes(&s->arena, data, size);
        if (s->copies[r][i] == UINT64_MAX) *no_memory = true;
    }
    return 0;
}

/* A value that does not fit its input (instance w, value reference vr): the run stops (END_RANGE). */
static void out_of_range(rg_engine *s, int w, uint32_t vr, int kind, rg_value value)
{
    s->range_link = 0;
    s->range_target = w;
    s->range_vr = vr;
    s->range_kind = kind;
    s->range_value = value;
}

/* A linked value that does not fit its input: stops the exchange (forward() tells it from a lack
 * of memory by range_link). */
static bool narrowed(rg_engine *s, int g, int link, int from, rg_value value, bool *no_memory)
{
    out_of_range(s, s->p->set_target[g], s->p->link_vr[link], from, value);
    *no_memory = true;
    return false;
}

/* A real on its way along connection k of a table (the value links', or the clocked batches'):
 * factor * v + offset where k converts it (Link.scale; scaled NULL: no connection converts). */
static double converted(const bool *scaled, const double *factor, const double *offset, int k, double v)
{
    return scaled != NULL && scaled[k] ? factor[k] * v + offset[k] : v;
}

/* Whether an integer of kind `from` (widened by integer_of) fits kind `to`. */
static bool fits(int from, int to, uint64_t v)
{
    bool negative = (from == K_I64 || from == K_I32 || from == K_I16 || from == K_I8) && (int64_t)v < 0;
    int64_t i = (int64_t)v;
    switch (to) {
    case K_I64: return negative || v <= (uint64_t)INT64_MAX;
    case K_U64: return !negative;
    case K_I32: return negative ? i >= INT32_MIN : v <= (uint64_t)INT32_MAX;
    case K_U32: return !negative && v <= UINT32_MAX;
    case K_I16: return negative ? i >= INT16_MIN : v <= (uint64_t)INT16_MAX;
    case K_U16: return !negative && v <= UINT16_MAX;
    case K_I8: return negative ? i >= INT8_MIN : v <= (uint64_t)INT8_MAX;
    case K_U8: return !negative && v <= UINT8_MAX;
    default: return true;
    }
}

/* An integer (widened) as a value of kind `to`, into slot j of `values`. */
static void put_integer(void *values, int to, int j, uint64_t v)
{
    char *out = (char *)values;
    int64_t i = (int64_t)v;
    switch (to) {
    case K_I32: { int32_t x = (int32_t)i; memcpy(out + 4 * (size_t)j, &x, 4); break; }
    case K_U32: { uint32_t x = (uint32_t)v; memcpy(out + 4 * (size_t)j, &x, 4); break; }
    case K_I16: { int16_t x = (int16_t)i; memcpy(out + 2 * (size_t)j, &x, 2); break; }
    case K_U16: { uint16_t x = (uint16_t)v; memcpy(out + 2 * (size_t)j, &x, 2); break; }
    case K_I8: { int8_t x = (int8_t)i; memcpy(out + (size_t)j, &x, 1); break; }
    case K_U8: { uint8_t x = (uint8_t)v; memcpy(out + (size_t)j, &x, 1); break; }
    case K_BOOL: { bool x = v != 0; memcpy(out + sizeof(bool) * (size_t)j, &x, sizeof(bool)); break; }
    default: memcpy(out + 8 * (size_t)j, &v, 8); break;
    }
}

/* Whether a link's source value differs from the value last set (as Python's != compares them:
 * NaN differs from itself, -0.0 equals 0.0); if it does, it becomes the value last set, and goes
 * into slot j of the Set call's arrays, converted in one step: a real by the connection's factor
 * and offset (Link.scale), then to the input's type (a connection between FMI 2.0 and 3.0, or
 * between integer or real types). False with *no_memory when a copy cannot be made, with
 * *narrowing when the value does not fit the input's type (s->range_link says which link). */
static bool changed(rg_engine *s, int g, int link, int j, bool *no_memory)
{
    int r = s->p->link_read[link], kind = s->p->set_kind[g], from = s->p->kind[r];
    size_t i = (size_t)s->p->link_index[link], size;
    rg_value *last = s->last + link;
    if (kind == K_F64 || kind == K_F32) {
        double v = converted(s->p->link_scaled, s->p->link_factor, s->p->link_offset, link,
                             real_of(from, s->p->buffer[r], i));
        float f;
        if (s->last_valid[link] && !(v != last->d)) return false;
        if (kind == K_F32 && isfinite(v) && fabs(v) > FLT_MAX) {
            rg_value value;
            value.d = v;
            return narrowed(s, g, link, from, value, no_memory);
        }
        last->d = v;
        f = (float)v;
        if (kind == K_F32) memcpy((char *)s->set_values + 4 * (size_t)j, &f, 4);
        else s->set_values[j].d = v;
    } else if (!is_bytes(kind)) {
        uint64_t v = integer_of(from, s->p->buffer[r], i);
        if (s->last_valid[link] && v == last->u) return false;
        if (!fits(from, kind, v)) {
            rg_value value;
            value.u = v;
            return narrowed(s, g, link, from, value, no_memory);
        }
        last->u = v;
        put_integer(s->set_values, kind, j, v);
    } else {
        const char *data = bytes_of(s, r, i, &size);
        if (s->last_valid[link] && size == s->last_size[link] && memcmp(data, s->last_bytes[link], size) == 0)
            return false;
        if (rg_keep_last(s, link, data, size) != 0) {
            *no_memory = true;
            return false;
        }
        s->set_pointers[j] = (const uint8_t *)s->last_bytes[link];
        s->set_sizes[j] = size;
    }
    s->last_valid[link] = true;
    return true;
}

/* Group g: the connected inputs whose value changed, in one fmi3Set<Type> call (*count of them,
 * their value references in s->set_vrs); 0, the failing status, or -1 when memory runs out. */
static int forward(rg_engine *s, int g, int *count)
{
    int k, n = 0, st;
    bool no_memory = false;
    for (k = 0; k < s->p->set_count[g]; k++) {
        int link = s->p->set_first[g] + k;
        if (changed(s, g, link, n, &no_memory)) s->set_vrs[n++] = s->p->link_vr[link];
        if (no_memory) return s->range_link >= 0 ? -7 : -1;
    }
    *count = n;
    if (n == 0) return 0;
    *s->p->note_call = s->p->set_note[g];
    if (s->p->set_kind[g] == K_BINARY)
        st = s->p->set_binary[g](s->p->set_instance[g], s->set_vrs, (size_t)n, s->set_sizes, s->set_pointers, (size_t)n);
    else if (s->p->set_kind[g] == K_STRING)
        st = s->p->set[g](s->p->set_instance[g], s->set_vrs, (size_t)n, s->set_pointers, (size_t)n);
    else
        st = s->p->set[g](s->p->set_instance[g], s->set_vrs, (size_t)n, s->set_values, (size_t)n);
    return st > 1 ? st : 0;
}

/* ---------------------------------------------------------------------------------------------
 * Rows */

static void put(rg_bytes *b, const char *text, size_t n)
{
    memcpy(b->data + b->used, text, n);
    b->used += n;
}

/* The CSV cell of value i of a buffer of numbers or Booleans of this kind; false when memory
 * runs out. */
static bool number_cell(rg_bytes *b, int kind, const void *buffer, size_t i)
{
    if (kind == K_F64 || kind == K_F32) {
        if (!reserve(b, 32)) return false;
        b->used += rg_format_double(b->data + b->used, real_of(kind, buffer, i));
    } else {
        uint64_t v = integer_of(kind, buffer, i);
        bool negative = (kind == K_I64 || kind == K_I32 || kind == K_I16 || kind == K_I8) && (int64_t)v < 0;
        if (!reserve(b, 24)) return false;
        if (kind == K_BOOL) put(b, v ? "True" : "False", v ? 4 : 5);
        else b->used += format_integer(b->data + b->used, negative ? 0 - v : v, negative);
    }
    return true;
}

/* The CSV cell of a String or Binary copied to the arena at `offset`; false when memory runs out. */
static bool bytes_cell(rg_bytes *b, int kind, const rg_bytes *arena, uint64_t offset)
{
    static const char hex[] = "0123456789abcdef";
    const char *data;
    size_t size, j;
    memcpy(&size, arena->data + offset, sizeof size);
    data = arena->data + offset + sizeof size;
    if (!reserve(b, 2 * size + 2)) return false;
    if (kind == K_BINARY) {
        put(b, "0x", 2);
        for (j = 0; j < size; j++) {
            b->data[b->used++] = hex[(unsigned char)data[j] >> 4];
            b->data[b->used++] = hex[(unsigned char)data[j] & 15];
        }
        return true;
    }
    b->data[b->used++] = '"';
    for (j = 0; j < size; j++) {
        if (data[j] == '"') b->data[b->used++] = '"';
        b->data[b->used++] = data[j];
    }
    b->data[b->used++] = '"';
    return true;
}

/* A recorded value's CSV cell; false when memory runs out. */
static bool cell(rg_engine *s, int r, size_t i)
{
    int kind = s->p->kind[r];
    if (!is_bytes(kind)) return number_cell(&s->text, kind, s->p->buffer[r], i);
    return bytes_cell(&s->text, kind, &s->arena, s->copies[r][i]);
}

/* The operations first..last-1 (reads, Set groups); 0, the failing call's status (the call notes
 * say which), or -1 when memory runs out. */
static int run_ops(rg_engine *s, int first, int last)
{
    int k, st, count;
    bool no_memory = false;
    for (k = first; k < last; k++) {
        int op = s->p->op[k];
        st = op >= 0 ? get_values(s, op, &no_memory) : forward(s, -1 - op, &count);
        if (st > 0) return st;
        if (no_memory || st < 0) return st == -7 ? -7 : -1;
    }
    return 0;
}

/* The exchange and the reads after a step (or for an instant's row). 0, the failing call's
 * status, or -1 when memory runs out. */
static int exchange_and_read(rg_engine *s)
{
    if (s->p->store == STORE_TEXT) s->arena.used = 0; /* the previous row's copies are written out */
    return run_ops(s, 0, s->p->n_ops);
}

static double wall_clock(void)
{
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (double)now.tv_sec + 1e-9 * (double)now.tv_nsec;
}

/* fmi3DoStep of every FMU from t to t_next; 0 or the failing status (*who the FMU). */
static int step_all(rg_engine *s, double t, double t_next, bool *event, bool *terminate, int *who)
{
    int u, st;
    *s->p->note_time = t;
    for (u = 0; u < s->p->n_instances; u++) {
        bool *f = s->flags + 4 * u;
        *s->p->note_call = s->p->step_note[u];
        st = s->p->do_step[u](s->p->instance[u], t, t_next - t, true, f, f + 1, f + 2, s->last_time + u);
        if (st > 1) {
            *who = u;
            return st;
        }
        if (f[0] && s->p->event_mode[u]) *event = true;
        if (f[1] && !*terminate) {
            *terminate = true;
            *who = u;
        }
    }
    return 0;
}

/* The value last set to a String or Binary input (Python's, before the run; or the engine's). */
RG_EXPORT int rg_keep_last(rg_engine *s, int link, const char *data, size_t size)
{
    char *copy = (char *)realloc(s->last_bytes[link], size + 1);
    if (copy == NULL) return -1;
    if (size) memcpy(copy, data, size);
    copy[size] = '\0';
    s->last_bytes[link] = copy;
    s->last_size[link] = size;
    return 0;
}
