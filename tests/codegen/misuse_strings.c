/* String variables of a generated FMU (tests/codegen/models/strings.rct) called rightly and
 * wrongly by a plain C importer, under the sanitizers.
 *
 *     misuse_strings <strings.so>
 *
 * Compiled with -include of a header that test_misuse_generated.py writes from the FMU's
 * modelDescription.xml (STRINGS_*, and STRINGS_CAPACITY, the texts of the importer it keeps).
 * The importer's texts (none of the model's literals) are kept by the instance: up to the
 * capacity, each below 256 bytes, part of the FMU state and of its serialisation; a NULL text, a
 * text too long, one too many, a String set where it may not be, must each end in fmi3Error with
 * a message; 1,000 instantiate/fill/free cycles end it. Output as misuse_harness.h says.
 */
#include <stdint.h>

#define HARNESS_FUNCTIONS(X)                                                                       \
    X(InstantiateCoSimulation) X(FreeInstance) X(EnterInitializationMode) X(ExitInitializationMode) \
    X(GetString) X(SetString) X(GetInt64) X(Reset) X(GetFMUState) X(SetFMUState) X(FreeFMUState)   \
    X(SerializedFMUStateSize) X(SerializeFMUState) X(DeserializeFMUState)

#include "misuse_harness.h"

static fmu_api fmu;

/* An instance in Initialization Mode, where the parameter and the clocked input may be set. */
static fmi3Instance initializing(void)
{
    fmi3Instance inst = fmu.InstantiateCoSimulation("strings", STRINGS_TOKEN, NULL, fmi3False, fmi3True, fmi3True,
                                                    fmi3False, NULL, 0, NULL, capture_log, NULL);
    if (inst == NULL) {
        printf("Bail out! cannot instantiate (last log: %s)\n", last_log);
        exit(2);
    }
    require("EnterInitializationMode", fmu.EnterInitializationMode(inst, fmi3False, 0.0, 0.0, fmi3False, 0.0));
    return inst;
}

/* A misuse on an instance of its own (after an fmi3Error an instance is Terminated). */
#define FRESH(name, expected, call)             \
    do {                                        \
        fmi3Instance fresh = initializing();    \
        MISUSE(name, expected, call);           \
        fmu.FreeInstance(fresh);                \
    } while (0)

static fmi3Status set_text(fmi3Instance inst, fmi3ValueReference vr, const char *text)
{
    fmi3String value = text;
    return fmu.SetString(inst, &vr, 1, &value, 1);
}

/* Is the string variable vr now `expected`? */
static int reads(fmi3Instance inst, fmi3ValueReference vr, const char *expected)
{
    fmi3String got = NULL;
    return fmu.GetString(inst, &vr, 1, &got, 1) == fmi3OK && got != NULL && strcmp(got, expected) == 0;
}

/* The i-th text of the importer: "guest <i>". */
static const char *guest(int i, char *buffer, size_t size)
{
    snprintf(buffer, size, "guest %d", i);
    return buffer;
}

static void texts(void)
{
    char name[32], expected[64], big[300];
    fmi3ValueReference pair[2] = {STRINGS_VR_NAME, STRINGS_VR_GREETING};
    fmi3String values[2] = {"hello", "bob"}, back[2] = {NULL, NULL};
    fmi3ValueReference state_vr = STRINGS_VR_STATE;
    fmi3Int64 number;
    fmi3Instance inst = initializing();
    int i, ok = 1;
    begin_case();
    report("the start values: name \"\", greeting \"hello\"",
           reads(inst, STRINGS_VR_NAME, "") && reads(inst, STRINGS_VR_GREETING, "hello"), last_log);
    begin_case();
    require("SetString of two", fmu.SetString(inst, pair, 2, values, 2));
    require("GetString of two", fmu.GetString(inst, pair, 2, back, 2));
    report("two at once: a literal of the model and a text of the importer",
           strcmp(back[0], "hello") == 0 && strcmp(back[1], "bob") == 0, last_log);
    for (i = 1; i < STRINGS_CAPACITY && ok; ++i) { /* bob is the first */
        ok = set_text(inst, STRINGS_VR_NAME, guest(i, name, sizeof name)) == fmi3OK && reads(inst, STRINGS_VR_NAME, name);
    }
    begin_case();
    report("as many texts of the importer as the capacity", ok, last_log);
    begin_case();
    report("a text already kept takes no room", set_text(inst, STRINGS_VR_NAME, "guest 1") == fmi3OK, last_log);
    snprintf(expected, sizeof expected, "would be the %d-th string", STRINGS_CAPACITY + 1);
    MISUSE("fmi3SetString: one text more than the capacity", expected, set_text(inst, STRINGS_VR_NAME, "one too many"));
    fmu.FreeInstance(inst);

    memset(big, 'x', 256);
    big[256] = '\0';
    FRESH("fmi3SetString: a text of 256 bytes", "a string of 256 bytes, longer than the 255", set_text(fresh, STRINGS_VR_NAME, big));
    big[255] = '\0';
    inst = initializing();
    begin_case();
    report("a text of 255 bytes", set_text(inst, STRINGS_VR_NAME, big) == fmi3OK && reads(inst, STRINGS_VR_NAME, big), last_log);
    fmu.FreeInstance(inst);
    FRESH("fmi3SetString: a NULL text", "the value is NULL", set_text(fresh, STRINGS_VR_NAME, NULL));
    FRESH("fmi3SetString: NULL values", "values is NULL", fmu.SetString(fresh, pair, 1, NULL, 1));
    FRESH("fmi3SetString of the output reply.value", "cannot be set", set_text(fresh, STRINGS_VR_REPLY, "hi"));
    FRESH("fmi3GetInt64 of a String", "is a String variable, not Int64", fmu.GetInt64(fresh, pair, 1, &number, 1));
    FRESH("fmi3GetString of the Int64 state", "not String", fmu.GetString(fresh, &state_vr, 1, back, 1));
}

static void states(void)
{
    fmi3FMUState state = NULL, copy = NULL;
    size_t size = 0;
    fmi3Byte *bytes;
    fmi3Instance inst = initializing(), other;
    require("SetString bob", set_text(inst, STRINGS_VR_NAME, "bob"));
    require("GetFMUState", fmu.GetFMUState(inst, &state));
    require("SetString amy", set_text(inst, STRINGS_VR_NAME, "amy"));
    require("SetFMUState", fmu.SetFMUState(inst, state));
    begin_case();
    report("an FMU state holds the importer's texts", reads(inst, STRINGS_VR_NAME, "bob"), last_log);
    require("SerializedFMUStateSize", fmu.SerializedFMUStateSize(inst, state, &size));
    bytes = (fmi3Byte *)malloc(size);
    require("SerializeFMUState", fmu.SerializeFMUState(inst, state, bytes, size));
    other = initializing(); /* another instance, which never saw bob */
    require("SetString eve", set_text(other, STRINGS_VR_NAME, "eve"));
    require("DeserializeFMUState", fmu.DeserializeFMUState(other, bytes, size, &copy));
    require("SetFMUState of the copy", fmu.SetFMUState(other, copy));
    begin_case();
    report("a serialised state carries them to another instance", reads(other, STRINGS_VR_NAME, "bob"), last_log);
    require("Reset", fmu.Reset(other));
    require("EnterInitializationMode after Reset", fmu.EnterInitializationMode(other, fmi3False, 0.0, 0.0, fmi3False, 0.0));
    begin_case();
    report("fmi3Reset forgets them", reads(other, STRINGS_VR_NAME, ""), last_log);
    free(bytes);
    fmu.FreeInstance(other);
    fmu.FreeInstance(inst);
}

static void cycles(void)
{
    char name[32];
    int i, k, ok = 1;
    for (k = 0; k < 1000 && ok; ++k) {
        fmi3Instance inst = initializing();
        for (i = 0; i < STRINGS_CAPACITY && ok; ++i) ok = set_text(inst, STRINGS_VR_NAME, guest(i, name, sizeof name)) == fmi3OK;
        ok = ok && fmu.ExitInitializationMode(inst) <= fmi3Warning;
        fmu.FreeInstance(inst);
    }
    begin_case();
    report("1000 instantiate/fill/free cycles", ok, last_log);
}

int main(int argc, char **argv)
{
    if (argc != 2 || !load(argv[1], &fmu)) {
        fprintf(stderr, "usage: misuse_strings <strings.so>\n");
        return 2;
    }
    texts();
    states();
    cycles();
    return harness_finish();
}
